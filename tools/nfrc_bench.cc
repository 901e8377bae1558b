// Benchmarks of the foundation (prints figures; asserts nothing). Every run first times the
// calibration unit LU(320) and prints wall times also in that unit:
//   1. the Duffing FRC with H = 7 (cases/duffing.json): wall time, points, Newton per point;
//   2. the friction oscillator FRC, N = 10, N_φ = 60 (cases/friction/frc_n10.json);
//   3. condensation of sparse chain models (10^4 and 10^5 DOFs) onto 2 DOFs with H = 20:
//      time per frequency (factorisation + Schur complement + ω-derivatives of all harmonics);
//   4. the rigid-obstacle rod NFRC, N_h = 20, N_t = 400 (cases/rod/rigid_nh20.json);
//   5. the same rod refined to 10^4 and 10^5 elements (sparse condensation, Rayleigh
//      damping 0.75 % at ω0): a short stretch in contact, time per continuation step, per
//      evaluation, and of the condensation update per frequency alone, and the rounding
//      noise of the condensed operator, which grows with the mesh and decides whether the
//      arclength corrector (ω moves every iteration) can meet the residual tolerance;
//   6. LCP-HBM per point on the rigid-obstacle rod, N_h = 20, N_t = 41, 400, 600
//      (cases/lcp/rigid_stepping_nt400.json): assembly of W, p, the Lemke solve and the
//      whole point at two frequencies in contact, and the mean over a cold-start sweep; with
//      Siconos (NFRC_HAVE_SICONOS) its lcp_lexicolemke on the same scaled W, p alongside,
//      and both solvers' verified solutions / failures over the sweep;
//   7. transients to periodic steady state from rest (validation/): IDA on the friction
//      oscillator at point E and on the rod against a flexible obstacle at ω0, the explicit
//      Lagrange-multiplier scheme on the rod against a rigid one: integration time, periods,
//      steps and events;
//   8. stability (Hill's method at every point, bifurcations localised): the whole trace
//      (TraceCase, measures included) with stability off and on, and Hill's time per point
//      against the trace's, for Duffing, the friction FRC at N_φ = 60 and 160 (the latter
//      on its first 60 points), the rigid-obstacle rod and the rod against 4 k_rod.
#include <Eigen/Sparse>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "analysis/lcp_hbm.h"
#ifdef NFRC_HAVE_SICONOS
#include "core/lcp_siconos.h"
#endif
#include "analysis/trace.h"
#include "analysis/validation_settings.h"
#include "core/condensation.h"
#include "models/damping.h"
#include "models/rod.h"
#include "tools/case_file.h"
#include "validation/make_integrator.h"

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// The calibration unit: one dense LU with partial pivoting of a fixed 320 × 320 matrix, a
// plain triple loop compiled with the project's flags. Figures divided by it survive a shared,
// noisy machine better than seconds. Median of 7 (s).
double LuUnitSeconds() {
  constexpr int kN = 320;
  std::vector<double> times;
  for (int repeat = 0; repeat < 7; ++repeat) {
    std::vector<double> a(kN * kN);
    // Fixed, well-conditioned and pivot-demanding: a Hilbert-like part plus a shifted diagonal.
    for (int i = 0; i < kN; ++i) {
      for (int j = 0; j < kN; ++j) a[i * kN + j] = 1.0 / (1.0 + i + j) + (i == (j + 7) % kN);
    }
    const auto start = Clock::now();
    for (int k = 0; k < kN; ++k) {
      int pivot = k;
      for (int i = k + 1; i < kN; ++i) {
        if (std::abs(a[i * kN + k]) > std::abs(a[pivot * kN + k])) pivot = i;
      }
      if (pivot != k) {
        for (int j = 0; j < kN; ++j) std::swap(a[k * kN + j], a[pivot * kN + j]);
      }
      for (int i = k + 1; i < kN; ++i) {
        const double factor = a[i * kN + k] / a[k * kN + k];
        a[i * kN + k] = factor;
        for (int j = k + 1; j < kN; ++j) a[i * kN + j] -= factor * a[k * kN + j];
      }
    }
    times.push_back(Seconds(start));
    if (!std::isfinite(a[kN * kN - 1])) std::abort();  // keeps the loop from being elided
  }
  return Median(times);
}

