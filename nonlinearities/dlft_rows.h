#pragma once

#include <Eigen/Dense>
#include <string>

#include "core/nonlinearity.h"

namespace nfrc {

// What the DLFT laws (contact and friction) predict their force from: the condensed linear
// equations L = A x − b of the law's DOF, or half the difference of its two DOFs' rows for a
// pair (the force then equals −(L_a − L_b)/2 at any solution).
struct DlftRows {
  Eigen::MatrixXd a;  // NumCoefficients × displacement unknowns
  Eigen::VectorXd b;
};

// The rows at ω (or their ω-derivatives). The context's condensation must be at ω: a
// violated invariant throws std::logic_error naming `law`.
DlftRows PredictionRows(const NonlinearityContext& ctx, double omega, bool pair, bool derivative,
                        const std::string& law);

// Hill's LinearResidualDependence of a force f̃ = W·(−L) on the law's rows (+f̃ on the first
// DOF, −f̃ on the second of a pair), L as in PredictionRows.
LinearResidualDependence PredictedForceDependence(Eigen::MatrixXd weights, bool pair);

}  // namespace nfrc
