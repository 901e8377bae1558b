#pragma once

#include <memory>
#include <string>

#include "core/linear_model.h"
#include "core/nonlinearity.h"
#include "nonlinearities/contact_geometry.h"

namespace nfrc {

// Unilateral contact as a complementarity problem on the N_t samples of a period (LCP-HBM,
// Vadcard, Batailly & Thouverez 2022, Sec. 2.5). The law's own unknowns are the contact
// force on the samples θ_j in displacement units, λ_j/ε (m), so that they share the
// displacements' scale in the continuation engine (a force group would be scaled by its
// values, which are zero wherever the structure does not touch); the harmonic equations
// see the force's projection P·λ, so the displacements follow linearly from λ.
//
// Two ways to solve it share this law:
// - Lemke on g = W λ + p (tools/lcp_hbm.h), for any N_t ≥ 2H + 1 (the paper's method);
// - Newton-based continuation, where the law closes its unknowns by the complementarity
//   function min(ε g_j, λ_j) = 0 (semismooth Newton). The residual is defined for any N_t,
//   but Newton needs a square Fourier matrix (N_t = 2H + 1): with more samples than
//   coefficients the forces on the contact samples enter only through their projection and
//   the Jacobian is singular (CheckForContinuation).
// ε (N/m) only scales gaps to forces so that both branches of the min weigh alike; it does
// not change the solution. Same case fields and default ε as dlft_contact.
class LcpContact : public Nonlinearity {
 public:
  // obstacle_stiffness: N/m, 0 = rigid. epsilon: N/m, 0 = default. smoothing δ: m, 0 = exact.
  LcpContact(ContactGeometry geometry, double obstacle_stiffness, double epsilon,
             double smoothing = 0.0);

  std::string type() const override { return "lcp_contact"; }
  std::vector<int> Dofs() const override { return spec_.geometry.Dofs(); }
  std::vector<double> ObstacleCompliance() const override { return spec_.ObstacleCompliance(); }
  // Checks the gap against the harmonic set and resolves the default ε once the system's
  // condensation is known.
  void Bind(const NonlinearityContext& ctx) override {
    spec_.geometry.GapCoefficients(ctx.harmonic_set());
    resolved_epsilon_ = spec_.EpsilonFor(ctx);
  }
  int NumOwnUnknowns(const HarmonicSet& set) const override { return set.num_samples(); }
  bool OwnUnknownsAreCoefficients() const override { return false; }
  void CheckForContinuation(const HarmonicSet& set) const override;
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;
  // λ_j = max(0, −ε g_j) on the linear response: the penalty force at stiffness ε.
  bool OwnUnknownsScaleLikeDisplacements() const override { return true; }
  void InitialOwnUnknowns(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                          Eigen::Ref<Eigen::VectorXd> own) const override;
  std::vector<LawSignal> Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double omega, const FourierTransform& fine) const override;
  LawSummary Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                       const FourierTransform& fine) const override;
  std::vector<LawSignal> RawSamples(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                    double omega) const override;
  // ContactDiagnostics plus "complementarity": max_j |min(g_j, λ_j/ε)| (m).
  std::map<std::string, double> Diagnostics(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const override;

  const ContactGeometry& geometry() const { return spec_.geometry; }
  double obstacle_stiffness() const { return spec_.obstacle_stiffness; }
  // ε in use (N/m): the configured one or the default; own unknown j is λ_j/ε.
  double EpsilonFor(const NonlinearityContext& ctx) const {
    if (spec_.epsilon > 0.0) return spec_.epsilon;
    return resolved_epsilon_ > 0.0 ? resolved_epsilon_ : spec_.EpsilonFor(ctx);
  }

 private:
  ContactState State(const NonlinearityContext& ctx, const Eigen::VectorXd& y) const;

  LagrangianContactSpec spec_;
  double resolved_epsilon_ = 0.0;  // N/m, set by Bind when ε is the default
  double smoothing_;               // m
};

}  // namespace nfrc