double g_lu_unit = 0.0;  // s, set once at start

void BenchCase(const std::string& name, int repeats) {
  const std::string path = std::string(NFRC_SOURCE_DIR) + "/cases/" + name;
  std::vector<double> times;
  nfrc::Branch branch;
  for (int r = 0; r < repeats; ++r) {
    nfrc::Case the_case = nfrc::LoadCase(path);
    const auto start = Clock::now();
    auto system = nfrc::BuildSystem(the_case);
    const Eigen::VectorXd guess = nfrc::StartingGuess(the_case, *system, nullptr);
    branch = nfrc::Trace(*system, the_case.continuation, nullptr, &guess);
    times.push_back(Seconds(start));
  }
  const auto& s = branch.summary;
  std::printf("%s: %s, %d points, %d folds, %d unknowns\n", name.c_str(), nfrc::ToString(s.reason),
              s.num_points, s.num_folds, static_cast<int>(branch.points.front().y.size()));
  std::printf("  wall time      %.2f ms = %.1f LU(320) (median of %d runs)\n", 1e3 * Median(times),
              Median(times) / g_lu_unit, repeats);
  std::printf("  per point      %.3f ms\n", 1e3 * Median(times) / s.num_points);
  std::printf("  Newton/point   %.2f (%d iterations, %d rejected steps)\n",
              static_cast<double>(s.total_newton_iterations) / s.num_points,
              s.total_newton_iterations, s.num_rejected_steps);
}

// Clamped chain of n unit masses and unit springs, 1 % stiffness-proportional damping.
nfrc::LinearModel Chain(int n) {
  std::vector<Eigen::Triplet<double>> k, m;
  for (int i = 0; i < n; ++i) {
    m.emplace_back(i, i, 1.0);
    k.emplace_back(i, i, i + 1 < n ? 2.0 : 1.0);
    if (i + 1 < n) {
      k.emplace_back(i, i + 1, -1.0);
      k.emplace_back(i + 1, i, -1.0);
    }
  }
  nfrc::LinearModel model;
  model.mass.resize(n, n);
  model.stiffness.resize(n, n);
  model.mass.setFromTriplets(m.begin(), m.end());
  model.stiffness.setFromTriplets(k.begin(), k.end());
  model.damping = 0.01 * model.stiffness;
  return model;
}

void BenchChain(int n, int frequencies) {
  const nfrc::HarmonicSet set(20, false);
  nfrc::Condensation condensation(Chain(n), {n / 2, n - 1}, set, {{n - 1, 1, 1.0, 0.0}},
                                  nfrc::Condensation::Method::kSparse);
  std::vector<double> times;
  for (int f = 0; f < frequencies; ++f) {
    const double omega = 1e-3 * (1.0 + 0.1 * f);  // below the chain's cut-off frequency 2
    const auto start = Clock::now();
    condensation.Update(omega);
    times.push_back(Seconds(start));
  }
  std::printf(
      "sparse chain %6d DOFs -> 2 DOFs, H=20 (21 harmonics): %.1f ms per frequency "
      "(median of %d)\n",
      n, 1e3 * Median(times), frequencies);
}

// Lowest eigenfrequency sqrt(λ_min) of K φ = λ M φ (K symmetric positive definite) by
// inverse iteration with a sparse Cholesky factorisation of K.
double LowestEigenfrequency(const nfrc::LinearModel& model) {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> k(model.stiffness);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(model.num_dofs());
  double lambda = 0.0;
  for (int i = 0; i < 40; ++i) {
    x = k.solve(model.mass * x);
    x /= std::sqrt(x.dot(model.mass * x));
    const double next = x.dot(model.stiffness * x);  // Rayleigh quotient (xᵀMx = 1)
    if (i > 0 && std::abs(next - lambda) <= 1e-14 * next) {
      lambda = next;
      break;
    }
    lambda = next;
  }
  return std::sqrt(lambda);
}

