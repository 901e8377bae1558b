#pragma once

#include <atomic>
#include <iosfwd>
#include <string>
#include <vector>

#include "tools/sweep.h"

namespace nfrc {

// How many MPI ranks this process was started among, from the launcher's environment
// (Open MPI's OMPI_COMM_WORLD_SIZE, else PMI_SIZE); 1 outside mpirun.
int LaunchedRanks();

// MPI for the lifetime of the object (MPI_Init, MPI_Finalize). Throws InputError if nfrc was
// built without MPI (libopenmpi-dev missing at configure time).
class RankSession {
 public:
  RankSession();
  ~RankSession();
  RankSession(const RankSession&) = delete;
  RankSession& operator=(const RankSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0;
  int size_ = 1;
};

// `mpirun -n P nfrc sweep ...`: rank 0 locks DIR and plans the sweep of the grid (PlanSweep:
// resume included); every rank then takes the next pending run from a shared counter on rank 0
// (MPI one-sided fetch-and-add: dynamic load balancing, since branches differ a lot in cost),
// traces it into DIR/<k>/ with its run.json, and rank 0 rewrites DIR/sweep.json from the
// runs' records after each of its own runs and once all ranks are done. DIR must be on a
// file system every rank sees. An I/O error or a broken invariant on any rank aborts all
// (MPI_Abort, exit 4 or 5); bad input found while planning is an InputError on every rank.
// Returns the runs as recorded (complete only on rank 0).
std::vector<SweepRun> RunSweepOnRanks(const RankSession& session, const CaseFile& file,
                                      const SweepPlan& plan, const std::string& out_dir,
                                      std::ostream* progress, const std::atomic<bool>* stop);

}  // namespace nfrc
