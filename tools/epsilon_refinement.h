#pragma once

#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "analysis/case.h"

namespace nfrc {

// ε-refinement of DLFT contact at one frequency (Vadcard et al. 2022, Sec. 4.1): the case is
// solved at ω with each ε of a sequence in turn, every solve warm-started from the previous
// solution, so that very large ε (where a cold start fails) are reached.
struct RefinementOptions {
  double omega = 0.0;            // rad/s; must lie on the case's ω range
  std::vector<double> epsilons;  // N/m, in the order solved; every one > 0

  // Throws InputError naming "omega" or "epsilons".
  void Validate(const Case& the_case) const;
};

// ε_i = ε_0·factor^i, i = 0..steps.
std::vector<double> GeometricEpsilons(double epsilon0, double factor, int steps);

// Traces the case from omega_start until the branch first reaches ω (the points go to
// DIR/branch.json as in `nfrc run`), then solves at ω for each ε. Each step's signals and
// samples are written as by `nfrc run` (signals_<i>.csv, samples_<i>.csv), and
// DIR/refinement.json lists per step: epsilon, converged, newton_iterations, residual_norm,
// min_gap, max_penetration, min_force, contact_fraction, max_abs, h1 and the files. Steps
// after a failed one are not attempted. When every law is dlft_contact, the LCP-HBM limit
// (the same case with lcp_contact, Lemke at ω) is written to DIR/lcp/ and refinement.json's
// "lcp", and each step gets "distance_to_lcp": relative distances of the raw force and gap
// (max norm), the truncated force and the condensed displacements (2-norm) to it.
// Returns refinement.json's content.
// Throws InputError if the case has no dlft_contact law.
nlohmann::json RefineEpsilon(const Case& the_case, const RefinementOptions& options,
                             const std::string& out_dir, std::ostream* progress,
                             const nlohmann::json& source = nullptr);

}  // namespace nfrc