// cases/rod/rigid_nh20.json refined to `elements` elements with Rayleigh damping
// C = βK, β = 2ζ/ω0 (ζ = 0.75 % at ω0 = 63 954 rad/s, the 20-element rod's first mode;
// modal damping is limited to 3000 DOFs), traced from ω = 6.3e4 (in contact) towards 6.6e4
// for at most `max_points` points. Also times the condensation update alone and measures
// its rounding noise: |Z(ω+δ) − Z(ω−δ) − 2δ dZ/dω(ω)| / 2 at harmonic 1, δ = 1e-3 rad/s
// (the truncation error, δ²/6·|d³Z/dω³|, is negligible at this δ).
void BenchRefinedRod(int elements, int max_points) {
  constexpr double kOmega0 = 63954.0;
  constexpr double kRatio = 0.0075;
  const double beta = 2.0 * kRatio / kOmega0;
  const std::string path = std::string(NFRC_SOURCE_DIR) + "/cases/rod/rigid_nh20.json";
  // The case as read, with the rod refined: the model is rebuilt from the file's rod
  // parameters (the typed case keeps the built matrices, not the parameters) and the
  // contact and forcing move to the new end DOF.
  const nfrc::CaseFile file = nfrc::ReadCaseFile(path);
  nfrc::Case the_case = file.the_case;
  nfrc::RodParameters rod;
  rod.elements = elements;
  rod.length = file.source["model"]["length"].get<double>();
  rod.area = file.source["model"]["area"].get<double>();
  rod.young = file.source["model"]["young"].get<double>();
  rod.density = file.source["model"]["density"].get<double>();
  the_case.model.model = nfrc::BuildRod(rod);
  const int end = the_case.model.model.FindDof("end");
  the_case.model.model.damping =
      nfrc::RayleighDamping(the_case.model.model.mass, the_case.model.model.stiffness, 0.0, beta);
  for (nfrc::ForcingTerm& term : the_case.model.forcing) term.dof = end;
  for (nfrc::LawSpec& law : the_case.laws)
    std::get<nfrc::DlftContactSpec>(law).contact.geometry.dof = end;
  the_case.output_dofs = {end};
  the_case.continuation.lambda_start = 6.3e4;
  the_case.continuation.lambda_end = 6.6e4;
  the_case.continuation.max_points = max_points;
  const nfrc::LinearModel model = the_case.model.model;  // MakeSystem copies it anyway
  const std::vector<nfrc::ForcingTerm> forcing = the_case.model.forcing;
  const double omega0 = LowestEigenfrequency(model);

  auto start = Clock::now();
  auto system = nfrc::BuildSystem(the_case);
  const double build_time = Seconds(start);
  start = Clock::now();
  const Eigen::VectorXd guess = nfrc::StartingGuess(the_case, *system, nullptr);
  const double start_time = Seconds(start);
  start = Clock::now();
  const nfrc::Branch branch = nfrc::Trace(*system, the_case.continuation, nullptr, &guess);
  const double trace_time = Seconds(start);
  const auto& s = branch.summary;
  int fallbacks = 0;  // accepted steps solved at fixed ω after the arclength corrector failed
  for (const nfrc::StepRecord& record : s.history) {
    if (record.accepted && record.note.rfind("natural-parameter", 0) == 0) ++fallbacks;
  }

  // The condensation update alone, at ω − δ, ω, ω + δ in the traced range (after one
  // untimed update).
  nfrc::Condensation condensation(model, {model.FindDof("end")}, the_case.harmonics, forcing);
  constexpr double kOmega = 6.4e4;
  constexpr double kDelta = 1e-3;
  condensation.Update(6.3e4);  // first update: symbolic analysis and allocations, not timed
  std::vector<double> update_times;
  std::complex<double> z[3];
  std::complex<double> dz;
  for (int i = 0; i < 3; ++i) {
    start = Clock::now();
    condensation.Update(kOmega + (i - 1) * kDelta);
    update_times.push_back(Seconds(start));
    z[i] = condensation.Z(1)(0, 0);
    if (i == 1) dz = condensation.dZ(1)(0, 0);
  }
  const double noise = 0.5 * std::abs(z[2] - z[0] - 2.0 * kDelta * dz);

  // One residual + Jacobian evaluation at the last point at the cached ω: the laws and the
  // assembly without the condensation update.
  const nfrc::BranchPoint& last = branch.points.back();
  Eigen::VectorXd residual, jacobian_omega;
  Eigen::MatrixXd jacobian_y;
  system->Evaluate(last.y, last.lambda, &residual, &jacobian_y, &jacobian_omega);
  std::vector<double> cached_times;
  for (int i = 0; i < 20; ++i) {
    start = Clock::now();
    system->Evaluate(last.y, last.lambda, &residual, &jacobian_y, &jacobian_omega);
    cached_times.push_back(Seconds(start));
  }
  // The residual tolerance in newtons: residual_tolerance · ‖R(0, ω_start)‖.
  system->Evaluate(Eigen::VectorXd::Zero(system->NumUnknowns()), the_case.continuation.lambda_start,
                   &residual, nullptr, nullptr);
  const double tolerance = the_case.continuation.residual_tolerance * residual.norm();
  const double x_norm = last.y.head(system->num_displacement_unknowns()).norm();

  const int steps = std::max(1, s.num_accepted_steps);
  std::printf(
      "rod %d elements (%d DOFs), rigid contact at end, N_h=20, N_t=400, %s "
      "condensation, Rayleigh C = %.4g s * K\n",
      elements, model.num_dofs(),
      model.num_dofs() >= nfrc::Condensation::kDenseLimit ? "sparse" : "dense", beta);
  std::printf("  omega0         %.1f rad/s (inverse iteration), damping ratio there %.4f %%\n",
              omega0, 100.0 * 0.5 * beta * omega0);
  std::printf(
      "  traced         %s: %d points, omega %.0f -> %.0f, %d accepted + %d rejected "
      "steps, %d Newton iterations, %d evaluations\n",
      nfrc::ToString(s.reason), s.num_points, branch.points.front().lambda, last.lambda,
      s.num_accepted_steps, s.num_rejected_steps, s.total_newton_iterations, s.num_evaluations);
  std::printf(
      "  setup          %.1f ms system, %.1f ms starting point (not in the figures "
      "below)\n",
      1e3 * build_time, 1e3 * start_time);
  std::printf(
      "  per step       %.1f ms (trace %.2f s / %d accepted steps, start Newton "
      "included); %d of %d steps needed the fixed-omega fallback\n",
      1e3 * trace_time / steps, trace_time, steps, fallbacks, steps);
  std::printf(
      "  per evaluation %.2f ms in the trace (%.1f evaluations/step); %.3f ms at a "
      "cached omega (median of 20)\n",
      1e3 * trace_time / std::max(1, s.num_evaluations),
      static_cast<double>(s.num_evaluations) / steps, 1e3 * Median(cached_times));
  std::printf("  update         %.2f ms per frequency, condensation alone (median of 3)\n",
              1e3 * Median(update_times));
  std::printf(
      "  Z rounding     %.3g N/m at harmonic 1 (|Z| = %.3g N/m): residual noise "
      "~%.2g N vs tolerance %.2g N\n",
      noise, std::abs(z[1]), noise * x_norm, tolerance);
}

