#include "nonlinearities/dlft_friction.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "nonlinearities/law_spec.h"

namespace nfrc {
DlftFriction::DlftFriction(int dof, int other, double limit, double epsilon)
    : dof_(dof), other_(other), limit_(limit), epsilon_(epsilon) {
  if (!(limit_ >= 0.0) || !std::isfinite(limit_)) {
    throw std::invalid_argument("mu*normal_load: must be finite and >= 0");
  }
  if (!(epsilon_ > 0.0) || !std::isfinite(epsilon_)) {
    throw std::invalid_argument("epsilon: must be finite and > 0 (N/m)");
  }
  if (dof_ == other_) throw std::invalid_argument("other: must differ from dof");
}

std::unique_ptr<Nonlinearity> DlftFrictionSpec::MakeHarmonic(const LinearModel& model) const {
  return std::make_unique<DlftFriction>(dof, other, mu * normal_load, EpsilonFor(model));
}

std::vector<int> DlftFriction::Dofs() const {
  if (other_ < 0) return {dof_};
  return {dof_, other_};
}

DlftFriction::Prediction DlftFriction::Predict(const NonlinearityContext& ctx,
                                               const Eigen::VectorXd& y, double omega, bool resolve,
                                               bool with_jacobian) const {
  const int nc = ctx.num_coefficients();
  Prediction p;
  p.rows = PredictionRows(ctx, omega, other_ >= 0, false, type());
  const auto x = y.head(p.rows.a.cols());
  Eigen::VectorXd z = y.segment(ctx.DofOffset(0), nc);
  if (other_ >= 0) z -= y.segment(ctx.DofOffset(1), nc);
  z -= (p.rows.a * x - p.rows.b) / epsilon_;
  if (resolve) {
    p.resolved = ResolveReturnMapping(*ctx.fourier, z, epsilon_, limit_, with_jacobian);
  } else {
    p.input = ctx.fourier->ToTime(z).col(0);
    p.history = ReturnMapping(p.input, epsilon_, limit_);
  }
  return p;
}

Eigen::VectorXd DlftFriction::Input(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                    double omega) const {
  return Predict(ctx, y, omega, false).input;
}

void DlftFriction::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                            Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                            Eigen::VectorXd* d_omega) const {
  const int nc = ctx.num_coefficients();
  const int row_dof = ctx.DofOffset(0);
  const int row_other = other_ >= 0 ? ctx.DofOffset(1) : -1;
  const Prediction p = Predict(ctx, y, omega, true, jacobian != nullptr || d_omega != nullptr);
  const Eigen::VectorXd& force = p.resolved.force;
  residual.segment(row_dof, nc) += force;
  if (row_other >= 0) residual.segment(row_other, nc) -= force;
  if (jacobian == nullptr && d_omega == nullptr) return;

  // λ̃ = λ̃(z̃), z̃ = (S_a − S_b)x − (A x − b)/ε: ∂λ̃/∂z̃ = J (the return mapping's).
  const Eigen::MatrixXd& dz = p.resolved.jacobian;
  const int nx = static_cast<int>(p.rows.a.cols());
  if (jacobian != nullptr) {
    Eigen::MatrixXd dforce = -(dz * p.rows.a) / epsilon_;
    dforce.middleCols(row_dof, nc) += dz;
    if (row_other >= 0) dforce.middleCols(row_other, nc) -= dz;
    jacobian->block(row_dof, 0, nc, nx) += dforce;
    if (row_other >= 0) jacobian->block(row_other, 0, nc, nx) -= dforce;
  }
  if (d_omega != nullptr) {
    const DlftRows d_rows = PredictionRows(ctx, omega, other_ >= 0, true, type());
    const Eigen::VectorXd dforce = -(dz * (d_rows.a * y.head(nx) - d_rows.b)) / epsilon_;
    d_omega->segment(row_dof, nc) += dforce;
    if (row_other >= 0) d_omega->segment(row_other, nc) -= dforce;
  }
}

