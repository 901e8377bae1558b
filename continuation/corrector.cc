#include "continuation/corrector.h"

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "continuation/augmented_system.h"
#include "continuation/reused_factorization.h"

namespace nfrc {
namespace {

// Sufficient decrease of the merit for a damped step (Armijo with the usual small slope).
constexpr double kArmijo = 1e-4;
// Halvings of a Newton step before the line search gives up (step factor 2⁻¹²).
constexpr int kMaxBacktracks = 12;
// Without line search, a merit this many times its value at the start means divergence.
constexpr double kDivergenceGrowth = 1e2;
// Watchdog (Chamberlain et al. 1982): where no fraction of the Newton step decreases the
// merit (at a kink of a semismooth residual the Newton direction need not be a descent
// direction of ‖R‖), the full step is taken once; the merit must then fall below its value
// before that step within this many further iterations, or the correction fails.
constexpr int kWatchdogIterations = 3;
// A residual that falls by less than this factor in one iteration has stalled.
constexpr double kStallRatio = 0.5;
// Largest contraction θ = ‖Δu_k‖/‖Δu_{k-1}‖ of two full Newton steps from which the error
// left after the second is estimated, ‖u_{k+1} − u*‖ ≲ θ‖Δu_k‖/(1 − θ) (the later updates as a
// geometric series); above it Newton is not in its fast region and the estimate means nothing.
constexpr double kMaxContraction = 0.25;
// On the arclength a correction whose line search cut every step of the last
// kStagnationWindow iterations while the merit fell by less than kStagnationRatio over them,
// from iteration kStagnationStart on, fails at once: it is crawling at a kink (point E's
// failed corrections took steps of 2⁻² to 2⁻¹² for ten iterations and more), and the
// caller's fallbacks (a step at fixed λ, a shorter step) converge in a few iterations where
// the crawl ran to max_iterations nearly every time. Fixed-λ solves have no fallback and keep
// crawling.
constexpr int kStagnationStart = 6;
constexpr int kStagnationWindow = 3;
constexpr double kStagnationRatio = 0.5;

enum class Constraint { kArclength, kFixedLambda };

double Merit(const Eigen::VectorXd& residual, double constraint_residual, double residual_scale) {
  return std::hypot(residual.norm() / residual_scale, constraint_residual);
}

double Merit(const Linearization& linearization, double constraint_residual,
             double residual_scale) {
  return Merit(linearization.residual, constraint_residual, residual_scale);
}

CorrectorResult Fail(CorrectorResult result, std::string why) {
  result.converged = false;
  result.failure = std::move(why);
  return result;
}

// On the arclength, the last iteration's factorisation goes with the point when that solver
// (not a reused factorisation) solved it.
CorrectorResult Converged(CorrectorResult result, Constraint constraint, AugmentedSolver solver,
                          bool solver_solved) {
  result.converged = true;
  if (constraint == Constraint::kArclength && solver_solved) {
    result.last_step = std::make_shared<const AugmentedSolver>(std::move(solver));
  }
  return result;
}

// Newton on R(u) = 0, cᵀ D⁻¹(u − u_ref) = 0. The scaled merit ‖(R/r, constraint)‖ is what
// the line search decreases; it weighs both equations alike whatever the units.
CorrectorResult Correct(Evaluator& evaluator, const Scaling& scaling,
                        const NewtonSettings& settings, const Eigen::VectorXd& u_start,
                        const Eigen::VectorXd& row, const Eigen::VectorXd& u_ref,
                        Constraint constraint) {
  const int n = scaling.num_unknowns();
  const double r = settings.residual_scale;
  CorrectorResult result;
  result.u = u_start;
  if (!evaluator.Linearize(result.u, &result.linearization)) {
    return Fail(std::move(result), "evaluation failed before the first Newton step");
  }
  auto constraint_residual = [&](const Eigen::VectorXd& u) {
    return row.dot(scaling.ToScaled(u - u_ref));
  };
  double merit = Merit(result.linearization, constraint_residual(result.u), r);
  const double initial_merit = merit;
  result.residual_norm = result.linearization.residual.norm();

  Linearization trial_linearization;
  Eigen::VectorXd trial_residual;
  // At fixed λ only the laws' rows change between iterations: their factorisation is reused.
  std::optional<ReusedFactorization> reused;
  if (constraint == Constraint::kFixedLambda && result.linearization.elimination != nullptr &&
      !result.linearization.elimination->empty()) {
    reused.emplace(*result.linearization.elimination);
  }
  // At fixed λ its matrix is filled anew at each iteration, in the same storage; on the
  // arclength the elimination reads the Jacobians in place, and the last factorisation goes
  // out with the result (CorrectorResult::last_step).
  AugmentedSolver solver;
  Eigen::MatrixXd& augmented = solver.matrix();
  const Eigen::VectorXd zero_lambda =
      constraint == Constraint::kFixedLambda ? Eigen::VectorXd::Zero(n) : Eigen::VectorXd();
  bool solver_solved = false;  // whether the solver (not `reused`) solved the last iteration
  // The problem's rounding floor of ‖R‖, asked for once, from the second iteration on.
  double noise = -1.0;
  // Merit before a watchdog step and the iteration by which it must be beaten.
  bool watching = false;
  double watchdog_merit = 0.0;
  int watchdog_deadline = 0;
  double previous_full_update = -1.0;  // ‖Δu‖ of the last iteration if taken in full, else < 0
  std::vector<double> merits{merit};   // the merit after each iteration, from the start's
  merits.reserve(static_cast<size_t>(settings.max_iterations) + 1);
  int damped_run = 0;  // iterations in a row whose step the line search cut
  for (int iteration = 1; iteration <= settings.max_iterations; ++iteration) {
    if (settings.stop != nullptr && settings.stop->load()) {
      return Fail(std::move(result), kInterrupted);
    }
    Eigen::VectorXd rhs(n + 1);
    rhs.head(n) = -result.linearization.residual / r;
    rhs(n) = -constraint_residual(result.u);
    Eigen::VectorXd step_scaled;
    const EliminationBlocks* elimination = result.linearization.elimination.get();
    if (constraint == Constraint::kArclength) {
      // Read in place by the elimination; made only where it gives way.
      const BorderedView view(result.linearization.jacobian_y, result.linearization.jacobian_lambda,
                              scaling.scales(), r, row);
      solver_solved = true;
      if (!solver.Solve(view, rhs, &step_scaled, elimination)) {
        return Fail(std::move(result), "augmented system not solvable");
      }
    } else {
      // At fixed λ the last row gives Δλ = 0, so R_λ's column acts on nothing; zero, it is one
      // change less between iterations for the reused factorisation. Read in place by it
      // (the (n + 1)² copy was 6 % of the N_φ = 640 point), made where it gives way.
      const BorderedView view(result.linearization.jacobian_y, zero_lambda, scaling.scales(), r,
                              row);
      solver_solved = !(reused && reused->Solve(view, rhs, &step_scaled));
      if (solver_solved) {
        view.Materialize(&augmented);
        if (!solver.Solve(rhs, &step_scaled, elimination)) {
          return Fail(std::move(result), "augmented system not solvable");
        }
      }
    }
    if (reused) result.low_rank_updates = reused->counts().updates;
    result.iterations = iteration;
    if (constraint == Constraint::kFixedLambda) step_scaled(n) = 0.0;
    const double update_norm = step_scaled.norm();
    const Eigen::VectorXd step = scaling.FromScaled(step_scaled);

    // Near convergence rounding can stop the merit from decreasing: take full steps there,
    // and at the problem's noise floor (where a damped step would only halve into noise).
    if (iteration >= 2 && noise < 0.0 && result.residual_norm > settings.residual_tolerance * r) {
      noise = evaluator.ResidualNoise(result.u);
    }
    const bool at_floor = noise > 0.0 && result.residual_norm <= kNoiseFactor * noise;
    const bool damp =
        settings.line_search && result.residual_norm > settings.residual_tolerance * r && !at_floor;
    double alpha = 1.0;
    Eigen::VectorXd trial;
    double trial_merit = 0.0;
    for (int backtrack = 0;; ++backtrack) {
      trial = result.u + alpha * step;
      if (constraint == Constraint::kFixedLambda) trial(n) = u_ref(n);
      // The full step is evaluated with its Jacobian, as it is nearly always taken; a halved
      // one by its residual alone (a fifth to a third of the friction curves' evaluations are
      // halvings, most of them refused), and with its Jacobian once it is taken.
      const bool halved = backtrack > 0;
      const bool evaluated = halved ? evaluator.Residual(trial.head(n), trial(n), &trial_residual)
                                    : evaluator.Linearize(trial, &trial_linearization);
      if (evaluated) {
        trial_merit = Merit(halved ? trial_residual : trial_linearization.residual,
                            constraint_residual(trial), r);
      }
      if (!damp) {
        if (!evaluated) return Fail(std::move(result), "evaluation failed at a Newton iterate");
        break;
      }
      if (evaluated && trial_merit <= (1.0 - kArmijo * alpha) * merit &&
          (!halved || evaluator.Linearize(trial, &trial_linearization))) {
        if (halved) trial_merit = Merit(trial_linearization, constraint_residual(trial), r);
        break;
      }
      if (backtrack == kMaxBacktracks) {
        if (watching) {
          return Fail(std::move(result), "line search found no decrease of the residual");
        }
        // Watchdog: the full step, evaluated again (the loop left the last trial halved).
        trial = result.u + step;
        if (constraint == Constraint::kFixedLambda) trial(n) = u_ref(n);
        if (!evaluator.Linearize(trial, &trial_linearization)) {
          return Fail(std::move(result), "line search found no decrease of the residual");
        }
        trial_merit = Merit(trial_linearization, constraint_residual(trial), r);
        watching = true;
        watchdog_merit = merit;
        watchdog_deadline = iteration + kWatchdogIterations;
        break;
      }
      alpha *= 0.5;
    }
    const double previous_residual = result.residual_norm;
    result.u = trial;
    std::swap(result.linearization, trial_linearization);
    result.residual_norm = result.linearization.residual.norm();
    merit = trial_merit;
    merits.push_back(merit);
    damped_run = alpha < 1.0 ? damped_run + 1 : 0;
    if (watching && iteration != watchdog_deadline - kWatchdogIterations) {
      if (merit < watchdog_merit) {
        watching = false;
      } else if (iteration >= watchdog_deadline) {
        return Fail(std::move(result), "line search found no decrease of the residual");
      }
    }
    if (!settings.line_search && merit > kDivergenceGrowth * initial_merit) {
      return Fail(std::move(result), "Newton diverging (residual growing)");
    }
    const bool residual_small = result.residual_norm <= settings.residual_tolerance * r;
    if (update_norm <= settings.update_tolerance && residual_small) {
      return Converged(std::move(result), constraint, std::move(solver), solver_solved);
    }
    // Two full steps contracting fast bound the error left after this one: accepted without
    // the confirming iteration whose update would fall below update_tolerance. The residual
    // test still guards it, e.g. where a law's sample switched after the contraction.
    const bool full = alpha == 1.0 && !watching;
    if (full && previous_full_update > 0.0 && residual_small) {
      const double theta = update_norm / previous_full_update;
      const double error = update_norm * theta / (1.0 - theta);
      if (theta <= kMaxContraction && error <= settings.update_tolerance) {
        result.error_estimate = error;
        return Converged(std::move(result), constraint, std::move(solver), solver_solved);
      }
    }
    previous_full_update = full ? update_norm : -1.0;
    if (iteration >= 2 && result.residual_norm > settings.residual_tolerance * r &&
        result.residual_norm > kStallRatio * previous_residual) {
      if (result.residual_norm <= kNoiseFactor * noise) {
        result.at_noise_floor = true;
        result.noise_floor = noise;
        return Converged(std::move(result), constraint, std::move(solver), solver_solved);
      }
    }
    if (constraint == Constraint::kArclength && !watching && !residual_small &&
        iteration >= kStagnationStart && damped_run >= kStagnationWindow &&
        merit > kStagnationRatio * merits[iteration - kStagnationWindow]) {
      return Fail(std::move(result),
                  "stagnating: damped steps cut the merit by less than half in " +
                      std::to_string(kStagnationWindow) + " iterations");
    }
  }
  return Fail(std::move(result),
              "no convergence in " + std::to_string(settings.max_iterations) + " iterations");
}

}  // namespace

CorrectorResult CorrectOnArclength(Evaluator& evaluator, const Scaling& scaling,
                                   const NewtonSettings& settings, const Eigen::VectorXd& u_pred,
                                   const Eigen::VectorXd& tangent_scaled) {
  return Correct(evaluator, scaling, settings, u_pred, tangent_scaled, u_pred,
                 Constraint::kArclength);
}

CorrectorResult CorrectAtFixedLambda(Evaluator& evaluator, const Scaling& scaling,
                                     const NewtonSettings& settings,
                                     const Eigen::VectorXd& u_guess) {
  const int n = scaling.num_unknowns();
  return Correct(evaluator, scaling, settings, u_guess, Eigen::VectorXd::Unit(n + 1, n), u_guess,
                 Constraint::kFixedLambda);
}

}  // namespace nfrc