// Times of one LCP-HBM point at ω for `lcp` (medians of `repeats`). Assemble caches W, p per
// ω, so every timed call that must assemble gets its own ω, perturbed by a relative 1e-9
// (far below any change of the contact state); `perturbation` counts the offsets used.
struct LcpPointTimes {
  double assembly = 0.0;  // s, Assemble at a fresh ω (condensed operator, W, p)
  double lemke = 0.0;     // s, Solve at an already assembled ω (scaling, Lemke, unknowns)
  double total = 0.0;     // s, Solve at a fresh ω: the whole point
  nfrc::LcpHbm::Solution solution;  // of the last total
};

LcpPointTimes TimeLcpPoint(nfrc::LcpHbm& lcp, double omega, int repeats, int* perturbation) {
  std::vector<double> assembly, lemke, total;
  LcpPointTimes times;
  for (int r = 0; r < repeats; ++r) {
    double fresh = omega * (1.0 + 1e-9 * ++*perturbation);
    auto start = Clock::now();
    lcp.Assemble(fresh);
    assembly.push_back(Seconds(start));
    start = Clock::now();
    lcp.Solve(fresh);
    lemke.push_back(Seconds(start));
    fresh = omega * (1.0 + 1e-9 * ++*perturbation);
    start = Clock::now();
    times.solution = lcp.Solve(fresh);
    total.push_back(Seconds(start));
  }
  times.assembly = Median(assembly);
  times.lemke = Median(lemke);
  times.total = Median(total);
  return times;
}

