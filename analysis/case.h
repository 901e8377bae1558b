#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/harmonic_system.h"
#include "analysis/plot_curve.h"
#include "analysis/stability.h"
#include "analysis/validation_settings.h"
#include "continuation/options.h"
#include "core/harmonic_set.h"
#include "core/linear_model.h"
#include "models/craig_bampton.h"
#include "nonlinearities/law_spec.h"

namespace nfrc {

// How a branch is computed.
enum class Method {
  kArclength,      // the pseudo-arclength engine (any law)
  kLemkeStepping,  // LCP-HBM by Lemke at evenly spaced ω (every law lcp_contact)
};
const char* ToString(Method method);  // the case file's "arclength" / "lemke_stepping"

// Natural-parameter LCP-HBM stepping (continuation.method "lemke_stepping").
struct SteppingOptions {
  int points = 201;  // evenly spaced ω from omega_start to omega_end, both included
  // Warm-start Lemke from the last contact basis where the cold solve is trivial.
  bool track_contact = true;
};

// Bounds of the start's stiffness homotopy: at most this many rungs down, and the smallest
// stiffness ratio of a rung up before it gives up (a rung that fails is square-rooted).
inline constexpr int kMaxHomotopyRungs = 30;
inline constexpr double kMinHomotopyRatio = 1.05;

// How a trace finds its first point at omega_start when Newton from the linear guess fails
// (StartingGuess; case fields continuation.start_homotopy*).
struct StartOptions {
  // A homotopy in the laws' stiffness (LawStiffness: jenkins k_t, dlft_friction ε,
  // penalty_contact k): the case with every such stiffness divided by factor, factor², …
  // (at most `rungs` times) until Newton from the linear guess converges, then solved again
  // at each stiffness up to the case's, warm-started from the secant of the last two rungs
  // (the ratio of a rung that fails is square-rooted, down to kMinHomotopyRatio). Tried
  // before the harmonic ladder, and from the ladder's re-expressed coarse solution where the
  // full set cannot correct it. A stiff stick law starts from the linear guess only when soft:
  // on the Fig. 7 oscillator Jenkins at k_t = 1e4 did not, at any rung of the ladder.
  bool homotopy = true;
  double homotopy_factor = 10.0;  // > 1
  int homotopy_rungs = 8;         // ≥ 1: the softest rung is the case's stiffness / factor^rungs
  // Throws InputError("continuation.start_homotopy_<field>: ...").
  void Validate() const;
};

// A whole problem as typed values: the model (matrices loaded), the harmonic set, the laws
// as specifications, and the options of every analysis. Copy it and change a field to get
// a related problem (fewer harmonics, another ε or normal load); systems are built from it
// as often as needed (BuildSystem). Field names in messages are the case file's.
struct Case {
  std::string title;
  std::string path;  // the file it was read from; empty when built in memory
  ModelDefinition model;
  HarmonicSet harmonics{1, false};
  std::vector<LawSpec> laws;
  Method method = Method::kArclength;
  ContinuationOptions continuation;  // lambda = ω (rad per time unit)
  SteppingOptions stepping;
  StartOptions start;                     // the first point's homotopy (arclength method)
  std::vector<int> output_dofs;           // model DOF indices whose measures are reported
  std::vector<std::string> output_names;  // how the outputs are named (index or DOF name)
  std::vector<double> signals_at;         // ω at which time signals are resolved
  // What continuation.plot_tolerance holds the chords to: max |x| of the output DOFs, or the
  // energy (continuation.plot_measure "max_abs" / "energy").
  PlotMeasure plot_measure = PlotMeasure::kMaxAbs;
  ValidationSettings validation;
  StabilityOptions stability;  // Hill's method on every traced point, bifurcations
  // Responses of period m·T (SubharmonicCase): the harmonics are of ω/m and so is the
  // continuation parameter; writers report ω = m·λ. 1 for every case read from a file.
  int period_multiple = 1;
  // Set when `model` is a Craig–Bampton reduction of the case's FE model (model.reduction):
  // then every DOF index above (laws, forcing, outputs) is the reduced model's.
  std::optional<ReductionReport> reduction;

  // Cross-field checks of a case built in memory or changed after reading; throws InputError
  // naming the case-file field ("nonlinearities[1].mu: must be non-negative").
  void Validate() const;

  // What continuation.plot_tolerance holds the chords to: plot_measure of output_dofs.
  PlotSpec Plot() const { return {plot_measure, output_dofs}; }
};

// ContinuationOptions::Validate, as InputError naming the case file's field
// ("continuation.step: ..." for the engine's initial_step).
void ValidateContinuation(const ContinuationOptions& options);

// sqrt(max |K_ii| / max |M_ii|) (rad per time unit): the order of the highest frequency the
// model resolves (0 without stiffness or mass).
double FrequencyScale(const LinearModel& model);

// The sizes that decide what a problem costs, known before anything large is allocated
// (a reader fills them from the raw numbers of a file).
struct ProblemDimensions {
  double num_dofs = 1;      // model DOFs
  double num_retained = 1;  // DOFs the laws act on (kept by the condensation)
  double max_harmonic = 1;  // H
  bool odd_only = false;
  double samples = 0;        // N_t (0: the default for H)
  double own_blocks = 0;     // laws whose own unknowns are one signal (friction)
  double sample_blocks = 0;  // laws whose own unknowns are N_t samples (LCP)
  double points = 0;         // points computed for sure (Lemke stepping), 0 otherwise
  double signals = 0;        // output.signals_at entries
};

// Peak memory (bytes) and work (flop per Newton step) a problem of these sizes needs.
struct ProblemSize {
  double bytes = 0.0;
  double work_per_step = 0.0;
  double total_work = 0.0;  // for the points computed for sure
};
ProblemSize EstimateSize(const ProblemDimensions& dimensions);

// Throws InputError naming the case field that makes a problem too large for the machine
// class nfrc runs on (24 GiB, 2 cores), with the estimate.
void CheckProblemSize(const ProblemDimensions& dimensions);
ProblemDimensions DimensionsOf(const Case& the_case);

// The harmonic-balance system of a case (laws built from their specifications).
std::unique_ptr<HarmonicSystem> BuildSystem(const Case& the_case);

}  // namespace nfrc
