#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <complex>
#include <string>
#include <vector>

#include "validation/transient.h"
#include "validation/transient_model.h"

namespace nfrc {

// Options of the transient monodromy matrix (case fields "validation.monodromy").
struct MonodromyOptions {
  // Compute it in `nfrc validate` for every HBM solution validated.
  bool enabled = true;
  // Central-difference step of state component j, relative to the orbit's scale A (m):
  // h_j = relative_step × A for a displacement, relative_step × ω × A for a velocity. Two
  // errors compete. Truncation, ~h²|P'''|/|P'|: ~1e-8 relative at 1e-4 on a smooth orbit.
  // Integration noise, the part of the integrator's error that does not vary smoothly with the
  // start, enters as δ/h: with IDA at rtol 1e-10 (atol ~1e-13 A), smooth orbits keep the same
  // steps in the ± runs and δ is tiny (Φ changes ≤ 1e-7 from 1e-5 to 1e-7 on a Duffing orbit);
  // at events (stick, slip reversal, contact) the event times and re-initialisations carry
  // ~rtol, and Φ then moves by ~1e-3 at 1e-6, ~5e-5 at 1e-4 (friction stick-slip orbit,
  // tests/validation/monodromy_test.cc). 1e-4 keeps both below ~1e-5 of Φ for either kind; a
  // ± pair that changes the event sequence itself (grazing) is not covered by any step.
  double relative_step = 1e-4;
  // A (m); 0: max over the DOFs with mass of max(|x_i(0)|, |v_i(0)|/ω), which for a
  // near-harmonic orbit x_i = X_i cos(ωt + φ_i) is ≥ max_i X_i / √2 (|x|² + |v/ω|² = X²).
  // Set it for an orbit that is (nearly) at rest.
  double scale = 0.0;

  // Throws InputError("validation.monodromy.<field>: ...") for a bad value.
  void Validate() const;
};

// The monodromy matrix Φ = ∂P/∂z0 of the period map P (one period T = 2π/ω from t = 0, where
// the excitation's phase is 0) at a state z0 on (or near) a T-periodic orbit, and its Floquet
// multipliers.
struct MonodromyResult {
  bool ok = false;
  std::string message;  // why not ok; else empty
  // The state: z = (x_d, v_d, o) for the DOFs d in state_dofs, x first (m, then m/s), then
  // the laws' free own unknowns o (state_own; a sticking Jenkins force, N).
  Eigen::MatrixXd matrix;
  // Eigenvalues of `matrix`, sorted by decreasing modulus.
  std::vector<std::complex<double>> multipliers;
  std::vector<int> state_dofs;  // DOFs with mass (a non-zero row of M), increasing
  std::vector<int> state_own;   // indices into InitialState::own of the free own unknowns
  double scale = 0.0;           // A used for the steps (m)
  // |P(z0) − z0|∞ / A with z = (x, v/ω): how far z0 is from a T-periodic orbit.
  double closure = 0.0;
  int integrations = 0;  // one-period integrations run (2·dim + 1 when ok)
  double wall_seconds = 0.0;

  double max_modulus() const { return multipliers.empty() ? 0.0 : std::abs(multipliers[0]); }
};

// Φ by central differences of the period map: column j is (P(z0 + h_j e_j) − P(z0 − h_j e_j))
// / (2 h_j). Only the DOFs with mass are state: a massless DOF's velocity is algebraic (its
// momentum row has no inertia) and its displacement, held at its on_orbit value in every run,
// is left to the integrator's consistent initialisation, so a massless but damped DOF's
// first-order memory is not part of Φ. The laws' own unknowns are re-initialised from (x, v)
// by each run (friction forces), except the differential ones given in on_orbit.own: those
// that are free there (TimeLaw::OwnStateScale > 0, a sticking Jenkins force) are state
// components, stepped by relative_step × their scale; the others are held. `integrator` is the
// model's (MakeTransientIntegrator); on_orbit.x and .v hold every DOF. A set `stop` (polled before
// each integration) ends it with ok = false. Throws InputError for bad options or ω.
MonodromyResult ComputeMonodromy(TransientIntegrator& integrator, const TransientModel& model,
                                 double omega, const InitialState& on_orbit,
                                 const MonodromyOptions& options = {},
                                 const std::atomic<bool>* stop = nullptr);

}  // namespace nfrc
