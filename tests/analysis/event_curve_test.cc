// Event curves. Peaks: the one-harmonic Duffing resonance peak in the forcing against its
// closed form, and the friction oscillator's peaks in the normal load against branches traced
// at fixed loads. Neimark–Sacker points of an oscillator with a nonlinear energy sink against
// the bifurcations of fixed-forcing traces.
#include "analysis/event_curve.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "analysis/bifurcation.h"
#include "analysis/trace.h"
#include "core/errors.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

constexpr double kK = 1.0, kC = 0.2, kK3 = 0.1, kBeta = 0.75 * kK3;
// The peak is bracketed to 1e-8 relative in ω and the H = 1 balance is the amplitude equation
// exactly (16 samples resolve x³), so only the Newton tolerance (1e-10 scaled updates) and the
// bracket width stand between the two.
constexpr double kClosedFormOmega = 1e-7;
constexpr double kClosedFormAmplitude = 1e-8;

// ẍ + 0.2ẋ + x + 0.1x³ = P cos ωt with one harmonic, P = 0.3.
Case DuffingCase() {
  const nlohmann::json source = R"({
    "model": {"type": "matrices", "M": [[1]], "C": [[0.2]], "K": [[1]],
              "forcing": [{"dof": 0, "cos": 0.3}]},
    "nonlinearities": [{"type": "cubic_spring", "dof": 0, "coefficient": 0.1}],
    "harmonics": {"max": 1, "odd_only": true, "samples": 16},
    "continuation": {"omega_start": 0.5, "omega_end": 2.0, "step": 0.01},
    "output": {"dofs": [0]}
  })"_json;
  return ParseCase(source, ".");
}

// The maximum of A over ω of [(k − ω² + βA²)² + (cω)²]A² = P²: where ∂/∂ω vanishes,
// k − ω² + βA² = c²/2, so (c⁴/4 + c²ω²)A² = P², a quadratic in a = A².
void ClosedFormPeak(double p, double* omega, double* amplitude) {
  const double b = kC * kC * kK - std::pow(kC, 4) / 4.0;
  const double a =
      (-b + std::sqrt(b * b + 4.0 * kC * kC * kBeta * p * p)) / (2.0 * kC * kC * kBeta);
  *amplitude = std::sqrt(a);
  *omega = std::sqrt(kK + kBeta * a - kC * kC / 2.0);
}

TEST_CASE("peak curve of Duffing with one harmonic in the forcing: closed form") {
  const Case the_case = DuffingCase();
  const CaseParameter forcing("model.forcing[0].cos", the_case);
  EventCurveOptions options;
  options.to = 1.0;
  options.measure = ParsePeakMeasure("h1:0", the_case);
  options.stations = {0.5, 0.75};
  const EventCurveResult result = TracePeakCurves(the_case, forcing, options);
  REQUIRE(result.branch_events == 1);
  REQUIRE(result.curves.size() == 1);
  const EventCurve& curve = result.curves[0];
  CHECK(curve.end == EventCurveEnd::kReachedTo);
  REQUIRE(curve.points.size() >= 4);
  double worst_omega = 0.0, worst_amplitude = 0.0;
  int stations = 0;
  for (const EventCurvePoint& point : curve.points) {
    double omega = 0.0, amplitude = 0.0;
    ClosedFormPeak(point.parameter, &omega, &amplitude);
    worst_omega = std::max(worst_omega, std::abs(point.omega - omega));
    worst_amplitude = std::max(worst_amplitude, std::abs(point.measure - amplitude) / amplitude);
    stations += point.parameter == 0.5 || point.parameter == 0.75;
  }
  CHECK(stations == 2);
  CHECK(curve.points.back().parameter == 1.0);
  CHECK(worst_omega < kClosedFormOmega);
  CHECK(worst_amplitude < kClosedFormAmplitude);
  MESSAGE("H = 1 peak curve, P 0.3 -> 1: " << curve.points.size() << " points, " << curve.solves
                                           << " solves; largest errors: omega " << worst_omega
                                           << ", relative amplitude " << worst_amplitude);
}

