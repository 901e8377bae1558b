#pragma once

#include <optional>
#include <string>
#include <vector>

#include "validation/monodromy.h"
#include "validation/transient.h"

namespace nfrc {

// The chirp sweep of `nfrc validate` (Vadcard et al. 2022, eq. 66), run up and/or down.
struct ChirpSettings {
  bool enabled = false;
  double omega_start = 0.0;    // ω1 of the upward sweep (rad per time unit)
  double omega_end = 0.0;      // ω2 of the upward sweep
  double cycles = 2000;        // duration in excitation cycles at the mean ω; sweep rate follows
  int samples_per_cycle = 64;  // samples per cycle for max |x|
  bool up = true;
  bool down = true;
};

// What `nfrc validate` does, from the case file's optional "validation" object, overridden by
// the command line:
//   "validation": {"omega": [..], "start": "hbm" | "rest",
//                  "transient": {TransientOptions fields},
//                  "chirp": {"omega_start", "omega_end", "cycles", "samples_per_cycle",
//                            "directions": ["up", "down"]},
//                  "monodromy": {"enabled", "relative_step", "scale"}}
struct ValidationSettings {
  enum class Start {
    kHbm,   // one transient from each HBM solution at ω (tests its stability, fast to settle)
    kRest,  // one transient from rest at each ω (lands where the basin of rest leads)
  };
  std::vector<double> omegas;
  Start start = Start::kHbm;
  TransientOptions transient;
  ChirpSettings chirp;
  // The transient monodromy matrix of every HBM solution validated (validation/monodromy.h).
  MonodromyOptions monodromy;

  // Throws InputError naming "validation.<field>" for a bad value.
  void Validate() const;
};

}  // namespace nfrc
