#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "analysis/harmonic_system.h"
#include "analysis/solution_report.h"
#include "analysis/trace.h"
#include "continuation/branch.h"

namespace nfrc {

// How much of one period a law spends in its phase ("stick" for friction, "contact" for
// contact laws), for comparing an HBM solution with a transient's PeriodMeasures.
struct PhaseSummary {
  std::string name;
  int count = 0;          // phases (entries into the phase) per period; 1 if in it throughout
  double fraction = 0.0;  // share of the period they cover
};

// An HBM solution at exactly one ω: a crossing of a traced branch, resolved by a fixed-ω
// Newton solve from the branch points around it. Inside a fold ω is crossed several times;
// the crossings are told apart by their label.
struct CrossingSolution {
  double omega = 0.0;   // rad per time unit
  int after_point = 0;  // index of the branch point that ends the crossed segment
  // By period-mean energy among the converged crossings: "only"; "lower"/"upper";
  // "lower"/"middle"/"upper"; or "solution i of n by energy". "not converged" if the
  // Newton solve failed (then only `message` and the last iterate `y` are set).
  std::string label;
  bool converged = false;
  std::string message;  // the solver's, empty on success
  Eigen::VectorXd y;    // the unknowns of the HarmonicSystem
  // Every model DOF × NumCoefficients (HarmonicSet layout), condensed DOFs recovered; m.
  Eigen::MatrixXd coefficients;
  SolutionSignals signals;  // measures of the output DOFs and the time signals over a period
  std::vector<PhaseSummary> phases;  // per law with a phase, in the order of the laws
};

// Every crossing of ω by `branch` (traced on `system`, built from `the_case`), in branch
// order, labelled by energy. `system` is the one the branch was traced on or an identical one
// (BuildSystem of the same case).
std::vector<CrossingSolution> SolveCrossings(const Case& the_case, HarmonicSystem& system,
                                             const Branch& branch, double omega);

// A traced branch and its solutions at one ω.
struct SolveAtResult {
  TraceResult trace;
  std::vector<CrossingSolution> solutions;  // empty if the branch never reaches ω
};

// Traces the case's branch (TraceCase) and solves it at every crossing of ω. Needs the
// arclength method (Lemke stepping has no branch to resolve between its points); throws
// InputError otherwise or for bad input.
SolveAtResult SolveAt(const Case& the_case, double omega, const TraceOptions& options = {});

}  // namespace nfrc
