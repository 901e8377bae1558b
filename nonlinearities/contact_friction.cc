#include "nonlinearities/contact_friction.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "nonlinearities/law_spec.h"

namespace nfrc {
namespace {

// The normal part as the Lagrangian contact specs hold it (its ε rule is equality_contact's
// default ρ).
LagrangianContactSpec NormalSpec(const ContactFriction::Parameters& p) {
  return LagrangianContactSpec{p.geometry, p.obstacle_stiffness, 0.0};
}

}  // namespace

ContactFriction::ContactFriction(Parameters parameters) : parameters_(std::move(parameters)) {
  NormalSpec(parameters_).Validate();
  const Parameters& p = parameters_;
  if (p.tangent_dof < 0) throw std::invalid_argument("tangent_dof: must be a DOF");
  const std::vector<int> dofs = Dofs();
  for (size_t i = 0; i < dofs.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (dofs[i] == dofs[j]) {
        throw std::invalid_argument(std::string(i + 1 == dofs.size() && p.tangent_other >= 0
                                                    ? "tangent_other"
                                                    : "tangent_dof") +
                                    ": must differ from the contact's other DOFs");
      }
    }
  }
  if (!(p.mu >= 0.0) || !std::isfinite(p.mu)) throw std::invalid_argument("mu: must be >= 0");
  if (!(p.rho >= 0.0) || !std::isfinite(p.rho)) {
    throw std::invalid_argument("rho: must be finite and > 0 (N/m; 0 = default)");
  }
  if (!(p.friction_rho > 0.0) || !std::isfinite(p.friction_rho)) {
    throw std::invalid_argument("friction_rho: must be finite and > 0");
  }
}

std::unique_ptr<Nonlinearity> ContactFrictionSpec::MakeHarmonic(
    const LinearModel& /*model*/) const {
  return std::make_unique<ContactFriction>(ContactFriction::Parameters{
      geometry, obstacle_stiffness, tangent_dof, tangent_other, mu, rho, friction_rho});
}

std::vector<int> ContactFriction::Dofs() const {
  std::vector<int> dofs = parameters_.geometry.Dofs();
  dofs.push_back(parameters_.tangent_dof);
  if (parameters_.tangent_other >= 0) dofs.push_back(parameters_.tangent_other);
  return dofs;
}

std::vector<double> ContactFriction::ObstacleCompliance() const {
  if (parameters_.obstacle_stiffness == 0.0) return {};
  std::vector<double> compliance(Dofs().size(), 0.0);
  compliance[0] = 1.0 / parameters_.obstacle_stiffness;
  return compliance;
}

double ContactFriction::RhoFor(const NonlinearityContext& ctx) const {
  if (parameters_.rho > 0.0) return parameters_.rho;
  if (resolved_rho_ > 0.0) return resolved_rho_;
  // The default reads the static stiffness at the normal DOF(s) only.
  NonlinearityContext normal = ctx;
  normal.local_dofs.resize(parameters_.geometry.Dofs().size());
  return NormalSpec(parameters_).DefaultEpsilon(normal);
}

void ContactFriction::Bind(const NonlinearityContext& ctx) {
  parameters_.geometry.GapCoefficients(ctx.harmonic_set());
  if (parameters_.rho > 0.0) return;
  try {
    resolved_rho_ = RhoFor(ctx);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("rho: no default (") + e.what() + "); give rho in N/m");
  }
}

Eigen::VectorXd ContactFriction::VelocityCoefficients(const NonlinearityContext& ctx,
                                                      const Eigen::VectorXd& y,
                                                      double omega) const {
  const int nc = ctx.num_coefficients();
  const int t = TangentIndex();
  Eigen::VectorXd relative = y.segment(ctx.DofOffset(t), nc);
  if (parameters_.tangent_other >= 0) relative -= y.segment(ctx.DofOffset(t + 1), nc);
  // By rows, not the dense D (an n_c² product per evaluation): the same sums, zeros aside.
  ctx.fourier->Differentiate(relative, relative);
  return omega * relative;
}

FrictionResidual ContactFriction::Friction(double velocity, double force, double augmented) const {
  FrictionParameters p;
  p.equality = FrictionEquality::kMinMax;
  p.rho = parameters_.friction_rho;
  p.limit = parameters_.mu * std::max(0.0, augmented);
  FrictionResidual out = EvaluateFrictionEquality(p, velocity, force);
  // ∂Ψ/∂(λ − ρg) = ∂Ψ/∂(μN)·μ in contact; the limit is 0 (and flat) where open.
  out.d_limit = augmented > 0.0 ? out.d_limit * parameters_.mu : 0.0;
  return out;
}

ContactFriction::Samples ContactFriction::Sample(const NonlinearityContext& ctx,
                                                 const Eigen::VectorXd& y, double omega) const {
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  Samples s;
  s.gap = fourier.ToTime(parameters_.geometry.GapOf(ctx, y)).col(0);
  s.normal = fourier.ToTime(y.segment(ctx.own_offset, nc)).col(0);
  s.friction = fourier.ToTime(y.segment(ctx.own_offset + nc, nc)).col(0);
  s.velocity = fourier.ToTime(VelocityCoefficients(ctx, y, omega)).col(0);
  s.augmented = s.normal - RhoFor(ctx) * s.gap;
  return s;
}