TEST_CASE("peak curve options and measures are checked") {
  const Case the_case = DuffingCase();
  CHECK_THROWS_WITH_AS(ParsePeakMeasure("h2:0", the_case), doctest::Contains("measure"),
                       InputError);
  CHECK_THROWS_WITH_AS(ParsePeakMeasure("max_abs:x9", the_case), doctest::Contains("x9"),
                       InputError);
  const CaseParameter forcing("model.forcing[0].cos", the_case);
  EventCurveOptions options;
  options.to = 0.3;
  CHECK_THROWS_WITH_AS(TracePeakCurves(the_case, forcing, options), doctest::Contains("to"),
                       InputError);
  options.to = 1.0;
  options.stations = {2.0};
  CHECK_THROWS_WITH_AS(TracePeakCurves(the_case, forcing, options), doctest::Contains("stations"),
                       InputError);
  options.stations.clear();
  options.near = -1.0;
  CHECK_THROWS_WITH_AS(TracePeakCurves(the_case, forcing, options), doctest::Contains("near"),
                       InputError);
  const CaseParameter coefficient("nonlinearities[0].coefficient", the_case);
  options.near = std::numeric_limits<double>::quiet_NaN();
  options.to = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH_AS(TracePeakCurves(the_case, coefficient, options), doctest::Contains("to"),
                       InputError);
}

// The friction oscillator of Legrand & Pierre (2024), Fig. 7, at N_φ = 30 and 512 samples
// (the published curves use 60 and 1024; a coarser balance keeps the test short and changes
// nothing in what is compared: the same discretisation on both sides).
Case FrictionCase(double normal_load) {
  CaseFile file = ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/friction/frc_n10.json");
  nlohmann::json source = file.source;
  source["harmonics"]["max"] = 29;
  source["harmonics"]["samples"] = 512;
  source["nonlinearities"][0]["normal_load"] = normal_load;
  source["continuation"]["plot_tolerance"] = 2e-4;
  return ParseCase(source, ".");
}

// The largest value of the measure among a traced branch's points near ω, with the vertex of
// the parabola through it and its two neighbours: an estimate of the peak from the arclength
// engine's points alone.
struct BranchPeak {
  double point_measure = 0.0;
  double omega = 0.0, measure = 0.0;  // the parabola's vertex
  double spacing = 0.0;               // largest ω distance to the neighbours
};

BranchPeak PeakOfBranch(const Case& the_case, const PeakMeasure& measure, double near) {
  Case branch_case = the_case;
  branch_case.stability.enabled = false;
  TraceOptions options;
  options.solve_signals = false;
  const TraceResult trace = TraceCase(branch_case, options);
  auto system = BuildSystem(the_case);
  PointAnalyzer analyzer(*system, the_case.output_dofs);
  std::vector<double> omega, m;
  for (const TracePoint& point : trace.points) {
    omega.push_back(point.point.lambda);
    m.push_back(EvaluatePeakMeasure(measure, *system, analyzer, point.point.y, omega.back()));
  }
  size_t best = 1;
  for (size_t i = 1; i + 1 < m.size(); ++i) {
    const bool is_max = m[i] > m[i - 1] && m[i] >= m[i + 1];
    if (is_max && std::abs(omega[i] - near) < std::abs(omega[best] - near)) best = i;
  }
  const double x0 = omega[best - 1], x1 = omega[best], x2 = omega[best + 1];
  const double y0 = m[best - 1], y1 = m[best], y2 = m[best + 1];
  // Vertex of the interpolating parabola (divided differences).
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
  const double curvature = (d12 - d01) / (x2 - x0);
  BranchPeak peak;
  peak.point_measure = y1;
  peak.omega = 0.5 * (x0 + x1) - d01 / (2.0 * curvature);
  peak.measure = y0 + (peak.omega - x0) * (d01 + curvature * (peak.omega - x1));
  peak.spacing = std::max(x1 - x0, x2 - x1);
  return peak;
}

const EventCurvePoint* PointAt(const EventCurve& curve, double parameter) {
  for (const EventCurvePoint& point : curve.points) {
    if (point.parameter == parameter) return &point;
  }
  return nullptr;
}

// The branch points are held to the plot tolerance (2e-4 relative in the energy) and the
// parabola through the three around the maximum is off by O(spacing³): relative 2e-3 covers
// both; ω may be off by up to the points' spacing where the maximum is flat.
constexpr double kBranchMeasure = 2e-3;

void CheckAgainstBranch(const EventCurvePoint& point, const Case& the_case,
                        const PeakMeasure& measure) {
  const BranchPeak branch = PeakOfBranch(the_case, measure, point.omega);
  // The located maximum cannot lie below a solution on the branch (1e-9: solve tolerance).
  CHECK(point.measure >= branch.point_measure * (1.0 - 1e-9));
  CHECK(std::abs(point.measure - branch.measure) <= kBranchMeasure * branch.measure);
  CHECK(std::abs(point.omega - branch.omega) <= branch.spacing);
  MESSAGE(measure.name << " at N = " << point.parameter << ": peak curve omega " << point.omega
                       << ", " << point.measure << "; single branch omega " << branch.omega << ", "
                       << branch.measure << " (points " << branch.spacing << " apart)");
}

