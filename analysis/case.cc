#include "analysis/case.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/errors.h"

namespace nfrc {
namespace {

// A third of the machine's 24 GiB: the rest is the OS, the outputs and a second run.
constexpr double kMaxBytes = 8.0 * (1 << 30);
// Evaluations of R and its Jacobian in a typical trace (~1000 points, ~5 Newton iterations).
constexpr double kTypicalEvaluations = 5000;
// About ten hours at the 2–3 Gflop/s one core of this machine class sustains: a 10⁵-DOF
// rod (the scale nfrc targets) fits, a 10⁶-DOF one does not.
constexpr double kMaxTraceWork = 1e14;
// About a day of work for the points a run computes for sure (Lemke stepping).
constexpr double kMaxTotalWork = 1e14;
// Each signals_at crossing is a Newton solve and a file; beyond this it is not a study.
constexpr double kMaxSignals = 1000;
// The dense Jacobian is stored in several copies (Jacobian, LU, bordered system, scaling).
constexpr double kDenseCopies = 4.0;
// Sparse LU and solves per harmonic and retained DOF of a banded FE model, per model DOF
// (flop), measured on the rod: about 1 s per ω for 10⁶ DOFs and 21 harmonics.
constexpr double kCondensationFlopPerDof = 2000;
// How far above the model's frequency scale sqrt(max K_ii / max M_ii) (at least its highest
// eigenfrequency's order) a traced ω may lie: 10⁶ times, ω²M swamps K by 10¹², and the
// dynamic stiffness keeps four digits of the stiffness.
constexpr double kMaxFrequencyRatio = 1e6;
// Oversampling N_t/(2H + 1) beyond which more samples cannot change a result (the cases of
// the papers use at most ~30×; AFT of a degree-p law is exact from (p + 1)H + 1 samples).
constexpr double kMaxOversampling = 1024;
// Below this many samples no oversampling is refused (cheap whatever H).
constexpr double kFreeSamples = 65536;

std::string Bytes(double bytes) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3g GB", bytes / 1e9);
  return text;
}

std::string Count(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

}  // namespace

const char* ToString(Method method) {
  switch (method) {
    case Method::kArclength:
      return "arclength";
    case Method::kLemkeStepping:
      return "lemke_stepping";
  }
  return "?";
}

ProblemSize EstimateSize(const ProblemDimensions& d) {
  const double h = std::max(1.0, d.max_harmonic);
  const double harmonics = d.odd_only ? std::ceil(h / 2.0) : h + 1.0;
  const double coefficients = d.odd_only ? 2.0 * harmonics : 2.0 * h + 1.0;
  const double samples = d.samples > 0 ? d.samples : std::max(16.0, 4.0 * h + 1.0) * 2.0;
  const double signals = d.num_retained + d.own_blocks;
  const double unknowns = signals * coefficients + d.sample_blocks * samples;
  ProblemSize size;
  // Dense Jacobian copies, the Fourier matrices of every law (coefficients × samples), the
  // condensation's recovery blocks (model DOFs × retained × harmonics, complex) and the
  // samples of every law.
  size.bytes = 8.0 * (kDenseCopies * unknowns * unknowns + 2.0 * coefficients * samples +
                      2.0 * d.num_dofs * d.num_retained * harmonics +
                      (signals + d.sample_blocks) * samples * 4.0);
  // Dense LU of the Newton matrix, the laws' Jacobian blocks P diag(f') E (by product-to-sum
  // from one FFT of f': coefficients² + FFT per signal), the sparse condensation per harmonic
  // and retained DOF.
  size.work_per_step =
      unknowns * unknowns * unknowns / 3.0 +
      signals * (coefficients * coefficients + 5.0 * samples * std::log2(samples)) +
      kCondensationFlopPerDof * d.num_dofs * harmonics * d.num_retained;
  size.total_work = d.points * size.work_per_step;
  return size;
}

void CheckProblemSize(const ProblemDimensions& d) {
  const double oversampling = d.samples / (2.0 * std::max(1.0, d.max_harmonic) + 1.0);
  if (d.samples > kFreeSamples && oversampling > kMaxOversampling) {
    throw InputError("harmonics.samples: " + Count(d.samples) + " samples per period is " +
                     Count(oversampling) + "x oversampling of harmonic " + Count(d.max_harmonic) +
                     " (at most " + Count(kMaxOversampling) + "x)");
  }
  const ProblemSize size = EstimateSize(d);
  // The field to blame: whichever dimension dominates the estimate.
  const char* blame = d.num_dofs * d.num_retained > 10.0 * d.max_harmonic * d.max_harmonic
                          ? "model"
                          : "harmonics.max";
  if (size.bytes > kMaxBytes) {
    throw InputError(std::string(blame) + ": the problem needs about " + Bytes(size.bytes) +
                     " of memory, more than the " + Bytes(kMaxBytes) + " nfrc allows");
  }
  const double trace_work = kTypicalEvaluations * size.work_per_step;
  if (trace_work > kMaxTraceWork) {
    throw InputError(std::string(blame) + ": a trace needs about " + Count(trace_work) + " flop (" +
                     Count(size.work_per_step) + " per Newton step, " + Count(d.num_dofs) +
                     " DOFs, H = " + Count(d.max_harmonic) + "), more than the " +
                     Count(kMaxTraceWork) + " (about ten hours) nfrc allows");
  }
  if (size.total_work > kMaxTotalWork) {
    throw InputError("continuation.points: " + Count(d.points) + " points need about " +
                     Count(size.total_work) + " flop (limit " + Count(kMaxTotalWork) + ")");
  }
  if (d.signals > kMaxSignals) {
    throw InputError("output.signals_at: " + Count(d.signals) + " frequencies (at most " +
                     Count(kMaxSignals) + "; each is a solve and a file)");
  }
}

ProblemDimensions DimensionsOf(const Case& c) {
  ProblemDimensions d;
  d.num_dofs = c.model.model.num_dofs();
  std::vector<int> retained;
  for (const LawSpec& law : c.laws) {
    for (int dof : LawDofs(law)) {
      if (std::find(retained.begin(), retained.end(), dof) == retained.end()) {
        retained.push_back(dof);
      }
    }
    if (std::holds_alternative<CoulombFrictionSpec>(law) ||
        std::holds_alternative<EqualityContactSpec>(law)) {
      d.own_blocks += 1;
    }
    if (std::holds_alternative<ContactFrictionSpec>(law)) d.own_blocks += 2;
    if (std::holds_alternative<LcpContactSpec>(law)) d.sample_blocks += 1;
  }
  d.num_retained = std::max<double>(1.0, static_cast<double>(retained.size()));
  d.max_harmonic = c.harmonics.max_harmonic();
  d.odd_only = c.harmonics.odd_only();
  d.samples = c.harmonics.num_samples();
  d.points = c.method == Method::kLemkeStepping ? c.stepping.points : 0;
  d.signals = static_cast<double>(c.signals_at.size());
  return d;
}

void ValidateContinuation(const ContinuationOptions& options) {
  try {
    options.Validate();
  } catch (const std::invalid_argument& error) {
    // The engine names its own fields; the case file names some of them otherwise.
    static const std::pair<const char*, const char*> kCaseNames[] = {
        {"initial_step", "step"}, {"lambda_start", "omega_start"}, {"lambda_end", "omega_end"}};
    std::string message = error.what();
    for (const auto& [engine, file] : kCaseNames) {
      const std::string prefix = std::string(engine) + ":";
      if (message.rfind(prefix, 0) == 0) message = file + message.substr(prefix.size() - 1);
    }
    throw InputError("continuation." + message);
  }
}

double FrequencyScale(const LinearModel& model) {
  double k = 0.0, m = 0.0;
  for (int dof = 0; dof < model.num_dofs(); ++dof) {
    k = std::max(k, std::abs(model.stiffness.coeff(dof, dof)));
    m = std::max(m, std::abs(model.mass.coeff(dof, dof)));
  }
  return k > 0.0 && m > 0.0 ? std::sqrt(k / m) : 0.0;
}

void StartOptions::Validate() const {
  if (!(homotopy_factor > 1.0) || !std::isfinite(homotopy_factor)) {
    throw InputError("continuation.start_homotopy_factor: must be finite and > 1");
  }
  if (homotopy_rungs < 1 || homotopy_rungs > kMaxHomotopyRungs) {
    throw InputError("continuation.start_homotopy_rungs: must be between 1 and " +
                     std::to_string(kMaxHomotopyRungs));
  }
}

void Case::Validate() const {
  try {
    model.model.Validate();
  } catch (const std::invalid_argument& error) {
    throw InputError(std::string("model: ") + error.what());
  }
  const int n = model.model.num_dofs();
  const auto& list = harmonics.harmonics();
  for (size_t i = 0; i < model.forcing.size(); ++i) {
    const ForcingTerm& term = model.forcing[i];
    const std::string where = "model.forcing[" + std::to_string(i) + "]";
    if (term.dof < 0 || term.dof >= n) {
      throw InputError(where + ".dof: DOF " + std::to_string(term.dof) + " is not in the model");
    }
    if (std::find(list.begin(), list.end(), term.harmonic) == list.end()) {
      throw InputError("model.forcing: harmonic " + std::to_string(term.harmonic) +
                       " is not in the harmonic set");
    }
    if (!std::isfinite(term.cos) || !std::isfinite(term.sin)) {
      throw InputError(where + ".cos: amplitudes must be finite");
    }
  }
  // Without forcing or a moving obstacle the response is zero at every ω: no branch to follow
  // (the engine would report a singular tangent).
  bool driven = false;
  for (const ForcingTerm& term : model.forcing) driven |= term.cos != 0.0 || term.sin != 0.0;
  for (const LawSpec& law : laws) {
    const ContactGeometry* geometry = LawContactGeometry(law);
    if (geometry == nullptr) continue;
    for (const auto& h : geometry->gap_harmonics) driven |= h.cos != 0.0 || h.sin != 0.0;
  }
  if (!driven) {
    throw InputError(
        "model.forcing: every amplitude is zero and no gap moves: the response "
        "is zero at every omega");
  }
  for (size_t i = 0; i < laws.size(); ++i) {
    try {
      ValidateLaw(laws[i], model.model);
      CheckLawRanges(laws[i], model.model);
    } catch (const InputError& error) {
      throw InputError("nonlinearities[" + std::to_string(i) + "]." + error.what());
    }
    const ContactGeometry* geometry = LawContactGeometry(laws[i]);
    if (geometry == nullptr) continue;
    try {
      geometry->GapCoefficients(harmonics);  // every gap harmonic must be in the set
    } catch (const std::invalid_argument& error) {
      throw InputError("nonlinearities[" + std::to_string(i) + "]." + error.what());
    }
  }
  if (output_dofs.empty()) throw InputError("output.dofs: expected a non-empty list of DOFs");
  if (output_names.size() != output_dofs.size()) {
    throw InputError("output.dofs: output_names must have one name per output DOF");
  }
  for (size_t i = 0; i < output_dofs.size(); ++i) {
    if (output_dofs[i] < 0 || output_dofs[i] >= n) {
      throw InputError("output.dofs[" + std::to_string(i) + "]: DOF " +
                       std::to_string(output_dofs[i]) + " is not in the model");
    }
  }
  if (!(continuation.lambda_start > 0.0) || !std::isfinite(continuation.lambda_start)) {
    throw InputError("continuation.omega_start: must be positive");
  }
  if (!(continuation.lambda_end > 0.0) || !std::isfinite(continuation.lambda_end)) {
    throw InputError("continuation.omega_end: must be positive");
  }
  if (continuation.lambda_end == continuation.lambda_start) {
    throw InputError("continuation.omega_end: must differ from omega_start");
  }
  ValidateContinuation(continuation);
  // A response far above every mode the model resolves is its matrices' rounding: refused
  // before it shows as a singular condensation or a stalled start.
  const double scale = FrequencyScale(model.model);
  const double highest = scale * kMaxFrequencyRatio;
  for (const auto& [field, lambda] : {std::pair{"omega_start", continuation.lambda_start},
                                      std::pair{"omega_end", continuation.lambda_end}}) {
    const double omega = lambda * period_multiple;
    if (scale > 0.0 && omega > highest) {
      throw InputError("continuation." + std::string(field) + ": " + Count(omega) +
                       " is more than " + Count(kMaxFrequencyRatio) +
                       " times the model's highest frequency scale sqrt(max K_ii / max M_ii) = " +
                       Count(scale) + " (at most " + Count(highest) + ")");
    }
  }
  for (double omega : signals_at) {
    if (!(omega > 0.0) || !std::isfinite(omega)) {
      throw InputError("output.signals_at: frequencies must be positive");
    }
  }
  start.Validate();
  if (method == Method::kLemkeStepping) {
    // Every law must be lcp_contact: LcpHbm checks it, naming the law.
    if (stepping.points < 2) throw InputError("continuation.points: must be at least 2");
  }
  validation.Validate();
  stability.Validate();
  const ProblemDimensions dimensions = DimensionsOf(*this);
  if (stability.hill_modes > 0 && !laws.empty()) {
    const int interior = n - static_cast<int>(dimensions.num_retained);  // the laws' DOFs kept
    if (stability.hill_modes > interior) {
      throw InputError("stability.hill_modes: " + std::to_string(stability.hill_modes) +
                       " fixed-interface modes asked, the model has " + std::to_string(interior) +
                       " DOFs besides the laws'");
    }
  }
  CheckProblemSize(dimensions);
}

std::unique_ptr<HarmonicSystem> BuildSystem(const Case& the_case) {
  std::vector<std::unique_ptr<Nonlinearity>> laws;
  for (size_t i = 0; i < the_case.laws.size(); ++i) {
    try {
      laws.push_back(MakeHarmonicLaw(the_case.laws[i], the_case.model.model));
    } catch (const std::invalid_argument& error) {
      throw InputError("nonlinearities[" + std::to_string(i) + "]." + error.what());
    }
  }
  return std::make_unique<HarmonicSystem>(the_case.model, the_case.harmonics, std::move(laws),
                                          the_case.output_dofs);
}

}  // namespace nfrc