#ifdef NFRC_HAVE_SICONOS
// Siconos's lcp_lexicolemke on the problem LcpHbm::Solve hands to Lemke (W/‖W‖max,
// p/‖p‖∞): the solve's time (s) and whether it returned a verified solution, i.e. info 0
// and z ≥ 0, g = W z + p ≥ 0, g_i z_i = 0 to 1e-8 of the unit scales (nfrc's Lemke meets
// ~1e-12 there; Siconos's "info 0" alone also covers garbage on some problems).
struct SiconosPoint {
  double seconds = 0.0;
  bool solved = false;
  int pivots = 0;
};

SiconosPoint SolveSiconos(const nfrc::LcpHbm::Problem& problem) {
  constexpr double kTolerance = 1e-8;
  const Eigen::MatrixXd w = problem.w / problem.w.cwiseAbs().maxCoeff();
  const Eigen::VectorXd p = problem.p / problem.p.cwiseAbs().maxCoeff();
  const auto start = Clock::now();
  const nfrc::SiconosLcpResult r =
      nfrc::SolveLcpSiconos(w, p, nfrc::SiconosLcpSolver::kLexicoLemke);
  SiconosPoint point;
  point.seconds = Seconds(start);
  point.pivots = r.iterations;
  const Eigen::VectorXd gap = w * r.z + p;
  const double z_scale = std::max(1.0, r.z.lpNorm<Eigen::Infinity>());
  point.solved = r.ok && r.z.minCoeff() >= -kTolerance * z_scale && gap.minCoeff() >= -kTolerance &&
                 gap.cwiseProduct(r.z).lpNorm<Eigen::Infinity>() <= kTolerance * z_scale;
  return point;
}
#endif

