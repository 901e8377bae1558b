#pragma once

#include <vector>

#include "core/linear_model.h"

namespace nfrc {

// Amplitude of the linear steady response to `terms` at ω (rad per time unit): max over the
// DOFs of Σ_h |X_h| with Z_h(ω) X_h = F_h (core/dynamic_stiffness.h), F_h the complex
// amplitude of the terms of harmonic h. A bound of max|x(t)| of the linear response (m); IDA
// scales its absolute tolerances with it. 0 if Z_h is singular or the model has no DOF.
double LinearAmplitude(const LinearModel& model, const std::vector<ForcingTerm>& terms,
                       double omega);

}  // namespace nfrc