void DlftFriction::LinearizeForStability(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                         double omega, Eigen::MatrixXd* jacobian,
                                         Eigen::MatrixXd* /*velocity_jacobian*/) const {
  if (jacobian == nullptr) return;
  const Eigen::MatrixXd block = Predict(ctx, y, omega, true).resolved.jacobian;
  const int nc = ctx.num_coefficients();
  const int row_a = ctx.DofOffset(0);
  jacobian->block(row_a, row_a, nc, nc) += block;
  if (other_ >= 0) {
    const int row_b = ctx.DofOffset(1);
    jacobian->block(row_a, row_b, nc, nc) -= block;
    jacobian->block(row_b, row_a, nc, nc) -= block;
    jacobian->block(row_b, row_b, nc, nc) += block;
  }
}

std::optional<LinearResidualDependence> DlftFriction::LinearResidualPart(
    const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega) const {
  return PredictedForceDependence(Predict(ctx, y, omega, true).resolved.jacobian / epsilon_,
                                  other_ >= 0);
}

std::optional<LinearizationMemory> DlftFriction::Memory(const NonlinearityContext& ctx,
                                                        const Eigen::VectorXd& y,
                                                        double omega) const {
  std::optional<LinearizationMemory> memory =
      SliderMemory(std::move(Predict(ctx, y, omega, true, false).resolved), epsilon_, other_ >= 0);
  if (!memory) return std::nullopt;
  // z = u − (A x − b)/ε, with the pair's half-difference rows (PredictedForceDependence).
  memory->residual_terms =
      other_ >= 0 ? std::vector<std::pair<int, double>>{{0, -0.5 / epsilon_}, {1, 0.5 / epsilon_}}
                  : std::vector<std::pair<int, double>>{{0, -1.0 / epsilon_}};
  return memory;
}

std::vector<LawSignal> DlftFriction::Signals(const NonlinearityContext& ctx,
                                             const Eigen::VectorXd& y, double omega,
                                             const FourierTransform& fine) const {
  const int nc = ctx.num_coefficients();
  const Eigen::VectorXd force = Predict(ctx, y, omega, true, false).resolved.force;
  Eigen::VectorXd relative = y.segment(ctx.DofOffset(0), nc);
  if (other_ >= 0) relative -= y.segment(ctx.DofOffset(1), nc);
  const Eigen::VectorXd velocity = omega * (ctx.fourier->DerivativeMatrix() * relative);
  return {{"force", -fine.ToTime(force).col(0)}, {"velocity", fine.ToTime(velocity).col(0)}};
}

std::vector<LawSignal> DlftFriction::RawSamples(const NonlinearityContext& ctx,
                                                const Eigen::VectorXd& y, double omega) const {
  const SlipHistory history = Predict(ctx, y, omega, false).history;
  Eigen::VectorXd slip(history.force.size());
  for (Eigen::Index j = 0; j < slip.size(); ++j) {
    slip(j) = history.Sticks(static_cast<int>(j)) ? 0.0 : 1.0;
  }
  // "force": the series the residual uses (the resolved return mapping's), on the samples.
  const Eigen::VectorXd force = Predict(ctx, y, omega, true, false).resolved.force;
  return {
      {"force_raw", -history.force}, {"force", -ctx.fourier->ToTime(force).col(0)}, {"slip", slip}};
}

LawSummary DlftFriction::Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                   double omega, const FourierTransform& /*fine*/) const {
  const PhaseCount phases = StickPhases(ctx.harmonic_set(), Predict(ctx, y, omega, false).history);
  LawSummary summary;
  summary.phase = LawSummary::Phase{"stick", phases.count, phases.fraction};
  return summary;
}

std::map<std::string, double> DlftFriction::Diagnostics(const NonlinearityContext& ctx,
                                                        const Eigen::VectorXd& y, double omega,
                                                        const FourierTransform& /*fine*/) const {
  const SlipHistory history = Predict(ctx, y, omega, false).history;
  const PhaseCount phases = StickPhases(ctx.harmonic_set(), history);
  std::map<std::string, double> result;
  result["stick_phases"] = phases.count;
  result["stick_fraction"] = phases.fraction;
  result["epsilon"] = epsilon_;
  if (limit_ > 0.0) result["max_force_ratio"] = history.force.cwiseAbs().maxCoeff() / limit_;
  return result;
}

}  // namespace nfrc