// LCP-HBM per point for the rigid-obstacle rod with N_h = 20 at each N_t in `samples`: the
// two contact frequencies, then the mean over a sweep of cold starts, each a Solve at a new
// ω as `nfrc run` does with lemke_stepping (its warm re-solves for coexisting contact
// states are not included). Siconos's lcp_lexicolemke, when built in, solves the same scaled
// problems: median of `siconos_repeats` at the two frequencies (it is O(n²) per pivot), once
// per sweep point.
void BenchLcpPerPoint(const std::vector<int>& samples, int repeats, int sweep_points,
                      int siconos_repeats) {
  const auto section_start = Clock::now();
  const std::string dir = std::string(NFRC_SOURCE_DIR) + "/cases/lcp";
  const nfrc::Case base = nfrc::LoadCase(dir + "/rigid_stepping_nt400.json");
  constexpr double kOmegas[] = {63953.9, 6.45e4};  // rad/s, both in contact
  constexpr double kSweepStart = 6.2e4;            // rad/s
  constexpr double kSweepEnd = 6.6e4;              // rad/s
  std::printf(
      "LCP-HBM per point: rigid-obstacle rod (cases/lcp/rigid_stepping_nt400.json), N_h=20, "
      "median of %d (LU = LU(320) units)\n",
      repeats);
  std::printf("  %4s %5s %10s %9s %8s %8s %6s %9s %8s", "N_t", "n", "omega", "assem ms", "Lemke ms",
              "Lemke LU", "pivots", "total ms", "total LU");
#ifdef NFRC_HAVE_SICONOS
  std::printf(" %10s %10s %8s", "Siconos ms", "Siconos LU", "pivots");
#endif
  std::printf("\n");
  for (int nt : samples) {
    nfrc::Case the_case = base;
    the_case.harmonics =
        nfrc::HarmonicSet(base.harmonics.max_harmonic(), base.harmonics.odd_only(), nt);
    auto system = nfrc::BuildSystem(the_case);
    nfrc::LcpHbm lcp(*system, the_case.laws);
    int perturbation = 0;
    lcp.Solve(kSweepStart);  // first point: allocations, not timed
    for (double omega : kOmegas) {
      const LcpPointTimes t = TimeLcpPoint(lcp, omega, repeats, &perturbation);
      std::printf("  %4d %5d %10.1f %9.3f %8.3f %8.3f %6d %9.3f %8.3f", nt, lcp.num_samples(),
                  omega, 1e3 * t.assembly, 1e3 * t.lemke, t.lemke / g_lu_unit,
                  t.solution.lemke.pivots, 1e3 * t.total, t.total / g_lu_unit);
#ifdef NFRC_HAVE_SICONOS
      std::vector<double> times;
      SiconosPoint point;
      for (int r = 0; r < siconos_repeats; ++r) {
        point = SolveSiconos(lcp.Assemble(omega));
        times.push_back(point.seconds);
      }
      std::printf(" %10.3f %10.3f %8d%s", 1e3 * Median(times), Median(times) / g_lu_unit,
                  point.pivots, point.solved ? "" : "  (Siconos failed)");
#else
      (void)siconos_repeats;
#endif
      std::printf("%s\n", t.solution.lemke.ok() ? "" : "  (Lemke failed)");
    }
    int pivots = 0;
    int failures = 0;
    const auto start = Clock::now();
    for (int i = 0; i < sweep_points; ++i) {
      const double omega = kSweepStart + (kSweepEnd - kSweepStart) * i / (sweep_points - 1);
      const nfrc::LcpHbm::Solution solution = lcp.Solve(omega);
      pivots += solution.lemke.pivots;
      if (!solution.lemke.ok()) ++failures;
    }
    const double sweep = Seconds(start);
    std::printf(
        "  %4d %5d  sweep %d cold starts %.0f..%.0f: %.3f ms/point mean = %.3f LU, %.1f "
        "pivots mean, nfrc Lemke solved %d, failed %d\n",
        nt, lcp.num_samples(), sweep_points, kSweepStart, kSweepEnd, 1e3 * sweep / sweep_points,
        sweep / sweep_points / g_lu_unit, static_cast<double>(pivots) / sweep_points,
        sweep_points - failures, failures);
#ifdef NFRC_HAVE_SICONOS
    double siconos_time = 0.0;
    int siconos_solved = 0;
    for (int i = 0; i < sweep_points; ++i) {
      const double omega = kSweepStart + (kSweepEnd - kSweepStart) * i / (sweep_points - 1);
      const SiconosPoint point = SolveSiconos(lcp.Assemble(omega));
      siconos_time += point.seconds;
      siconos_solved += point.solved;
    }
    std::printf(
        "  %4d %5d  same sweep, Siconos lcp_lexicolemke: %.3f ms/solve mean = %.3f LU, "
        "solved %d, failed %d\n",
        nt, lcp.num_samples(), 1e3 * siconos_time / sweep_points,
        siconos_time / sweep_points / g_lu_unit, siconos_solved, sweep_points - siconos_solved);
#endif
  }
  std::printf("  section time   %.2f s\n", Seconds(section_start));
}

void BenchTransient(const std::string& name, double omega, int repeats) {
  nfrc::Case the_case = nfrc::LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
  const nfrc::ValidationSettings& settings = the_case.validation;
  nfrc::TransientModel model = nfrc::MakeTransientModel(the_case.model, the_case.laws);
  const std::unique_ptr<nfrc::TransientIntegrator> integrator =
      nfrc::MakeTransientIntegrator(model, settings.transient);
  nfrc::InitialState rest;
  rest.x = Eigen::VectorXd::Zero(model.num_dofs());
  rest.v = rest.x;
  std::vector<double> times;
  nfrc::TransientResult result;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    result = integrator->RunToSteadyState(omega, rest);
    times.push_back(Seconds(start));
  }
  std::printf("transient %s at omega=%g from rest (%s): %s\n", name.c_str(), omega,
              result.method.c_str(), nfrc::ToString(result.status));
  std::printf("  wall time      %.3f s = %.1f LU(320) (median of %d runs)\n", Median(times),
              Median(times) / g_lu_unit, repeats);
  std::printf("  periods        %d (%.3f ms/period), %ld steps, %ld events\n", result.periods,
              1e3 * Median(times) / std::max(1, result.periods), result.steps, result.events);
  const nfrc::TransientStatistics& st = result.statistics;
  std::printf(
      "  integrator     %ld residual and %ld Jacobian evaluations, %ld nonlinear "
      "iterations, %ld convergence and %ld error-test failures\n",
      st.residual_evaluations, st.jacobian_evaluations, st.nonlinear_iterations,
      st.nonlinear_convergence_failures, st.error_test_failures);
}

}  // namespace

