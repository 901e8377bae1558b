#include "nonlinearities/penalty_contact.h"

#include <cmath>
#include <stdexcept>

#include "nonlinearities/law_spec.h"

namespace nfrc {

PenaltyContact::PenaltyContact(ContactGeometry geometry, double stiffness)
    : geometry_(std::move(geometry)), stiffness_(stiffness) {
  if (!(stiffness_ > 0.0) || !std::isfinite(stiffness_)) {
    throw std::invalid_argument("stiffness: must be finite and > 0");
  }
}

std::unique_ptr<Nonlinearity> PenaltyContactSpec::MakeHarmonic(const LinearModel& /*model*/) const {
  return std::make_unique<PenaltyContact>(geometry, stiffness);
}

ContactState PenaltyContact::State(const NonlinearityContext& ctx, const Eigen::VectorXd& y) const {
  ContactState state;
  state.gap = ctx.fourier->ToTime(geometry_.GapOf(ctx, y)).col(0);
  state.force = (-stiffness_ * state.gap).cwiseMax(0.0);
  state.force_coefficients = ctx.fourier->ToCoefficients(state.force).col(0);
  return state;
}

void PenaltyContact::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                              double /*omega*/, Eigen::Ref<Eigen::VectorXd> residual,
                              Eigen::MatrixXd* jacobian, Eigen::VectorXd* d_omega) const {
  const ContactState state = State(ctx, y);
  geometry_.AddForce(ctx, state.force_coefficients, residual);
  if (jacobian != nullptr) {
    // ∂(nλ)/∂x_dof = n·k·[g < 0]·n = k·[g < 0]; the pair adds the usual ± blocks.
    const Eigen::VectorXd weights = stiffness_ * (state.gap.array() < 0.0).cast<double>();
    const Eigen::MatrixXd block = ctx.fourier->WeightedProduct(weights);
    const int nc = ctx.num_coefficients();
    const int row_a = ctx.DofOffset(0);
    jacobian->block(row_a, row_a, nc, nc) += block;
    if (geometry_.other >= 0) {
      const int row_b = ctx.DofOffset(1);
      jacobian->block(row_a, row_b, nc, nc) -= block;
      jacobian->block(row_b, row_a, nc, nc) -= block;
      jacobian->block(row_b, row_b, nc, nc) += block;
    }
  }
  // A displacement law: no dependence on ω.
  (void)d_omega;
}

std::vector<LawSignal> PenaltyContact::Signals(const NonlinearityContext& ctx,
                                               const Eigen::VectorXd& y, double /*omega*/,
                                               const FourierTransform& fine) const {
  return ContactSignals(State(ctx, y), geometry_.GapOf(ctx, y), fine);
}

std::vector<LawSignal> PenaltyContact::RawSamples(const NonlinearityContext& ctx,
                                                  const Eigen::VectorXd& y,
                                                  double /*omega*/) const {
  return ContactRawSamples(State(ctx, y), *ctx.fourier);
}

std::map<std::string, double> PenaltyContact::Diagnostics(const NonlinearityContext& ctx,
                                                          const Eigen::VectorXd& y,
                                                          double /*omega*/,
                                                          const FourierTransform& fine) const {
  return ContactDiagnostics(State(ctx, y), fine);
}

LawSummary PenaltyContact::Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                     double /*omega*/, const FourierTransform& fine) const {
  return ContactSummary(State(ctx, y), fine);
}

}  // namespace nfrc
