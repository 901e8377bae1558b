#include "tools/sweep_ranks.h"

#include <cstdint>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <optional>
#include <string>

#include "core/errors.h"
#include "tools/output_files.h"
#include "tools/rewrite_schedule.h"

#ifdef NFRC_HAVE_MPI
#include <mpi.h>
#endif

namespace nfrc {

int LaunchedRanks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (const char* value = std::getenv(name)) {
      const int size = std::atoi(value);
      if (size >= 1) return size;
    }
  }
  return 1;
}

#ifndef NFRC_HAVE_MPI

RankSession::RankSession() {
  throw InputError(
      "mpirun: this nfrc was built without MPI (install libopenmpi-dev and rebuild), or run the "
      "sweep without mpirun (--jobs N uses the cores of one machine)");
}
RankSession::~RankSession() = default;

std::vector<SweepRun> RunSweepOnRanks(const RankSession&, const CaseFile&, const SweepPlan&,
                                      const std::string&, std::ostream*, const std::atomic<bool>*) {
  throw InputError("mpirun: this nfrc was built without MPI");
}

#else

namespace {

// Exit codes of a rank that aborts all (the CLI's: an I/O error, an internal error).
constexpr int kAbortIo = 4;
constexpr int kAbortInternal = 5;

// Every rank learns rank 0's string.
std::string Broadcast(const std::string& text, int rank) {
  std::int64_t size = static_cast<std::int64_t>(text.size());
  MPI_Bcast(&size, 1, MPI_INT64_T, 0, MPI_COMM_WORLD);
  std::string out = rank == 0 ? text : std::string(static_cast<size_t>(size), '\0');
  if (size > 0) MPI_Bcast(out.data(), static_cast<int>(size), MPI_CHAR, 0, MPI_COMM_WORLD);
  return out;
}

// Rank 0's view: every run's latest record (run.json of the runs traced in this sweep).
void Refresh(const SweepJob& job, std::vector<SweepRun>* runs) {
  for (SweepRun& run : *runs) {
    // Kept from an earlier sweep, or already final: nothing new can be on disk.
    if (run.resumed || run.status == "complete" || run.status == "failed") continue;
    if (std::optional<SweepRun> record = ReadRunRecord(job, run)) run = *record;
  }
}

}  // namespace

RankSession::RankSession() {
  MPI_Init(nullptr, nullptr);
  // Errors come back as codes (a missing one-sided window is handled, not fatal).
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

RankSession::~RankSession() { MPI_Finalize(); }

std::vector<SweepRun> RunSweepOnRanks(const RankSession& session, const CaseFile& file,
                                      const SweepPlan& plan, const std::string& out_dir,
                                      std::ostream* progress, const std::atomic<bool>* stop) {
  const int rank = session.rank();
  std::optional<OutputDirectoryLock> lock;
  std::vector<SweepRun> runs;
  std::string failure;  // rank 0's planning error, shared with every rank
  const SweepJob job{file, plan, out_dir, CaseFingerprint(file)};
  // Rank 0 rewrites sweep.json from every run's run.json, on the schedule: reading them all
  // after every run would cost O(runs²) over a large sweep.
  RewriteSchedule schedule(kSweepRecordInterval);
  if (rank == 0) {
    try {
      lock.emplace(out_dir);
      std::vector<std::string> notes;
      runs = PlanSweep(job, &notes);
      if (progress != nullptr) {
        for (const std::string& note : notes) *progress << "nfrc: " << note << "\n";
      }
      WriteSweepRecord(job, runs);
    } catch (const std::exception& error) {
      failure = error.what();
      if (failure.empty()) failure = "planning the sweep failed";
    }
  }
  failure = Broadcast(failure, rank);
  if (!failure.empty()) throw InputError(failure);
  // The pending runs, in rank 0's order.
  std::vector<int> todo;
  if (rank == 0) {
    for (const SweepRun& run : runs) {
      if (!run.resumed) todo.push_back(run.index);
    }
  }
  int pending = static_cast<int>(todo.size());
  MPI_Bcast(&pending, 1, MPI_INT, 0, MPI_COMM_WORLD);
  todo.resize(static_cast<size_t>(pending));
  if (pending > 0) MPI_Bcast(todo.data(), pending, MPI_INT, 0, MPI_COMM_WORLD);

  // The shared counter. Some transports offer no one-sided window (Open MPI's shared memory
  // with its single-copy mechanism disabled, as some containers require): then the runs are
  // dealt out round-robin instead, which every rank is told on stderr.
  std::int64_t counter = 0;
  MPI_Win window = MPI_WIN_NULL;
  int have_window =
      MPI_Win_create(rank == 0 ? &counter : nullptr, rank == 0 ? sizeof counter : 0, sizeof counter,
                     MPI_INFO_NULL, MPI_COMM_WORLD, &window) == MPI_SUCCESS;
  int all_have_window = 0;
  MPI_Allreduce(&have_window, &all_have_window, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (!all_have_window) {
    if (have_window) MPI_Win_free(&window);
    window = MPI_WIN_NULL;
    if (rank == 0) {
      std::cerr << "nfrc: no MPI one-sided window on this transport: branches dealt out "
                   "round-robin (no load balancing)\n";
    }
  }
  std::int64_t dealt = rank;  // round-robin: this rank's next position in todo
  try {
    for (;;) {
      if (stop != nullptr && stop->load()) break;
      std::int64_t next = 0;
      if (window != MPI_WIN_NULL) {
        const std::int64_t one = 1;
        MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window);
        MPI_Fetch_and_op(&one, &next, MPI_INT64_T, 0, 0, MPI_SUM, window);
        MPI_Win_unlock(0, window);
      } else {
        next = dealt;
        dealt += session.size();
      }
      if (next >= static_cast<std::int64_t>(todo.size())) break;
      const int k = todo[static_cast<size_t>(next)];
      SweepRun run = TraceSweepRun(job, PendingRun(plan, static_cast<size_t>(k)), stop,
                                   /*threads=*/0);  // ranks share the cores already
      PrintRun(progress, plan, run);
      if (rank == 0 && schedule.Due(true)) {
        schedule.Timed([&] {
          Refresh(job, &runs);
          WriteSweepRecord(job, runs);
        });
      }
    }
  } catch (const std::exception& error) {
    std::cerr << "nfrc: rank " << rank << ": error: " << error.what() << "\n";
    MPI_Abort(MPI_COMM_WORLD,
              dynamic_cast<const OutputError*>(&error) != nullptr ? kAbortIo : kAbortInternal);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (window != MPI_WIN_NULL) MPI_Win_free(&window);
  if (rank == 0) {
    Refresh(job, &runs);
    WriteSweepRecord(job, runs);
  }
  return runs;
}

#endif

}  // namespace nfrc
