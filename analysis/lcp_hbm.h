#pragma once

#include <Eigen/Dense>
#include <vector>

#include "analysis/harmonic_system.h"
#include "core/lemke.h"
#include "nonlinearities/law_spec.h"

namespace nfrc {

// LCP-HBM (Vadcard, Batailly & Thouverez 2022, Sec. 2.5) of a harmonic system whose laws are
// all lcp_contact. With A x = b − Σ_d n_d S_dᵀ P λ_d the condensed harmonic equations
// (S_d selects x_dof − x_other of contact d, P projects samples onto coefficients) and
// g_c = E (g̃0_c − n_c S_c x) the sampled gaps, eliminating x gives on the samples of all
// contacts the linear complementarity problem
//   g = W λ + p,  0 ≤ g ⊥ λ ≥ 0,  W_cd = n_c n_d E S_c A⁻¹ S_dᵀ P,  p_c = E (g̃0_c − n_c S_c A⁻¹ b),
// solved by Lemke; the displacements then follow linearly. With N_t > 2H + 1 samples W has
// rank at most the number of coefficients and is singular.
class LcpHbm {
 public:
  // Throws InputError naming nonlinearities[i] if a law is not lcp_contact, or if there are none.
  // `laws` are the specifications the system was built from (the case's laws).
  LcpHbm(HarmonicSystem& system, const std::vector<LawSpec>& laws);

  struct Problem {
    Eigen::MatrixXd w;  // m/N, Σ N_t square, contacts in law order
    Eigen::VectorXd p;  // m
  };
  // W and p at ω. Throws std::runtime_error if the condensed operator is singular there.
  const Problem& Assemble(double omega);

  // The system's unknowns (displacements and every law's λ samples) for the stacked contact
  // forces λ (N) at ω.
  Eigen::VectorXd Unknowns(const Eigen::VectorXd& lambda, double omega);

  struct Solution {
    LemkeResult lemke;       // in scaled units (see Solve); status, pivots, residuals, basis
    Eigen::VectorXd lambda;  // N, stacked per contact
    Eigen::VectorXd gap;     // m, W λ + p
    Eigen::VectorXd y;       // the system's unknowns
    // max |min(g, λ/w)| over the samples (m) with w = ‖W‖∞⁻¹ (N/m): complementarity in gap
    // units, 0 at an exact solution.
    double complementarity_gap = 0.0;
  };
  // Lemke on the scaled problem (W/‖W‖∞, p/‖p‖∞), so that its tolerances are relative; the
  // result is returned in physical units. options.warm_basis, if any, indexes samples.
  Solution Solve(double omega, const LemkeOptions& options = {});

  int num_samples() const { return num_samples_; }  // Σ N_t over the contacts

 private:
  struct Contact {
    int law = 0;     // index in system.laws()
    double n = 1.0;  // direction
    bool pair = false;
    Eigen::VectorXd gap0;  // g̃0 coefficients
    LagrangianContactSpec contact;
  };
  // S_c x: the coefficients of x_dof − x_other of contact c.
  Eigen::VectorXd Relative(const Contact& c, const Eigen::VectorXd& x) const;

  HarmonicSystem& system_;
  std::vector<Contact> contacts_;
  int num_samples_ = 0;
  double omega_;
  Problem problem_;
  Eigen::VectorXd x_linear_;        // A⁻¹ b
  Eigen::MatrixXd force_response_;  // A⁻¹ Σ n_d S_dᵀ P (nx × Σ N_t): x = x_lin − this·λ
};

}  // namespace nfrc
