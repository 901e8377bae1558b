#pragma once

#include <optional>

#include "analysis/case.h"
#include "models/craig_bampton.h"
#include "tools/input_fields.h"

namespace nfrc {

// What a case's "model": {"reduction": {...}} asks for:
//   {"type": "craig_bampton", "modes": N}            N fixed-interface modes, or
//   {"type": "craig_bampton", "max_frequency": ω}    every mode below kBandFactor·ω (rad/s),
//   optional "check_frequencies" (default 5, or the reduced size if smaller; an explicit count
//   above the reduced size is refused): eigenfrequencies compared with the full model.
// The boundary DOFs are every DOF a law acts on, every forced DOF and every output DOF.
// A "modal_ratio" damping is applied to the reduced model's modes (which approximate the
// full model's lowest ones; the full model's every mode is out of reach): `modal_ratio`
// holds it until then. Rayleigh damping and a "C" matrix are projected (Tᵀ C T; Rayleigh
// is then exactly αM_r + βK_r).
struct ReductionRequest {
  CraigBamptonOptions options;
  double modal_ratio = -1.0;  // ≥ 0: deferred modal damping
};

// Reads `model.reduction` (the caller's model fields); nullopt if absent. Throws InputError
// naming the field (model.reduction.modes, ...).
std::optional<ReductionRequest> ReadReduction(InputFields& model_fields);

// Replaces the case's model by its Craig–Bampton reduction onto the boundary DOFs, renumbers
// the laws, forcing and outputs, applies deferred modal damping and records the report in
// the_case.reduction. Throws InputError naming model.reduction for a reduction that fails.
void ApplyReduction(Case& the_case, const ReductionRequest& request);

}  // namespace nfrc
