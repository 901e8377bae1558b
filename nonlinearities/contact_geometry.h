#pragma once

#include <Eigen/Dense>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/fourier_transform.h"
#include "core/harmonic_set.h"
#include "core/linear_model.h"
#include "core/nonlinearity.h"

namespace nfrc {

// Where a unilateral contact sits: DOF `dof` (and optionally a second body's DOF `other`)
// facing an obstacle across the initial gap g0(θ) along `direction`. The gap is
//   g = g0 − n (x_dof − x_other)   (n = ±1; x_other = 0 without `other`),
// so n = +1 puts the obstacle on the positive side of the DOF. Contact laws push the DOF
// back with +n·λ in the residual (λ ≥ 0 compressive) and the other DOF with −n·λ.
struct ContactGeometry {
  struct GapHarmonic {
    int harmonic = 1;
    double cos = 0.0;  // m
    double sin = 0.0;  // m
  };
  int dof = -1;
  int other = -1;                          // −1: against ground (or a condensed obstacle)
  double direction = 1.0;                  // n
  double gap = 0.0;                        // constant part of g0 (m)
  std::vector<GapHarmonic> gap_harmonics;  // time-varying part of g0

  std::vector<int> Dofs() const;
  // Coefficients of g0 in `set`; throws std::invalid_argument naming "gap" if a gap
  // harmonic is not in the set.
  Eigen::VectorXd GapCoefficients(const HarmonicSet& set) const;
  // Coefficients of x_dof − x_other from y.
  Eigen::VectorXd RelativeCoefficients(const NonlinearityContext& ctx,
                                       const Eigen::VectorXd& y) const;
  // Coefficients of the gap g from y.
  Eigen::VectorXd GapOf(const NonlinearityContext& ctx, const Eigen::VectorXd& y) const;
  // Adds +n·force to the DOF's rows and −n·force to the other's.
  void AddForce(const NonlinearityContext& ctx, const Eigen::VectorXd& force,
                Eigen::Ref<Eigen::VectorXd> residual) const;
};

// What the Lagrangian contact laws (dlft_contact, lcp_contact) read from a case file: the
// geometry, "obstacle_stiffness" (N/m, > 0; absent = rigid, stored as 0) and "epsilon"
// (N/m, > 0; absent = the law's default, stored as 0).
struct LagrangianContactSpec {
  ContactGeometry geometry;
  double obstacle_stiffness = 0.0;
  double epsilon = 0.0;

  // Throws std::invalid_argument naming the field for a negative or non-finite value, or an
  // obstacle stiffness together with `other`.
  void Validate() const;
  // Compliance (m/N) of the obstacle for Nonlinearity::ObstacleCompliance.
  std::vector<double> ObstacleCompliance() const;
  // The default ε (N/m), independent of ω: the obstacle stiffness for a flexible obstacle,
  // else the static (harmonic 0) condensed stiffness at the contact averaged over the
  // context's DOFs. Throws std::invalid_argument naming "epsilon" if a rigid contact's set
  // has no harmonic 0 or the static stiffness vanishes.
  double DefaultEpsilon(const NonlinearityContext& ctx) const;
  // ε in use (N/m): `epsilon`, or the default (cheap: a sum over the contact's DOFs).
  double EpsilonFor(const NonlinearityContext& ctx) const;
};

// Outputs shared by contact laws at a solution. `gap` and `force` are the gap and contact
// force on the law's N_t samples as the law computed them (force before truncation);
// `force_coefficients` is the force the harmonic equations see (after truncation).
struct ContactState {
  Eigen::VectorXd gap;
  Eigen::VectorXd force;
  Eigen::VectorXd force_coefficients;
};

// min_gap (smallest gap on the samples, m), min_force (smallest truncated force on the fine
// grid, N), max_force (largest sampled force before truncation), contact_fraction (share of
// samples carrying force), max_penetration = max(0, −min_gap).
std::map<std::string, double> ContactDiagnostics(const ContactState& state,
                                                 const FourierTransform& fine);
// The typed summary of a contact state: contact phases (runs of samples whose force before
// truncation is positive: it is exactly zero while open), min_gap and min_force.
LawSummary ContactSummary(const ContactState& state, const FourierTransform& fine);
// Gap and truncated force on the fine grid.
std::vector<LawSignal> ContactSignals(const ContactState& state, const Eigen::VectorXd& gap_coeffs,
                                      const FourierTransform& fine);
// On the law's own samples: gap, force before truncation and force after truncation.
std::vector<LawSignal> ContactRawSamples(const ContactState& state,
                                         const FourierTransform& samples);

}  // namespace nfrc
