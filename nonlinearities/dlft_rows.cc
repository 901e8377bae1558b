#include "nonlinearities/dlft_rows.h"

#include <stdexcept>
#include <utility>

namespace nfrc {

DlftRows PredictionRows(const NonlinearityContext& ctx, double omega, bool pair, bool derivative,
                        const std::string& law) {
  if (ctx.condensation == nullptr)
    throw std::logic_error(law + ": the context has no condensation");
  const Condensation& condensation = *ctx.condensation;
  if (condensation.omega() != omega) {
    throw std::logic_error(law + ": the condensation is not at the evaluated omega");
  }
  const int a = ctx.local_dofs[0];
  DlftRows rows{condensation.RealOperatorRows(a, derivative),
                condensation.RealForcingRows(a, derivative)};
  if (pair) {
    const int b = ctx.local_dofs[1];
    rows.a = 0.5 * (rows.a - condensation.RealOperatorRows(b, derivative));
    rows.b = 0.5 * (rows.b - condensation.RealForcingRows(b, derivative));
  }
  return rows;
}

LinearResidualDependence PredictedForceDependence(Eigen::MatrixXd weights, bool pair) {
  LinearResidualDependence dependence;
  dependence.weights = std::move(weights);
  if (pair) {
    dependence.terms = {{0, -0.5}, {1, 0.5}};
    dependence.rows = {{0, 1.0}, {1, -1.0}};
  } else {
    dependence.terms = {{0, -1.0}};
    dependence.rows = {{0, 1.0}};
  }
  return dependence;
}

}  // namespace nfrc
