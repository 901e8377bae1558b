#include "nonlinearities/coulomb_friction.h"

#include <stdexcept>

#include "nonlinearities/law_spec.h"
#include "nonlinearities/phase_count.h"

namespace nfrc {

CoulombFriction::CoulombFriction(int dof, int other, FrictionParameters parameters)
    : dof_(dof), other_(other), parameters_(parameters) {
  if (parameters_.limit < 0.0) throw std::invalid_argument("mu*normal_load: must be >= 0");
  if (dof_ == other_) throw std::invalid_argument("other: must differ from dof");
  switch (parameters_.equality) {
    case FrictionEquality::kMinMax:
    case FrictionEquality::kHueber:
      if (!(parameters_.rho > 0.0)) throw std::invalid_argument("rho: must be positive");
      break;
    case FrictionEquality::kTanh:
    case FrictionEquality::kArctan:
      if (!(parameters_.alpha > 0.0)) throw std::invalid_argument("alpha: must be positive");
      break;
    case FrictionEquality::kPiecewiseLinear:
      if (!(parameters_.delta > 0.0)) throw std::invalid_argument("delta: must be positive");
      break;
    case FrictionEquality::kSign:
      break;
  }
}

std::unique_ptr<Nonlinearity> CoulombFrictionSpec::MakeHarmonic(
    const LinearModel& /*model*/) const {
  return std::make_unique<CoulombFriction>(dof, other, Parameters());
}

std::vector<int> CoulombFriction::Dofs() const {
  if (other_ < 0) return {dof_};
  return {dof_, other_};
}

Eigen::VectorXd CoulombFriction::VelocityCoefficients(const NonlinearityContext& ctx,
                                                      const Eigen::VectorXd& y,
                                                      double omega) const {
  const int nc = ctx.num_coefficients();
  Eigen::VectorXd relative = y.segment(ctx.DofOffset(0), nc);
  if (other_ >= 0) relative -= y.segment(ctx.DofOffset(1), nc);
  // By rows, not the dense D (an n_c² product per evaluation): the same sums, zeros aside.
  ctx.fourier->Differentiate(relative, relative);
  return omega * relative;
}

void CoulombFriction::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                               double omega, Eigen::Ref<Eigen::VectorXd> residual,
                               Eigen::MatrixXd* jacobian, Eigen::VectorXd* d_omega) const {
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  const int row_dof = ctx.DofOffset(0);
  const int row_other = other_ >= 0 ? ctx.DofOffset(1) : -1;
  const int row_own = ctx.own_offset;
  const auto force = y.segment(row_own, nc);

  // The friction force enters the equations of motion linearly.
  residual.segment(row_dof, nc) -= force;
  if (row_other >= 0) residual.segment(row_other, nc) += force;

  const Eigen::VectorXd velocity_coefficients = VelocityCoefficients(ctx, y, omega);
  const Eigen::MatrixXd v = fourier.ToTime(velocity_coefficients);
  const Eigen::MatrixXd r = fourier.ToTime(force);
  const int nt = static_cast<int>(v.rows());
  Eigen::MatrixXd psi(nt, 1);
  Eigen::VectorXd psi_v(nt), psi_r(nt);
  for (int j = 0; j < nt; ++j) {
    const FrictionResidual value = EvaluateFrictionEquality(parameters_, v(j, 0), r(j, 0));
    psi(j, 0) = value.value;
    psi_v(j) = value.d_velocity;
    psi_r(j) = value.d_force;
  }
  residual.segment(row_own, nc) += fourier.ToCoefficients(psi);

  if (jacobian != nullptr) {
    jacobian->block(row_dof, row_own, nc, nc).diagonal().array() -= 1.0;
    if (row_other >= 0) jacobian->block(row_other, row_own, nc, nc).diagonal().array() += 1.0;
    // ∂g/∂x_rel = P diag(Ψ_v) E ωD and ∂g/∂r̃ = P diag(Ψ_r) E, added in place.
    fourier.AddWeightedProduct(psi_v, omega, true, jacobian->block(row_own, row_dof, nc, nc));
    if (row_other >= 0) {
      fourier.AddWeightedProduct(psi_v, -omega, true, jacobian->block(row_own, row_other, nc, nc));
    }
    fourier.AddWeightedProduct(psi_r, 1.0, false, jacobian->block(row_own, row_own, nc, nc));
  }
  if (d_omega != nullptr) {
    // v = ωD x: ∂v/∂ω = D x = v / ω.
    Eigen::MatrixXd dv(nt, 1);
    dv.col(0) = psi_v.cwiseProduct(v.col(0)) / omega;
    d_omega->segment(row_own, nc) += fourier.ToCoefficients(dv);
  }
}

