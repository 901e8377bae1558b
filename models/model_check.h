#pragma once

#include <string>
#include <vector>

#include "core/linear_model.h"

namespace nfrc {

// What the linear part M ẍ + C ẋ + K x says of itself before any trace: the properties that
// make every periodic response unstable, or the problem ill-posed, whatever the laws do. A
// model with one of them is traced (it can be meant: a bistable structure has an indefinite K,
// a rotor a circulatory one, a self-excited system negative damping), but the run says so,
// naming the matrix, instead of reporting every point unstable without a word.
struct ModelCheck {
  std::vector<std::string> warnings;  // "model.K: ..." (the case file's names)
};

// Relative size below which an eigenvalue, or the asymmetric part of a matrix, is rounding.
inline constexpr double kDefinitenessTolerance = 1e-10;
// Models up to this many DOFs are checked by dense eigenvalues (and their undamped modes'
// damping); larger ones by the inertia of a sparse LDLᵀ factorisation.
inline constexpr int kDenseCheckDofs = 1000;

// Throws InputError("model.M: ...") for a mass matrix that is not symmetric or has a negative
// eigenvalue (zero masses are allowed: massless DOFs); warns for K not symmetric (circulatory
// forces), K indefinite (statically unstable without the laws), and C whose symmetric part is
// indefinite (negative damping along some motion, with the undamped modes it destabilises
// where the model is small enough to find them).
ModelCheck CheckLinearModel(const LinearModel& model);

}  // namespace nfrc