TEST_CASE("friction oscillator: peak curves in the normal load against single runs at 8, 10, 12") {
  const Case at_8 = FrictionCase(8.0);
  const CaseParameter load("nonlinearities[0].normal_load", at_8);
  // The primary resonance (energy, near the sliding mode 0.618) from N = 8 through 10.
  EventCurveOptions options;
  options.to = 10.0;
  options.near = 0.618;
  const EventCurveResult primary = TracePeakCurves(at_8, load, options);
  REQUIRE(primary.curves.size() == 1);
  CHECK(primary.curves[0].end == EventCurveEnd::kReachedTo);
  for (double n : {8.0, 10.0}) {
    const EventCurvePoint* point = PointAt(primary.curves[0], n);
    REQUIRE(point != nullptr);
    CheckAgainstBranch(*point, FrictionCase(n), options.measure);
  }
  // The damper's first-harmonic peak near 0.55 (mode 2's 3:1 resonance), from N = 10 to 12.
  const Case at_10 = FrictionCase(10.0);
  options.to = 12.0;
  options.near = 0.553;
  options.measure = ParsePeakMeasure("h1:x2", at_10);
  const EventCurveResult damper = TracePeakCurves(at_10, load, options);
  REQUIRE(damper.curves.size() == 1);
  CHECK(damper.curves[0].end == EventCurveEnd::kReachedTo);
  const EventCurvePoint* point = PointAt(damper.curves[0], 12.0);
  REQUIRE(point != nullptr);
  CheckAgainstBranch(*point, FrictionCase(12.0), options.measure);
}

}  // namespace
}  // namespace nfrc

namespace nfrc {
namespace {

// Both localisations stop at 1e-6 relative in ω or better (the trace's bifurcation_tolerance;
// the curve's bracket 1e-8), so they agree to a few 1e-6.
constexpr double kNeimarkSackerOmega = 5e-6;

TEST_CASE("Neimark-Sacker curves of the NES oscillator in the forcing against fixed-P runs") {
  const Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/nes_neimark_sacker.json");
  const CaseParameter forcing("model.forcing[0].cos", the_case);
  EventCurveOptions options;
  options.to = 0.01;
  options.stations = {0.0075};
  const EventCurveResult result = TraceNeimarkSackerCurves(the_case, forcing, options);
  REQUIRE(result.branch_events == 2);
  REQUIRE(result.curves.size() == 2);
  for (double p : {0.0075, 0.01}) {
    TraceOptions trace_options;
    trace_options.solve_signals = false;
    const TraceResult trace = TraceCase(forcing.With(the_case, p), trace_options);
    std::vector<double> reference;
    for (const Bifurcation& b : trace.bifurcations) {
      if (b.type == BifurcationType::kNeimarkSacker) reference.push_back(b.omega);
    }
    REQUIRE(reference.size() == 2);
    for (const EventCurve& curve : result.curves) {
      CHECK(curve.end == EventCurveEnd::kReachedTo);
      const EventCurvePoint* point = nullptr;
      for (const EventCurvePoint& q : curve.points) {
        if (q.parameter == p) point = &q;
      }
      REQUIRE(point != nullptr);
      double nearest = reference[0];
      for (double omega : reference) {
        if (std::abs(omega - point->omega) < std::abs(nearest - point->omega)) nearest = omega;
      }
      CHECK(std::abs(point->omega - nearest) < kNeimarkSackerOmega * nearest);
      MESSAGE("P = " << p << ": Neimark-Sacker curve omega " << point->omega << ", fixed-P run "
                     << nearest << ", relative difference "
                     << std::abs(point->omega - nearest) / nearest);
    }
  }
}

TEST_CASE("Neimark-Sacker curves need the stability analysis") {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/nes_neimark_sacker.json");
  the_case.stability.enabled = false;
  const CaseParameter forcing("model.forcing[0].cos", the_case);
  EventCurveOptions options;
  options.to = 0.01;
  CHECK_THROWS_WITH_AS(TraceNeimarkSackerCurves(the_case, forcing, options),
                       doctest::Contains("stability.enabled"), InputError);
}

}  // namespace
}  // namespace nfrc
