#pragma once

#include <atomic>
#include <iosfwd>
#include <limits>
#include <string>

namespace nfrc {

// Settings of the pseudo-arclength engine. Steps are arclengths in the scaled norm
// ‖(Δy/s_y, Δλ/s_λ)‖₂ (see Scaling), so they are dimensionless and the same options serve
// a case in physical units and its nondimensional twin.
struct ContinuationOptions {
  // Parameter range: the branch starts at lambda_start and is followed towards lambda_end;
  // it stops when it leaves [min, max] of the two (the last point lands on the bound).
  double lambda_start = 0.0;
  double lambda_end = 1.0;
  // Optional explicit bounds replacing min/max of the two above (NaN = not set), so that a
  // run can start inside its range, e.g. on an isola. The range must contain both.
  double lambda_min = std::numeric_limits<double>::quiet_NaN();
  double lambda_max = std::numeric_limits<double>::quiet_NaN();

  double initial_step = 0.01;  // scaled arclength of the first step
  double min_step = 1e-7;      // below this a failing step stops the run (stalled)
  double max_step = 0.05;      // cap on the scaled arclength of a step
  double step_increase = 2.0;  // largest growth factor of the step after an easy step
  double step_decrease = 0.5;  // factor applied to a rejected step

  int max_points = 10000;            // stop after this many points on the branch
  int max_newton_iterations = 15;    // corrector iterations before a step is rejected
  int target_newton_iterations = 4;  // AUTO-style: steps adapt towards this count
  int max_start_iterations = 50;     // Newton iterations for the starting point
  double newton_tolerance = 1e-10;   // scaled size of the last Newton update
  double residual_tolerance = 1e-8;  // ‖R‖ relative to the residual scale (‖R(0, λ0)‖)
  bool line_search = true;           // backtracking on ‖R‖ inside Newton (nonsmooth R)

  double max_tangent_angle = 0.35;  // rad (≈ 20°); larger turns between tangents are retried
  // Largest distance of a chord from the plotted curve (the PlotCurve given to Continue),
  // in each (λ, coordinate) plane with λ over |lambda_end − lambda_start|; steps are sized to
  // it instead of the tangent's turn, which then only guards against jumps of branch (turns
  // above max_plot_turn_angle are retried). 0 = off: the tangent's turn sizes the steps.
  double plot_tolerance = 0.0;
  double max_plot_turn_angle = 1.2;  // rad; the guard on the full tangent's turn with a plot
  bool detect_folds = true;          // localise sign changes of the tangent's λ component
  double fold_tolerance = 1e-8;      // relative accuracy in λ of a localised fold
  int max_fold_iterations = 40;      // secant iterations of the fold localisation

  // λ scale s_λ; 0 picks max(|lambda_start|, |lambda_end|) (or 1 if both vanish).
  double lambda_scale = 0.0;
  // Floor of an unknown group's scale relative to the largest group scale seen so far.
  double scale_floor = 1e-6;

  // Raised (a signal handler's flag): the run ends at once, within a Newton iteration, with
  // the points found so far (TerminationReason::kStoppedByObserver). Null: never.
  const std::atomic<bool>* stop = nullptr;

  // Progress lines on this stream (point count, λ, step, Newton iterations); null = quiet.
  std::ostream* progress = nullptr;
  std::string lambda_name = "lambda";  // how progress lines name λ

  // Throws std::invalid_argument naming the offending field.
  void Validate() const;

  // The range [min, max] outside which the run stops, from the fields above.
  double LowerBound() const;
  double UpperBound() const;
};

}  // namespace nfrc