void ContactFriction::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                               double omega, Eigen::Ref<Eigen::VectorXd> residual,
                               Eigen::MatrixXd* jacobian, Eigen::VectorXd* d_omega) const {
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  const int row_normal = ctx.own_offset, row_friction = ctx.own_offset + nc;
  const int t = TangentIndex();
  const int row_tangent = ctx.DofOffset(t);
  const int row_tangent_other = parameters_.tangent_other >= 0 ? ctx.DofOffset(t + 1) : -1;
  const double rho = RhoFor(ctx);
  const double n = parameters_.geometry.direction;

  parameters_.geometry.AddForce(ctx, y.segment(row_normal, nc), residual);
  residual.segment(row_tangent, nc) -= y.segment(row_friction, nc);
  if (row_tangent_other >= 0)
    residual.segment(row_tangent_other, nc) += y.segment(row_friction, nc);

  const Samples s = Sample(ctx, y, omega);
  const Eigen::Index nt = s.gap.size();
  Eigen::VectorXd phi(nt), psi(nt), on_gap(nt), on_force(nt), psi_v(nt), psi_r(nt), psi_n(nt);
  for (Eigen::Index j = 0; j < nt; ++j) {
    // min(λ, ρg): the gap branch in contact (λ > ρg), the force branch where open.
    const bool contact = s.normal(j) > rho * s.gap(j);
    phi(j) = contact ? rho * s.gap(j) : s.normal(j);
    on_gap(j) = contact ? 1.0 : 0.0;
    on_force(j) = contact ? 0.0 : 1.0;
    const FrictionResidual f = Friction(s.velocity(j), s.friction(j), s.augmented(j));
    psi(j) = f.value;
    psi_v(j) = f.d_velocity;
    psi_r(j) = f.d_force;
    psi_n(j) = f.d_limit;
  }
  residual.segment(row_normal, nc) += fourier.ToCoefficients(phi);
  residual.segment(row_friction, nc) += fourier.ToCoefficients(psi);

  if (jacobian != nullptr) {
    const int row_dof = ctx.DofOffset(0);
    const int row_other = parameters_.geometry.other >= 0 ? ctx.DofOffset(1) : -1;
    jacobian->block(row_dof, row_normal, nc, nc).diagonal().array() += n;
    if (row_other >= 0) jacobian->block(row_other, row_normal, nc, nc).diagonal().array() -= n;
    jacobian->block(row_tangent, row_friction, nc, nc).diagonal().array() -= 1.0;
    if (row_tangent_other >= 0)
      jacobian->block(row_tangent_other, row_friction, nc, nc).diagonal().array() += 1.0;
    // Signorini rows: g = g0 − n(x_dof − x_other).
    const Eigen::MatrixXd d_gap = rho * fourier.WeightedProduct(on_gap);
    jacobian->block(row_normal, row_dof, nc, nc) -= n * d_gap;
    if (row_other >= 0) jacobian->block(row_normal, row_other, nc, nc) += n * d_gap;
    jacobian->block(row_normal, row_normal, nc, nc) += fourier.WeightedProduct(on_force);
    // Coulomb rows: v = ωD(x_t − x_t_other), and the limit through λ.
    Eigen::MatrixXd product;
    fourier.WeightedProduct(psi_v, &product);
    fourier.AddTimesDerivative(product, omega, jacobian->block(row_friction, row_tangent, nc, nc));
    if (row_tangent_other >= 0) {
      fourier.AddTimesDerivative(product, -omega,
                                 jacobian->block(row_friction, row_tangent_other, nc, nc));
    }
    jacobian->block(row_friction, row_friction, nc, nc) += fourier.WeightedProduct(psi_r);
    // The limit μ·max(0, λ − ρg): ∂/∂λ = μH, ∂/∂x_dof = μH·ρn.
    const Eigen::MatrixXd d_limit = fourier.WeightedProduct(psi_n);
    jacobian->block(row_friction, row_normal, nc, nc) += d_limit;
    jacobian->block(row_friction, row_dof, nc, nc) += n * rho * d_limit;
    if (row_other >= 0) jacobian->block(row_friction, row_other, nc, nc) -= n * rho * d_limit;
  }
  if (d_omega != nullptr) {
    // v = ωD x: ∂v/∂ω = v / ω; the gap does not depend on ω.
    const Eigen::VectorXd dv = psi_v.cwiseProduct(s.velocity) / omega;
    d_omega->segment(row_friction, nc) += fourier.ToCoefficients(dv);
  }
}

