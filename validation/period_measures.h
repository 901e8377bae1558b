#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "validation/transient.h"

namespace nfrc {

// The comparison measures of a recorded transient period, per requested DOF, in the terms of
// the HBM point measures (tools/point_measures.h) so the two can be set side by side.
struct PeriodMeasures {
  std::vector<double> max_abs;  // max |x| over the period's samples
  std::vector<double> h1;       // first-harmonic amplitude √(a_1² + b_1²) by the DFT
  double energy = 0.0;          // mean total energy over the period (exact, PeriodRecord)
  // Per law with a phase: its name ("stick", "contact") and count / fraction per period.
  std::vector<std::string> phase_names;
  std::vector<int> phase_counts;
  std::vector<double> phase_fractions;
  // Relative energy balance defect |W_in − W_damp − W_laws − ΔE| / W_in (0 if W_in = 0).
  double energy_balance_defect = 0.0;
};

PeriodMeasures MeasurePeriod(const PeriodRecord& record, const std::vector<int>& dofs);

// First-harmonic cosine and sine coefficients (a_1, b_1) of uniform samples over one period,
// x(θ) ≈ a_1 cos θ + b_1 sin θ + ..., θ_i = 2πi/N.
Eigen::Vector2d FirstHarmonic(const Eigen::VectorXd& samples);

}  // namespace nfrc