void BenchStability(const std::string& name, int max_harmonic, int max_points) {
  nfrc::Case the_case = nfrc::LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
  if (max_harmonic > 0) the_case.harmonics = nfrc::HarmonicSet(max_harmonic, true);
  if (max_points > 0) the_case.continuation.max_points = max_points;
  the_case.stability.enabled = false;
  auto start = Clock::now();
  const nfrc::TraceResult off = nfrc::TraceCase(the_case);
  const double t_off = Seconds(start);
  the_case.stability.enabled = true;
  start = Clock::now();
  const nfrc::TraceResult on = nfrc::TraceCase(the_case);
  const double t_on = Seconds(start);
  double hill = 0.0;
  for (const nfrc::TracePoint& p : on.points) hill += p.floquet.seconds;
  const double n = static_cast<double>(on.points.size());
  std::printf("%s%s: %d points, %d unknowns, %zu bifurcations\n", name.c_str(),
              max_harmonic > 0 ? (" H=" + std::to_string(max_harmonic)).c_str() : "",
              static_cast<int>(on.points.size()), on.num_unknowns, on.bifurcations.size());
  std::printf("  trace, stability off  %.1f ms = %.1f LU(320)\n", 1e3 * t_off, t_off / g_lu_unit);
  std::printf("  trace, stability on   %.1f ms = %.1f LU(320)  (x%.2f)\n", 1e3 * t_on,
              t_on / g_lu_unit, t_on / t_off);
  std::printf("  per point: point %.3f ms = %.3f LU(320), Hill %.3f ms = %.3f LU(320) (x%.2f)\n",
              1e3 * t_off / n, t_off / n / g_lu_unit, 1e3 * hill / n, hill / n / g_lu_unit,
              hill / t_off);
}

// usage: nfrc_bench [SECTION ...] runs the numbered sections above (default: all).
int main(int argc, char** argv) {
  std::vector<int> sections;
  for (int i = 1; i < argc; ++i) sections.push_back(std::atoi(argv[i]));
  auto run = [&](int section) {
    return sections.empty() ||
           std::find(sections.begin(), sections.end(), section) != sections.end();
  };
  g_lu_unit = LuUnitSeconds();
  std::printf("calibration: one LU(320) = %.3f ms on this machine now\n", 1e3 * g_lu_unit);
  if (run(1)) BenchCase("duffing.json", 5);
  if (run(2)) BenchCase("friction/frc_n10.json", 3);
  if (run(3)) {
    BenchChain(10000, 5);
    BenchChain(100000, 5);
  }
  if (run(4)) BenchCase("rod/rigid_nh20.json", 3);
  if (run(5)) {
    BenchRefinedRod(20, 20);
    BenchRefinedRod(10000, 20);
    BenchRefinedRod(100000, 8);
  }
  if (run(6)) BenchLcpPerPoint({41, 400, 600}, 5, 31, 3);
  if (run(7)) {
    BenchTransient("validation/friction_point_e.json", 0.308, 3);
    BenchTransient("validation/rod_flexible_4krod.json", 63954.0, 3);
    BenchTransient("validation/rod_rigid.json", 63954.0, 3);
  }
  if (run(8)) {
    BenchStability("duffing.json", 0, 0);
    BenchStability("friction/frc_n10.json", 0, 0);
    BenchStability("friction/frc_n10.json", 159, 60);
    BenchStability("rod/rigid_nh20.json", 0, 0);
    BenchStability("rod/flexible_4krod.json", 0, 0);
  }
  return 0;
}
