#pragma once

#include <Eigen/Dense>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "analysis/harmonic_system.h"
#include "analysis/point_measures.h"

namespace nfrc {

// Everything reported about one HBM solution: response measures per output DOF, each law's
// scalar diagnostics and, for contact cases, the smallest gap and force over the laws.
struct SolutionMeasures {
  PointMeasures response;
  std::vector<std::map<std::string, double>> laws;  // per law, Nonlinearity::Diagnostics
  std::optional<double> min_gap;                    // m, contact laws only
  std::optional<double> min_force;                  // N, contact laws only
};

// Named columns of equal length.
struct SignalTable {
  std::vector<std::string> names;
  std::vector<Eigen::VectorXd> columns;
};

// Time signals of one solution over a period: θ, t, x and v of every output DOF and the laws'
// signals ("law<i>_<name>") on the fine grid; and, when the laws have raw samples, the same
// on the solver's N_t samples before truncation.
struct SolutionSignals {
  double omega = 0.0;
  // Index of the branch point the solution follows: the start of the crossed segment, or the
  // point itself when it sits exactly at ω (as branch.json's signals record it).
  int after_point = 0;
  bool converged = true;
  std::string note;  // the solver's message
  Eigen::VectorXd y;
  SolutionMeasures measures;
  SignalTable fine;
  SignalTable samples;  // empty when no law has raw samples
};

// Computes measures and signals of solutions of one system.
class SolutionReporter {
 public:
  SolutionReporter(HarmonicSystem& system, std::vector<int> output_dofs,
                   std::vector<std::string> output_names);

  SolutionMeasures Measure(const Eigen::VectorXd& y, double omega);
  SolutionSignals Signals(const Eigen::VectorXd& y, double omega);
  PointAnalyzer& analyzer() { return analyzer_; }

 private:
  HarmonicSystem& system_;
  std::vector<int> output_dofs_;
  std::vector<std::string> output_names_;
  PointAnalyzer analyzer_;
};

// θ_j = 2πj/N, j = 0..N−1: the sample angles of one period.
Eigen::VectorXd Angles(int num_samples);

}  // namespace nfrc
