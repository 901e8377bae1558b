#include "nonlinearities/contact_geometry.h"

#include <cmath>
#include <stdexcept>

#include "nonlinearities/phase_count.h"

namespace nfrc {

std::vector<int> ContactGeometry::Dofs() const {
  if (other < 0) return {dof};
  return {dof, other};
}

Eigen::VectorXd ContactGeometry::GapCoefficients(const HarmonicSet& set) const {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(set.NumCoefficients());
  if (gap != 0.0) {
    if (!set.has_constant()) {
      throw std::invalid_argument("gap: a constant gap needs harmonic 0 (odd_only is false)");
    }
    g(set.CosIndex(0)) = gap;
  }
  for (const GapHarmonic& h : gap_harmonics) {
    int position = -1;
    for (int p = 0; p < set.num_harmonics(); ++p) {
      if (set.harmonics()[p] == h.harmonic) position = p;
    }
    if (position < 0) {
      throw std::invalid_argument("gap: harmonic " + std::to_string(h.harmonic) +
                                  " is not in the harmonic set");
    }
    g(set.CosIndex(position)) += h.cos;
    g(set.SinIndex(position)) += h.sin;
  }
  return g;
}

Eigen::VectorXd ContactGeometry::RelativeCoefficients(const NonlinearityContext& ctx,
                                                      const Eigen::VectorXd& y) const {
  const int nc = ctx.num_coefficients();
  Eigen::VectorXd relative = y.segment(ctx.DofOffset(0), nc);
  if (other >= 0) relative -= y.segment(ctx.DofOffset(1), nc);
  return relative;
}

Eigen::VectorXd ContactGeometry::GapOf(const NonlinearityContext& ctx,
                                       const Eigen::VectorXd& y) const {
  return GapCoefficients(ctx.harmonic_set()) - direction * RelativeCoefficients(ctx, y);
}

void ContactGeometry::AddForce(const NonlinearityContext& ctx, const Eigen::VectorXd& force,
                               Eigen::Ref<Eigen::VectorXd> residual) const {
  const int nc = ctx.num_coefficients();
  residual.segment(ctx.DofOffset(0), nc) += direction * force;
  if (other >= 0) residual.segment(ctx.DofOffset(1), nc) -= direction * force;
}

void LagrangianContactSpec::Validate() const {
  if (!(obstacle_stiffness >= 0.0) || !std::isfinite(obstacle_stiffness)) {
    throw std::invalid_argument("obstacle_stiffness: must be finite and > 0 (0 = rigid)");
  }
  if (!(epsilon >= 0.0) || !std::isfinite(epsilon)) {
    throw std::invalid_argument("epsilon: must be finite and > 0 (0 = default)");
  }
  if (obstacle_stiffness > 0.0 && geometry.other >= 0) {
    throw std::invalid_argument(
        "obstacle_stiffness: not with other (the second body is then part of the model)");
  }
}

std::vector<double> LagrangianContactSpec::ObstacleCompliance() const {
  if (obstacle_stiffness == 0.0) return {};
  return {1.0 / obstacle_stiffness};
}

double LagrangianContactSpec::DefaultEpsilon(const NonlinearityContext& ctx) const {
  if (obstacle_stiffness > 0.0) return obstacle_stiffness;
  const Condensation& condensation = *ctx.condensation;
  if (!condensation.harmonic_set().has_constant()) {
    throw std::invalid_argument(
        "epsilon: no default without harmonic 0 (odd_only); give epsilon in N/m");
  }
  // Position 0 is harmonic 0 in a full set; its block is K condensed, whatever ω.
  double sum = 0.0;
  for (int local : ctx.local_dofs) sum += std::abs(condensation.Z(0)(local, local).real());
  const double epsilon = sum / static_cast<double>(ctx.local_dofs.size());
  if (!(epsilon > 0.0) || !std::isfinite(epsilon)) {
    throw std::invalid_argument(
        "epsilon: the static stiffness at the contact is zero; give epsilon in N/m");
  }
  return epsilon;
}

double LagrangianContactSpec::EpsilonFor(const NonlinearityContext& ctx) const {
  return epsilon > 0.0 ? epsilon : DefaultEpsilon(ctx);
}

std::map<std::string, double> ContactDiagnostics(const ContactState& state,
                                                 const FourierTransform& fine) {
  const Eigen::VectorXd truncated = fine.ToTime(state.force_coefficients).col(0);
  int in_contact = 0;
  for (Eigen::Index j = 0; j < state.force.size(); ++j) in_contact += state.force(j) > 0.0;
  const double min_gap = state.gap.minCoeff();
  return {{"min_gap", min_gap},
          {"max_penetration", std::max(0.0, -min_gap)},
          {"min_force", truncated.minCoeff()},
          {"max_force", state.force.maxCoeff()},
          {"contact_fraction", static_cast<double>(in_contact) / state.force.size()}};
}

LawSummary ContactSummary(const ContactState& state, const FourierTransform& fine) {
  std::vector<bool> flags(static_cast<size_t>(state.force.size()));
  for (Eigen::Index j = 0; j < state.force.size(); ++j) flags[j] = state.force(j) > 0.0;
  const PhaseCount count = CountPhases(flags, 0.0);
  LawSummary summary;
  summary.phase = LawSummary::Phase{"contact", count.count, count.fraction};
  summary.min_gap = state.gap.minCoeff();
  summary.min_force = fine.ToTime(state.force_coefficients).col(0).minCoeff();
  return summary;
}

std::vector<LawSignal> ContactSignals(const ContactState& state, const Eigen::VectorXd& gap_coeffs,
                                      const FourierTransform& fine) {
  return {{"gap", fine.ToTime(gap_coeffs).col(0)},
          {"force", fine.ToTime(state.force_coefficients).col(0)}};
}

std::vector<LawSignal> ContactRawSamples(const ContactState& state,
                                         const FourierTransform& samples) {
  return {{"gap", state.gap},
          {"force_raw", state.force},
          {"force", samples.ToTime(state.force_coefficients).col(0)}};
}

}  // namespace nfrc
