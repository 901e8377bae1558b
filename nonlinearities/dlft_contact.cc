#include "nonlinearities/dlft_contact.h"

#include <cmath>
#include <stdexcept>

#include "nonlinearities/law_spec.h"

namespace nfrc {
DlftContact::DlftContact(ContactGeometry geometry, double obstacle_stiffness, double epsilon)
    : spec_{std::move(geometry), obstacle_stiffness, epsilon} {
  spec_.Validate();
}

std::unique_ptr<Nonlinearity> DlftContactSpec::MakeHarmonic(const LinearModel& /*model*/) const {
  return std::make_unique<DlftContact>(contact.geometry, contact.obstacle_stiffness,
                                       contact.epsilon);
}

void DlftContact::set_epsilon(double epsilon) {
  if (!(epsilon > 0.0) || !std::isfinite(epsilon)) {
    throw std::invalid_argument("epsilon: must be finite and > 0");
  }
  spec_.epsilon = epsilon;
}

DlftContact::Prediction DlftContact::Predict(const NonlinearityContext& ctx,
                                             const Eigen::VectorXd& y, const DlftRows& rows,
                                             double epsilon) const {
  const auto x = y.head(rows.a.cols());
  Prediction p;
  p.gap = spec_.geometry.GapOf(ctx, y);
  const Eigen::VectorXd predicted =
      -spec_.geometry.direction * (rows.a * x - rows.b) - epsilon * p.gap;
  const Eigen::VectorXd lambda_x = ctx.fourier->ToTime(predicted).col(0);
  p.mask = (lambda_x.array() > 0.0).cast<double>();
  p.state.force = lambda_x.cwiseProduct(p.mask);
  p.state.force_coefficients = ctx.fourier->ToCoefficients(p.state.force).col(0);
  p.state.gap = ctx.fourier->ToTime(p.gap).col(0);
  return p;
}

DlftContact::Prediction DlftContact::PredictAt(const NonlinearityContext& ctx,
                                               const Eigen::VectorXd& y, double omega) const {
  return Predict(ctx, y, Rows(ctx, omega, false), EpsilonFor(ctx));
}

void DlftContact::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                           Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                           Eigen::VectorXd* d_omega) const {
  const double epsilon = EpsilonFor(ctx);
  const DlftRows rows = Rows(ctx, omega, false);
  const Prediction p = Predict(ctx, y, rows, epsilon);
  spec_.geometry.AddForce(ctx, p.state.force_coefficients, residual);
  if (jacobian == nullptr && d_omega == nullptr) return;

  const int nc = ctx.num_coefficients();
  const int nx = static_cast<int>(rows.a.cols());
  const double n = spec_.geometry.direction;
  const bool pair = spec_.geometry.other >= 0;
  const Eigen::MatrixXd masked = ctx.fourier->WeightedProduct(p.mask);

  if (jacobian != nullptr) {
    // ∂λ̃_x/∂x = −n·A + ε n (S_a − S_b), with S the selection of a DOF's coefficients.
    Eigen::MatrixXd dpred = -n * rows.a;
    dpred.middleCols(ctx.DofOffset(0), nc).diagonal().array() += epsilon * n;
    if (pair) dpred.middleCols(ctx.DofOffset(1), nc).diagonal().array() -= epsilon * n;
    const Eigen::MatrixXd dforce = masked * dpred;
    jacobian->block(ctx.DofOffset(0), 0, nc, nx) += n * dforce;
    if (pair) jacobian->block(ctx.DofOffset(1), 0, nc, nx) -= n * dforce;
  }
  if (d_omega != nullptr) {
    const DlftRows d_rows = Rows(ctx, omega, true);
    const Eigen::VectorXd dforce = masked * (-n * (d_rows.a * y.head(nx) - d_rows.b));
    d_omega->segment(ctx.DofOffset(0), nc) += n * dforce;
    if (pair) d_omega->segment(ctx.DofOffset(1), nc) -= n * dforce;
  }
}

void DlftContact::LinearizeForStability(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                        double omega, Eigen::MatrixXd* jacobian,
                                        Eigen::MatrixXd* /*velocity_jacobian*/) const {
  if (jacobian == nullptr) return;
  const Prediction p = PredictAt(ctx, y, omega);
  // ∂(nλ)/∂x_dof = n·ε·[λ > 0]·n = ε·[λ > 0]; the pair adds the usual ± blocks.
  const Eigen::MatrixXd block = ctx.fourier->WeightedProduct(EpsilonFor(ctx) * p.mask);
  const int nc = ctx.num_coefficients();
  const int row_a = ctx.DofOffset(0);
  jacobian->block(row_a, row_a, nc, nc) += block;
  if (spec_.geometry.other >= 0) {
    const int row_b = ctx.DofOffset(1);
    jacobian->block(row_a, row_b, nc, nc) -= block;
    jacobian->block(row_b, row_a, nc, nc) -= block;
    jacobian->block(row_b, row_b, nc, nc) += block;
  }
}

std::optional<LinearResidualDependence> DlftContact::LinearResidualPart(
    const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega) const {
  // n·W·(−n·rows) = −W·rows since n = ±1.
  return PredictedForceDependence(ctx.fourier->WeightedProduct(PredictAt(ctx, y, omega).mask),
                                  spec_.geometry.other >= 0);
}

std::vector<LawSignal> DlftContact::Signals(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const {
  const Prediction p = PredictAt(ctx, y, omega);
  std::vector<LawSignal> signals = ContactSignals(p.state, p.gap, fine);
  if (spec_.obstacle_stiffness > 0.0) {
    // The obstacle spring carries the (truncated) contact force: x_obs = n λ / k_obs.
    signals.push_back({"obstacle", spec_.geometry.direction / spec_.obstacle_stiffness *
                                       fine.ToTime(p.state.force_coefficients).col(0)});
  }
  return signals;
}

std::vector<LawSignal> DlftContact::RawSamples(const NonlinearityContext& ctx,
                                               const Eigen::VectorXd& y, double omega) const {
  return ContactRawSamples(PredictAt(ctx, y, omega).state, *ctx.fourier);
}

std::map<std::string, double> DlftContact::Diagnostics(const NonlinearityContext& ctx,
                                                       const Eigen::VectorXd& y, double omega,
                                                       const FourierTransform& fine) const {
  std::map<std::string, double> diagnostics =
      ContactDiagnostics(PredictAt(ctx, y, omega).state, fine);
  diagnostics["epsilon"] = EpsilonFor(ctx);
  return diagnostics;
}

LawSummary DlftContact::Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                  double omega, const FourierTransform& fine) const {
  return ContactSummary(PredictAt(ctx, y, omega).state, fine);
}

}  // namespace nfrc
