#include "nonlinearities/jenkins.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "nonlinearities/law_spec.h"
#include "nonlinearities/phase_count.h"

namespace nfrc {

Jenkins::Jenkins(int dof, int other, double stiffness, double limit)
    : dof_(dof), other_(other), stiffness_(stiffness), limit_(limit) {
  if (!(stiffness_ > 0.0) || !std::isfinite(stiffness_)) {
    throw std::invalid_argument("stiffness: must be finite and > 0 (N/m)");
  }
  if (!(limit_ >= 0.0) || !std::isfinite(limit_)) {
    throw std::invalid_argument("mu*normal_load: must be finite and >= 0");
  }
  if (dof_ == other_) throw std::invalid_argument("other: must differ from dof");
}

std::unique_ptr<Nonlinearity> JenkinsSpec::MakeHarmonic(const LinearModel& /*model*/) const {
  return std::make_unique<Jenkins>(dof, other, stiffness, mu * normal_load);
}

std::vector<int> Jenkins::Dofs() const {
  if (other_ < 0) return {dof_};
  return {dof_, other_};
}

Eigen::VectorXd Jenkins::RelativeCoefficients(const NonlinearityContext& ctx,
                                              const Eigen::VectorXd& y) const {
  const int nc = ctx.num_coefficients();
  Eigen::VectorXd relative = y.segment(ctx.DofOffset(0), nc);
  if (other_ >= 0) relative -= y.segment(ctx.DofOffset(1), nc);
  return relative;
}

void Jenkins::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double /*omega*/,
                       Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                       Eigen::VectorXd* d_omega) const {
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  const int row_dof = ctx.DofOffset(0);
  const int row_other = other_ >= 0 ? ctx.DofOffset(1) : -1;
  // The switches resolved between the samples: sampled, every sample's switch would be a kink
  // of size ~2k_t/N_t in the Jacobian (see ResolveReturnMapping).
  const ResolvedSlip slip = ResolveReturnMapping(fourier, RelativeCoefficients(ctx, y), stiffness_,
                                                 limit_, jacobian != nullptr);
  residual.segment(row_dof, nc) += slip.force;
  if (row_other >= 0) residual.segment(row_other, nc) -= slip.force;

  if (jacobian != nullptr) {
    const Eigen::MatrixXd& block = slip.jacobian;
    jacobian->block(row_dof, row_dof, nc, nc) += block;
    if (row_other >= 0) {
      jacobian->block(row_dof, row_other, nc, nc) -= block;
      jacobian->block(row_other, row_dof, nc, nc) -= block;
      jacobian->block(row_other, row_other, nc, nc) += block;
    }
  }
  // Rate independent: no dependence on ω.
  (void)d_omega;
}

std::optional<LinearizationMemory> Jenkins::Memory(const NonlinearityContext& ctx,
                                                   const Eigen::VectorXd& y,
                                                   double /*omega*/) const {
  return SliderMemory(ResolveReturnMapping(*ctx.fourier, RelativeCoefficients(ctx, y), stiffness_,
                                           limit_, /*with_jacobian=*/false),
                      stiffness_, other_ >= 0);
}

std::vector<LawSignal> Jenkins::Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                        double /*omega*/, const FourierTransform& fine) const {
  const Eigen::VectorXd u = fine.ToTime(RelativeCoefficients(ctx, y)).col(0);
  const SlipHistory history = Sweep(u);
  const Eigen::VectorXd slider = u - history.force / stiffness_;
  return {{"force", history.force}, {"displacement", u}, {"slider", slider}};
}

std::map<std::string, double> Jenkins::Diagnostics(const NonlinearityContext& ctx,
                                                   const Eigen::VectorXd& y, double /*omega*/,
                                                   const FourierTransform& fine) const {
  const SlipHistory history = Sweep(fine.ToTime(RelativeCoefficients(ctx, y)).col(0));
  const PhaseCount phases = StickPhases(ctx.harmonic_set(), history);
  std::map<std::string, double> result;
  result["stick_phases"] = phases.count;
  result["stick_fraction"] = phases.fraction;
  if (limit_ > 0.0) result["max_force_ratio"] = history.force.cwiseAbs().maxCoeff() / limit_;
  return result;
}

LawSummary Jenkins::Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                              double /*omega*/, const FourierTransform& fine) const {
  const SlipHistory history = Sweep(fine.ToTime(RelativeCoefficients(ctx, y)).col(0));
  const PhaseCount phases = StickPhases(ctx.harmonic_set(), history);
  LawSummary summary;
  summary.phase = LawSummary::Phase{"stick", phases.count, phases.fraction};
  return summary;
}

}  // namespace nfrc
