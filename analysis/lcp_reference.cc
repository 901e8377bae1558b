#include "analysis/lcp_reference.h"

#include <stdexcept>
#include <string>
#include <variant>

#include "analysis/lcp_hbm.h"
#include "nonlinearities/dlft_contact.h"

namespace nfrc {
namespace {

double RelativeDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b, bool max_norm) {
  const double scale = max_norm ? b.cwiseAbs().maxCoeff() : b.norm();
  const double distance = max_norm ? (a - b).cwiseAbs().maxCoeff() : (a - b).norm();
  return scale > 0.0 ? distance / scale : distance;
}

}  // namespace

std::optional<Case> LcpLimitCase(const Case& the_case) {
  Case limit = the_case;
  for (LawSpec& law : limit.laws) {
    const auto* dlft = std::get_if<DlftContactSpec>(&law);
    if (dlft == nullptr) return std::nullopt;
    law = LcpContactSpec{dlft->contact, 0.0};
  }
  return limit;
}

LcpReference SolveLcpReference(const Case& lcp_case, double omega) {
  std::unique_ptr<HarmonicSystem> system = BuildSystem(lcp_case);
  LcpHbm lcp(*system, lcp_case.laws);
  const LcpHbm::Solution solution = lcp.Solve(omega);
  LcpReference reference;
  reference.status = solution.lemke.status;
  reference.pivots = solution.lemke.pivots;
  reference.complementarity_gap = solution.complementarity_gap;
  reference.min_gap = solution.gap.minCoeff();
  reference.force = solution.lambda;
  reference.gap = solution.gap;
  reference.num_unknowns = system->NumUnknowns();
  SolutionReporter reporter(*system, lcp_case.output_dofs, lcp_case.output_names);
  reference.signals = reporter.Signals(solution.y, omega);
  reference.signals.after_point = -1;
  reference.signals.converged = reference.ok();
  reference.signals.note = "LCP-HBM (Lemke)";
  return reference;
}

LcpDistance DistanceToLcp(const Case& dlft_case, const HarmonicSystem& system,
                          const Eigen::VectorXd& y, double omega, const LcpReference& reference) {
  const int nx = system.num_displacement_unknowns();
  const int nt = system.harmonic_set().num_samples();
  const int num_laws = static_cast<int>(dlft_case.laws.size());
  const FourierTransform& fourier = system.fourier();
  Eigen::VectorXd force_raw(nt * num_laws);
  Eigen::VectorXd force(nt * num_laws);
  Eigen::VectorXd gap(nt * num_laws);
  Eigen::VectorXd lcp_force(nt * num_laws);
  for (int i = 0; i < num_laws; ++i) {
    const auto* spec = std::get_if<DlftContactSpec>(&dlft_case.laws[i]);
    if (spec == nullptr) {
      throw std::invalid_argument("DistanceToLcp: nonlinearities[" + std::to_string(i) +
                                  "] is not dlft_contact");
    }
    // The system's law i was built from this spec; an instance of our own gives its samples
    // typed (the system holds it as a Nonlinearity).
    DlftContact law(spec->contact.geometry, spec->contact.obstacle_stiffness,
                    spec->contact.epsilon);
    law.Bind(system.context(i));
    const ContactState state = law.State(system.context(i), y, omega);
    gap.segment(i * nt, nt) = state.gap;
    force_raw.segment(i * nt, nt) = state.force;
    force.segment(i * nt, nt) = fourier.ToTime(state.force_coefficients).col(0);
    // The reference's force truncated to the harmonic set, on the same samples.
    lcp_force.segment(i * nt, nt) =
        fourier.ToTime(fourier.ToCoefficients(reference.force.segment(i * nt, nt))).col(0);
  }
  return {.force_raw = RelativeDistance(force_raw, reference.force, true),
          .force = RelativeDistance(force, lcp_force, false),
          .gap = RelativeDistance(gap, reference.gap, true),
          .displacement = RelativeDistance(y.head(nx), reference.signals.y.head(nx), false)};
}

}  // namespace nfrc
