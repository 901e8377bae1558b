#include "nonlinearities/equality_contact.h"

#include <stdexcept>

#include "nonlinearities/law_spec.h"

namespace nfrc {

EqualityContact::EqualityContact(ContactGeometry geometry, double obstacle_stiffness, double rho)
    : spec_{std::move(geometry), obstacle_stiffness, 0.0}, rho_(rho) {
  spec_.Validate();
  if (!(rho_ >= 0.0) || !std::isfinite(rho_)) {
    throw std::invalid_argument("rho: must be finite and > 0 (N/m; 0 = default)");
  }
}

std::unique_ptr<Nonlinearity> EqualityContactSpec::MakeHarmonic(
    const LinearModel& /*model*/) const {
  return std::make_unique<EqualityContact>(geometry, obstacle_stiffness, rho);
}

void EqualityContact::Bind(const NonlinearityContext& ctx) {
  spec_.geometry.GapCoefficients(ctx.harmonic_set());
  if (rho_ == 0.0) {
    try {
      resolved_rho_ = spec_.DefaultEpsilon(ctx);
    } catch (const std::invalid_argument& e) {
      // The default is DLFT's ε rule; its message names epsilon, this law's field is rho.
      throw std::invalid_argument(std::string("rho: ") + "no default (" + e.what() +
                                  "); give rho in N/m");
    }
  }
}

ContactState EqualityContact::State(const NonlinearityContext& ctx,
                                    const Eigen::VectorXd& y) const {
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  const double rho = RhoFor(ctx);
  ContactState state;
  state.gap = fourier.ToTime(spec_.geometry.GapOf(ctx, y)).col(0);
  state.force_coefficients = y.segment(ctx.own_offset, nc);
  const Eigen::VectorXd lambda = fourier.ToTime(state.force_coefficients).col(0);
  state.force.resize(lambda.size());
  for (Eigen::Index j = 0; j < lambda.size(); ++j) {
    state.force(j) = lambda(j) > rho * state.gap(j) ? lambda(j) : 0.0;
  }
  return state;
}

void EqualityContact::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                               double /*omega*/, Eigen::Ref<Eigen::VectorXd> residual,
                               Eigen::MatrixXd* jacobian, Eigen::VectorXd* d_omega) const {
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  const int row_own = ctx.own_offset;
  const double rho = RhoFor(ctx);
  const double n = spec_.geometry.direction;
  const auto force = y.segment(row_own, nc);
  spec_.geometry.AddForce(ctx, force, residual);

  const Eigen::VectorXd gap = fourier.ToTime(spec_.geometry.GapOf(ctx, y)).col(0);
  const Eigen::VectorXd lambda = fourier.ToTime(force).col(0);
  const Eigen::Index nt = gap.size();
  Eigen::VectorXd phi(nt), on_gap(nt), on_force(nt);
  for (Eigen::Index j = 0; j < nt; ++j) {
    // min(λ, ρg): the force branch where the gap is open (λ ≤ ρg), the gap branch in contact.
    const bool contact = lambda(j) > rho * gap(j);
    phi(j) = contact ? rho * gap(j) : lambda(j);
    on_gap(j) = contact ? 1.0 : 0.0;
    on_force(j) = contact ? 0.0 : 1.0;
  }
  residual.segment(row_own, nc) += fourier.ToCoefficients(phi);

  if (jacobian != nullptr) {
    const int row_dof = ctx.DofOffset(0);
    const int row_other = spec_.geometry.other >= 0 ? ctx.DofOffset(1) : -1;
    jacobian->block(row_dof, row_own, nc, nc).diagonal().array() += n;
    if (row_other >= 0) jacobian->block(row_other, row_own, nc, nc).diagonal().array() -= n;
    // g = g0 − n(x_dof − x_other): ∂Φ/∂x_dof = −nρ P diag(on_gap) E.
    const Eigen::MatrixXd d_gap = rho * fourier.WeightedProduct(on_gap);
    jacobian->block(row_own, row_dof, nc, nc) -= n * d_gap;
    if (row_other >= 0) jacobian->block(row_own, row_other, nc, nc) += n * d_gap;
    jacobian->block(row_own, row_own, nc, nc) += fourier.WeightedProduct(on_force);
  }
  // Neither the gap nor the force depends on ω.
  (void)d_omega;
}

void EqualityContact::InitialOwnUnknowns(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                         double /*omega*/, Eigen::Ref<Eigen::VectorXd> own) const {
  const double rho = RhoFor(ctx);
  const Eigen::MatrixXd gap = ctx.fourier->ToTime(spec_.geometry.GapOf(ctx, y));
  own = ctx.fourier->ToCoefficients((-rho * gap).cwiseMax(0.0));
}

std::vector<LawSignal> EqualityContact::Signals(const NonlinearityContext& ctx,
                                                const Eigen::VectorXd& y, double /*omega*/,
                                                const FourierTransform& fine) const {
  std::vector<LawSignal> signals =
      ContactSignals(State(ctx, y), spec_.geometry.GapOf(ctx, y), fine);
  if (spec_.obstacle_stiffness > 0.0) {
    // The obstacle spring carries the contact force: x_obs = n λ / k_obs.
    signals.push_back(
        {"obstacle", spec_.geometry.direction / spec_.obstacle_stiffness *
                         fine.ToTime(y.segment(ctx.own_offset, ctx.num_coefficients())).col(0)});
  }
  return signals;
}

std::vector<LawSignal> EqualityContact::RawSamples(const NonlinearityContext& ctx,
                                                   const Eigen::VectorXd& y,
                                                   double /*omega*/) const {
  return ContactRawSamples(State(ctx, y), *ctx.fourier);
}

LawSummary EqualityContact::Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                      double /*omega*/, const FourierTransform& fine) const {
  return ContactSummary(State(ctx, y), fine);
}

std::map<std::string, double> EqualityContact::Diagnostics(const NonlinearityContext& ctx,
                                                           const Eigen::VectorXd& y,
                                                           double /*omega*/,
                                                           const FourierTransform& fine) const {
  std::map<std::string, double> diagnostics = ContactDiagnostics(State(ctx, y), fine);
  diagnostics["rho"] = RhoFor(ctx);
  return diagnostics;
}

}  // namespace nfrc
