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
// Models up to this many DOFs (a 2n × 2n eigenproblem) also have the exponents of the linear
// structure alone checked: a growing one makes every periodic response of it unstable.
inline constexpr int kStateCheckDofs = 200;

// Throws InputError("model.M: ...") for a mass matrix that is not symmetric or has a negative
// eigenvalue (zero masses are allowed: massless DOFs); warns for K not symmetric (circulatory
// forces), K indefinite (statically unstable without the laws), and C whose symmetric part is
// indefinite (negative damping along some motion, with the undamped modes it destabilises
// where the model is small enough to find them), and, up to kStateCheckDofs with M regular,
// a linear structure that is unstable by itself (an exponent of M s² + C s + K with a
// positive real part).
ModelCheck CheckLinearModel(const LinearModel& model);

}  // namespace nfrc