void CoulombFriction::LinearizeForStability(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            Eigen::MatrixXd* jacobian,
                                            Eigen::MatrixXd* velocity_jacobian) const {
  Eigen::VectorXd scratch = Eigen::VectorXd::Zero(y.size());
  Evaluate(ctx, y, omega, scratch, jacobian, nullptr);
  if (velocity_jacobian == nullptr) return;
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  const Eigen::MatrixXd v = fourier.ToTime(VelocityCoefficients(ctx, y, omega));
  const Eigen::MatrixXd r = fourier.ToTime(y.segment(ctx.own_offset, nc));
  Eigen::VectorXd psi_v(v.rows());
  for (Eigen::Index j = 0; j < v.rows(); ++j) {
    psi_v(j) = EvaluateFrictionEquality(parameters_, v(j, 0), r(j, 0)).d_velocity;
  }
  const Eigen::MatrixXd block = fourier.WeightedProduct(psi_v);
  velocity_jacobian->block(ctx.own_offset, ctx.DofOffset(0), nc, nc) += block;
  if (other_ >= 0) velocity_jacobian->block(ctx.own_offset, ctx.DofOffset(1), nc, nc) -= block;
}

void CoulombFriction::InitialOwnUnknowns(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                         double omega, Eigen::Ref<Eigen::VectorXd> own) const {
  const Eigen::MatrixXd v = ctx.fourier->ToTime(VelocityCoefficients(ctx, y, omega));
  Eigen::MatrixXd r(v.rows(), 1);
  for (Eigen::Index j = 0; j < v.rows(); ++j) {
    r(j, 0) = v(j, 0) > 0.0 ? -parameters_.limit : (v(j, 0) < 0.0 ? parameters_.limit : 0.0);
  }
  own = ctx.fourier->ToCoefficients(r);
}

std::vector<LawSignal> CoulombFriction::Signals(const NonlinearityContext& ctx,
                                                const Eigen::VectorXd& y, double omega,
                                                const FourierTransform& fine) const {
  const int nc = ctx.num_coefficients();
  return {{"force", fine.ToTime(y.segment(ctx.own_offset, nc)).col(0)},
          {"velocity", fine.ToTime(VelocityCoefficients(ctx, y, omega)).col(0)}};
}

std::optional<PhaseCount> CoulombFriction::StickPhases(const NonlinearityContext& ctx,
                                                       const Eigen::VectorXd& r,
                                                       const Eigen::VectorXd& v) const {
  if (!HasStickBranch(parameters_.equality)) return std::nullopt;
  std::vector<bool> stuck(static_cast<size_t>(r.size()));
  for (Eigen::Index j = 0; j < r.size(); ++j) {
    stuck[static_cast<size_t>(j)] = OnStickBranch(parameters_, v(j), r(j));
  }
  return CountPhases(stuck, 1.0 / ctx.harmonic_set().max_harmonic());
}

LawReport CoulombFriction::Report(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                  double omega, const FourierTransform& fine) const {
  const std::vector<LawSignal> signals = Signals(ctx, y, omega, fine);
  const Eigen::VectorXd& r = signals[0].samples;
  const Eigen::VectorXd& v = signals[1].samples;
  LawReport report;
  if (parameters_.limit > 0.0) {
    report.diagnostics["max_force_ratio"] = r.cwiseAbs().maxCoeff() / parameters_.limit;
  }
  if (const std::optional<PhaseCount> phases = StickPhases(ctx, r, v)) {
    report.diagnostics["stick_phases"] = phases->count;
    report.diagnostics["stick_fraction"] = phases->fraction;
    report.summary.phase = LawSummary::Phase{"stick", phases->count, phases->fraction};
  }
  return report;
}

std::map<std::string, double> CoulombFriction::Diagnostics(const NonlinearityContext& ctx,
                                                           const Eigen::VectorXd& y, double omega,
                                                           const FourierTransform& fine) const {
  return Report(ctx, y, omega, fine).diagnostics;
}

LawSummary CoulombFriction::Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                      double omega, const FourierTransform& fine) const {
  if (!HasStickBranch(parameters_.equality)) return {};
  return Report(ctx, y, omega, fine).summary;
}

}  // namespace nfrc
