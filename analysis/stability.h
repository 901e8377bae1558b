#pragma once

#include <Eigen/Dense>
#include <complex>
#include <string>
#include <vector>

#include "analysis/point_measures.h"

namespace nfrc {

// Settings of the stability analysis of traced points (case field "stability").
struct StabilityOptions {
  // Hill's method at every point of a trace; off trades the stability of a curve for speed.
  bool enabled = true;
  // A multiplier counts as unstable when |μ| > 1 + unstable_tolerance: room for the
  // truncation error of Hill's exponents on points that are stable in theory (|μ| = 1 at a
  // fold or on an undamped orbit).
  double unstable_tolerance = 1e-6;
  // Bifurcations are localised in ω to this relative accuracy (as folds are).
  double bifurcation_tolerance = 1e-6;
  int max_bifurcation_iterations = 40;
  // A crossing whose multipliers stay more than 5 % off the unit circle at both ends of a
  // bracket this narrow (relative in ω) jumped across it where a sampled nonsmooth law
  // switched (Bifurcation::discontinuous): no smooth crossing lies in between, so its
  // localisation stops there instead of halving a jump down to bifurcation_tolerance.
  double jump_tolerance = 1e-4;
  // −1: Hill's pencil on the whole linear model. N ≥ 0: on its Craig–Bampton reduction onto
  // the DOFs the laws act on plus N fixed-interface modes (analysis/hill_reduction.h), a
  // smaller eigenproblem for a fine mesh, whose error is the user's to check (0 to 500).
  int hill_modes = -1;
  // Throws InputError("stability.<field>: ...") for a bad value.
  void Validate() const;
};

// Floquet exponents and multipliers of one periodic solution.
struct FloquetResult {
  bool computed = false;
  std::string message;  // why not computed, or what was approximated
  std::string method;   // "hill" or "monodromy"
  // The physical exponents s (1/time unit), one per family s + ikω of Hill's spectrum,
  // and the multipliers μ = exp(sT), T = 2π/ω, both sorted by decreasing |μ|.
  std::vector<std::complex<double>> exponents;
  std::vector<std::complex<double>> multipliers;
  double max_modulus = 0.0;  // largest |μ|
  int num_unstable = 0;      // multipliers with |μ| > 1 + unstable_tolerance
  bool stable() const { return computed && num_unstable == 0; }
  double seconds = 0.0;  // wall time of the analysis
  // Solves with Hill's shifted matrix (Arnoldi's operator applications; the dense path's
  // columns): the cost measure that a warm start reduces.
  int operator_applications = 0;
};

enum class BifurcationType { kFold, kBranchPoint, kPeriodDoubling, kNeimarkSacker };
const char* ToString(BifurcationType type);  // "fold", "branch_point", ...

// A change of stability along a branch, localised between two traced points.
struct Bifurcation {
  BifurcationType type = BifurcationType::kFold;
  double omega = 0.0;
  double omega_accuracy = 0.0;  // |ω error| bound reached by the localisation
  bool converged = false;       // accuracy reached within max_bifurcation_iterations
  int iterations = 0;
  int after_point = 0;  // index of the traced point preceding it
  Eigen::VectorXd y;    // the solution there (the HarmonicSystem's unknowns)
  PointMeasures measures;
  // The multipliers that cross the unit circle there (one real, or a complex pair).
  std::vector<std::complex<double>> crossing_multipliers;
  // The multipliers at an end of the localised bracket stay off the unit circle (by more than
  // kJumpModulus): they jumped across it where a sampled nonsmooth law changed its active set,
  // a discontinuous bifurcation rather than a smooth crossing; the type names the side they
  // jumped to.
  bool discontinuous = false;
};

// An ω interval of a branch bounded by two Neimark–Sacker points where a complex pair of
// multipliers is outside the unit circle: the periodic solution there gives way to a
// quasi-periodic motion (a torus), which a transient shows as not periodic.
struct QuasiPeriodicWindow {
  double omega_from = 0.0;  // the Neimark–Sacker point where the pair leaves the circle
  double omega_to = 0.0;    // the one where it comes back (or the branch's last point)
  int first_point = 0;      // traced points inside the window, in branch order
  int last_point = 0;
  bool closed = true;  // false when the branch ends inside the window
};

}  // namespace nfrc
