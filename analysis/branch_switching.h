#pragma once

#include <Eigen/Dense>
#include <string>

#include "analysis/case.h"
#include "analysis/stability.h"
#include "analysis/trace.h"

namespace nfrc {

// The same case written for responses of period m·T (T = 2π/ω): harmonics of ω/m up to
// m·H (a full set: a subharmonic breaks the odd symmetry), forcing harmonics times m, and
// every frequency of the case (continuation range and steps, signals_at, validation ω)
// divided by m, so that the continuation parameter of the new case is ν = ω/m.
Case SubharmonicCase(const Case& base, int multiple);

// Coefficients of a solution of `base` (harmonics k of ω, own signals alike) re-expressed in
// the harmonics m·k of ν = ω/m of SubharmonicCase(base, m).
Eigen::VectorXd ToSubharmonic(const Eigen::VectorXd& y, const HarmonicSet& from,
                              const HarmonicSet& to, int multiple);

// The period-2 branch born at a period doubling of `base` (ω is given in the base case's
// units). In harmonics of ν = ω/2 the period doubling is a branch point: the period-1
// solution has even ν-harmonics only and the Jacobian there has a null vector φ in the odd
// ν-harmonics (found by inverse iteration). The new branch is entered by Newton at a fixed
// ν beside the point, from y_pd + a·φ for a few amplitudes a and both sides, keeping the
// first solution with odd ν-harmonics (not the period-1 solution again), and then traced
// away from the point to the end of the base case's range.
struct SwitchedBranch {
  bool started = false;
  std::string message;  // how it started, or why it did not
  Case the_case;        // the period-2 case (continuation parameter ν = ω/2)
  // Its branch (λ = ν); when not started, no points and a start_failed summary whose message
  // says why.
  TraceResult trace;
  double start_omega = 0.0;  // ω (base units) of the first period-2 point
  // ‖odd ν-harmonics‖/‖y‖ of the first point: how far it is from the period-1 branch.
  double subharmonic_content = 0.0;
};
SwitchedBranch FollowPeriodDoubling(const Case& base, const Bifurcation& period_doubling,
                                    const TraceOptions& options = {});

// The other branch through a branch point of `base` (a real multiplier through +1 without a
// turning point, e.g. a symmetry-breaking pitchfork): the Jacobian's near-null vector φ at
// the point (inverse iteration), then Newton at a fixed ω beside the point from y_bp + a·φ
// for a few amplitudes and both sides; the first solution that differs from the one Newton
// finds from y_bp itself (by more than 1e-3 relative) starts a trace away from the point.
// subharmonic_content is then that relative difference.
SwitchedBranch FollowBranchPoint(const Case& base, const Bifurcation& branch_point,
                                 const TraceOptions& options = {});

// FollowPeriodDoubling or FollowBranchPoint by the bifurcation's type. Throws InputError
// ("bifurcation: ...") for a fold or a Neimark–Sacker point, which start no other branch of
// periodic solutions.
SwitchedBranch FollowBifurcation(const Case& base, const Bifurcation& bifurcation,
                                 const TraceOptions& options = {});

// ‖odd harmonics of a full set‖/‖y‖ over the DOF signals of y (the period-2 content).
double OddHarmonicContent(const Eigen::VectorXd& y, const HarmonicSet& set, int num_signals);

}  // namespace nfrc
