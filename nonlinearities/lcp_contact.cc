#include "nonlinearities/lcp_contact.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "nonlinearities/law_spec.h"

namespace nfrc {

LcpContact::LcpContact(ContactGeometry geometry, double obstacle_stiffness, double epsilon,
                       double smoothing)
    : spec_{std::move(geometry), obstacle_stiffness, epsilon}, smoothing_(smoothing) {
  spec_.Validate();
  if (!(smoothing_ >= 0.0) || !std::isfinite(smoothing_)) {
    throw std::invalid_argument("smoothing: must be finite and >= 0 (m)");
  }
}

std::unique_ptr<Nonlinearity> LcpContactSpec::MakeHarmonic(const LinearModel& /*model*/) const {
  return std::make_unique<LcpContact>(contact.geometry, contact.obstacle_stiffness, contact.epsilon,
                                      smoothing);
}

void LcpContact::CheckForContinuation(const HarmonicSet& set) const {
  if (set.num_samples() != set.NumCoefficients()) {
    throw std::invalid_argument(
        "harmonics.samples: lcp_contact on an arclength branch needs square Fourier matrices, "
        "samples = " +
        std::to_string(set.NumCoefficients()) + " for this harmonic set, got " +
        std::to_string(set.num_samples()) +
        " (oversampled LCP-HBM: continuation.method \"lemke_stepping\")");
  }
  if (set.odd_only()) {
    throw std::invalid_argument(
        "harmonics.odd_only: lcp_contact needs the full harmonic set (a gap has a mean)");
  }
}

void LcpContact::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                          double /*omega*/, Eigen::Ref<Eigen::VectorXd> residual,
                          Eigen::MatrixXd* jacobian, Eigen::VectorXd* /*d_omega*/) const {
  const int nt = ctx.harmonic_set().num_samples();
  const int nc = ctx.num_coefficients();
  const double epsilon = EpsilonFor(ctx);
  const double n = spec_.geometry.direction;
  const bool pair = spec_.geometry.other >= 0;
  const Eigen::VectorXd lambda = epsilon * y.segment(ctx.own_offset, nt);
  spec_.geometry.AddForce(ctx, ctx.fourier->ToCoefficients(lambda).col(0), residual);
  const Eigen::VectorXd gap = ctx.fourier->ToTime(spec_.geometry.GapOf(ctx, y)).col(0);
  // Fischer–Burmeister φ(a, b) = a + b − √(a² + b²) with a = ε g_j, b = λ_j: zero iff
  // a, b ≥ 0 and ab = 0, differentiable except at a = b = 0, and ½‖φ‖² is C¹, so Newton's
  // line search sees a smooth merit function (the min function's is not). With smoothing δ
  // the Chen–Harker–Kanzow–Smale form a + b − √((a − b)² + 4μ²), μ = ε δ (N), is zero iff
  // a, b > 0 and ab = μ², i.e. g·λ = ε δ²: a smooth branch for the arclength engine.
  const double mu = epsilon * smoothing_;
  Eigen::VectorXd da(nt), db(nt);
  for (int j = 0; j < nt; ++j) {
    const double a = epsilon * gap(j);
    const double b = lambda(j);
    if (mu > 0.0) {
      const double r = std::sqrt((a - b) * (a - b) + 4.0 * mu * mu);
      residual(ctx.own_offset + j) += a + b - r;
      da(j) = 1.0 - (a - b) / r;
      db(j) = 1.0 + (a - b) / r;
      continue;
    }
    const double r = std::hypot(a, b);
    residual(ctx.own_offset + j) += a + b - r;
    // At a = b = 0 any (1 − α, 1 − β) with α² + β² ≤ 1 is a generalised derivative.
    da(j) = r > 0.0 ? 1.0 - a / r : 1.0 - std::sqrt(0.5);
    db(j) = r > 0.0 ? 1.0 - b / r : 1.0 - std::sqrt(0.5);
  }
  // The own rows do not depend on ω, and neither does the force P·λ.
  if (jacobian == nullptr) return;
  const Eigen::MatrixXd& p = ctx.fourier->ProjectionMatrix();
  const Eigen::MatrixXd& e = ctx.fourier->SampleMatrix();
  jacobian->block(ctx.DofOffset(0), ctx.own_offset, nc, nt) += epsilon * n * p;
  if (pair) jacobian->block(ctx.DofOffset(1), ctx.own_offset, nc, nt) -= epsilon * n * p;
  for (int j = 0; j < nt; ++j) {
    const int row = ctx.own_offset + j;
    // g_j = (E g̃)_j with g̃ = g̃0 − n (x_dof − x_other).
    jacobian->block(row, ctx.DofOffset(0), 1, nc) -= da(j) * epsilon * n * e.row(j);
    if (pair) jacobian->block(row, ctx.DofOffset(1), 1, nc) += da(j) * epsilon * n * e.row(j);
    (*jacobian)(row, row) += db(j) * epsilon;
  }
}

void LcpContact::InitialOwnUnknowns(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                    double /*omega*/, Eigen::Ref<Eigen::VectorXd> own) const {
  const Eigen::VectorXd gap = ctx.fourier->ToTime(spec_.geometry.GapOf(ctx, y)).col(0);
  own = (-gap).cwiseMax(0.0);
}

ContactState LcpContact::State(const NonlinearityContext& ctx, const Eigen::VectorXd& y) const {
  ContactState state;
  state.gap = ctx.fourier->ToTime(spec_.geometry.GapOf(ctx, y)).col(0);
  state.force = EpsilonFor(ctx) * y.segment(ctx.own_offset, ctx.harmonic_set().num_samples());
  state.force_coefficients = ctx.fourier->ToCoefficients(state.force).col(0);
  return state;
}

std::vector<LawSignal> LcpContact::Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                           double /*omega*/, const FourierTransform& fine) const {
  const ContactState state = State(ctx, y);
  std::vector<LawSignal> signals = ContactSignals(state, spec_.geometry.GapOf(ctx, y), fine);
  if (spec_.obstacle_stiffness > 0.0) {
    // The obstacle spring carries the (truncated) contact force: x_obs = n λ / k_obs.
    signals.push_back({"obstacle", spec_.geometry.direction / spec_.obstacle_stiffness *
                                       fine.ToTime(state.force_coefficients).col(0)});
  }
  return signals;
}

std::vector<LawSignal> LcpContact::RawSamples(const NonlinearityContext& ctx,
                                              const Eigen::VectorXd& y, double /*omega*/) const {
  return ContactRawSamples(State(ctx, y), *ctx.fourier);
}

std::map<std::string, double> LcpContact::Diagnostics(const NonlinearityContext& ctx,
                                                      const Eigen::VectorXd& y, double /*omega*/,
                                                      const FourierTransform& fine) const {
  const ContactState state = State(ctx, y);
  std::map<std::string, double> diagnostics = ContactDiagnostics(state, fine);
  const double epsilon = EpsilonFor(ctx);
  diagnostics["epsilon"] = epsilon;
  diagnostics["complementarity"] = state.gap.cwiseMin(state.force / epsilon).cwiseAbs().maxCoeff();
  return diagnostics;
}

LawSummary LcpContact::Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double /*omega*/, const FourierTransform& fine) const {
  return ContactSummary(State(ctx, y), fine);
}

}  // namespace nfrc
