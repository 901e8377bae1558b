#include "analysis/validation_settings.h"

#include <cmath>

#include "core/errors.h"

namespace nfrc {

void ValidationSettings::Validate() const {
  for (double omega : omegas) {
    if (!(omega > 0.0) || !std::isfinite(omega)) {
      throw InputError("validation.omega: frequencies must be positive");
    }
  }
  transient.Validate();
  monodromy.Validate();
  if (!chirp.enabled) return;
  if (!(chirp.omega_start > 0.0))
    throw InputError("validation.chirp.omega_start: must be positive");
  if (!(chirp.omega_end > 0.0) || chirp.omega_end == chirp.omega_start) {
    throw InputError("validation.chirp.omega_end: must be positive and differ from omega_start");
  }
  if (!(chirp.cycles >= 10.0)) throw InputError("validation.chirp.cycles: must be at least 10");
  if (chirp.samples_per_cycle < 8) {
    throw InputError("validation.chirp.samples_per_cycle: must be at least 8");
  }
  if (!chirp.up && !chirp.down) {
    throw InputError("validation.chirp.directions: expected [\"up\", \"down\"]");
  }
}

}  // namespace nfrc