void ContactFriction::LinearizeForStability(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            Eigen::MatrixXd* jacobian,
                                            Eigen::MatrixXd* velocity_jacobian) const {
  Eigen::VectorXd scratch = Eigen::VectorXd::Zero(y.size());
  Evaluate(ctx, y, omega, scratch, jacobian, nullptr);
  if (velocity_jacobian == nullptr) return;
  const int nc = ctx.num_coefficients();
  const Samples s = Sample(ctx, y, omega);
  Eigen::VectorXd psi_v(s.gap.size());
  for (Eigen::Index j = 0; j < psi_v.size(); ++j) {
    psi_v(j) = Friction(s.velocity(j), s.friction(j), s.augmented(j)).d_velocity;
  }
  const Eigen::MatrixXd block = ctx.fourier->WeightedProduct(psi_v);
  const int row_friction = ctx.own_offset + nc, t = TangentIndex();
  velocity_jacobian->block(row_friction, ctx.DofOffset(t), nc, nc) += block;
  if (parameters_.tangent_other >= 0) {
    velocity_jacobian->block(row_friction, ctx.DofOffset(t + 1), nc, nc) -= block;
  }
}

void ContactFriction::InitialOwnUnknowns(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                         double omega, Eigen::Ref<Eigen::VectorXd> own) const {
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  const Eigen::VectorXd gap = fourier.ToTime(parameters_.geometry.GapOf(ctx, y)).col(0);
  const Eigen::VectorXd v = fourier.ToTime(VelocityCoefficients(ctx, y, omega)).col(0);
  const Eigen::VectorXd normal = (-RhoFor(ctx) * gap).cwiseMax(0.0);
  Eigen::VectorXd friction(normal.size());
  for (Eigen::Index j = 0; j < v.size(); ++j) {
    const double sign = v(j) > 0.0 ? 1.0 : (v(j) < 0.0 ? -1.0 : 0.0);
    friction(j) = -parameters_.mu * normal(j) * sign;
  }
  own.head(nc) = fourier.ToCoefficients(normal);
  own.tail(nc) = fourier.ToCoefficients(friction);
}

ContactState ContactFriction::State(const NonlinearityContext& ctx,
                                    const Eigen::VectorXd& y) const {
  const int nc = ctx.num_coefficients();
  const double rho = RhoFor(ctx);
  ContactState state;
  state.gap = ctx.fourier->ToTime(parameters_.geometry.GapOf(ctx, y)).col(0);
  state.force_coefficients = y.segment(ctx.own_offset, nc);
  const Eigen::VectorXd lambda = ctx.fourier->ToTime(state.force_coefficients).col(0);
  state.force = Eigen::VectorXd::Zero(lambda.size());
  for (Eigen::Index j = 0; j < lambda.size(); ++j) {
    if (lambda(j) > rho * state.gap(j)) state.force(j) = lambda(j);
  }
  return state;
}

std::vector<LawSignal> ContactFriction::Signals(const NonlinearityContext& ctx,
                                                const Eigen::VectorXd& y, double omega,
                                                const FourierTransform& fine) const {
  const int nc = ctx.num_coefficients();
  std::vector<LawSignal> signals =
      ContactSignals(State(ctx, y), parameters_.geometry.GapOf(ctx, y), fine);
  signals.push_back({"friction_force", fine.ToTime(y.segment(ctx.own_offset + nc, nc)).col(0)});
  signals.push_back({"velocity", fine.ToTime(VelocityCoefficients(ctx, y, omega)).col(0)});
  return signals;
}

LawSummary ContactFriction::Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                      double omega, const FourierTransform& fine) const {
  LawSummary summary = ContactSummary(State(ctx, y), fine);
  const PhaseCount phases = StickPhases(ctx, Sample(ctx, y, omega));
  summary.phase = LawSummary::Phase{"stick", phases.count, phases.fraction};
  return summary;
}

PhaseCount ContactFriction::StickPhases(const NonlinearityContext& ctx, const Samples& s) const {
  FrictionParameters p;
  p.rho = parameters_.friction_rho;
  std::vector<bool> stuck(static_cast<size_t>(s.gap.size()));
  for (Eigen::Index j = 0; j < s.gap.size(); ++j) {
    p.limit = parameters_.mu * std::max(0.0, s.augmented(j));
    stuck[static_cast<size_t>(j)] =
        s.augmented(j) > 0.0 && OnStickBranch(p, s.velocity(j), s.friction(j));
  }
  return CountPhases(stuck, 1.0 / ctx.harmonic_set().max_harmonic());
}

std::map<std::string, double> ContactFriction::Diagnostics(const NonlinearityContext& ctx,
                                                           const Eigen::VectorXd& y, double omega,
                                                           const FourierTransform& fine) const {
  std::map<std::string, double> diagnostics = ContactDiagnostics(State(ctx, y), fine);
  diagnostics["rho"] = RhoFor(ctx);
  const Samples s = Sample(ctx, y, omega);
  const PhaseCount phases = StickPhases(ctx, s);
  diagnostics["stick_phases"] = phases.count;
  diagnostics["stick_fraction"] = phases.fraction;
  const double max_normal = s.normal.maxCoeff();
  if (parameters_.mu > 0.0 && max_normal > 0.0) {
    diagnostics["max_friction_ratio"] =
        s.friction.cwiseAbs().maxCoeff() / (parameters_.mu * max_normal);
  }
  return diagnostics;
}

}  // namespace nfrc
