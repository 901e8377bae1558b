#include "nonlinearities/return_mapping.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace nfrc {
namespace {

constexpr double kPi = std::numbers::pi;

// A random band-limited input of the set, amplitude ~`size`, with a decaying spectrum.
Eigen::VectorXd RandomInput(const HarmonicSet& set, std::mt19937& rng, double size) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd c(set.NumCoefficients());
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const double k = std::max(1, set.harmonics()[static_cast<size_t>(p)]);
    c(set.CosIndex(p)) = size * normal(rng) / (k * k);
    if (set.harmonics()[static_cast<size_t>(p)] > 0)
      c(set.SinIndex(p)) = size * normal(rng) / (k * k);
  }
  return c;
}

// The sampled return mapping on N_t samples, projected: its N_t → ∞ limit is the resolved law.
Eigen::VectorXd SampledCoefficients(const HarmonicSet& set, int samples, const Eigen::VectorXd& c,
                                    double k, double limit) {
  const FourierTransform fine(HarmonicSet(set.max_harmonic(), set.odd_only(), samples));
  return fine.ToCoefficients(ReturnMapping(fine.ToTime(c).col(0), k, limit).force);
}

// The sampled law converges to the resolved one as N_t grows: O(1/N_t) (the quadrature of f's
// kinks and the switches' positions within a sample interval), here checked at two N_t a
// factor 16 apart.
TEST_CASE("resolved return mapping: the limit of the sampled law as N_t grows") {
  std::mt19937 rng(20261126);
  for (bool odd_only : {true, false}) {
    CAPTURE(odd_only);
    const HarmonicSet set(9, odd_only, 64);
    const FourierTransform fourier(set);
    for (double k : {1.0, 1e2, 1e4}) {
      CAPTURE(k);
      for (int trial = 0; trial < 4; ++trial) {
        const Eigen::VectorXd c = RandomInput(set, rng, 1.0);
        const double limit = 0.15 * k;  // play ±0.15 against an amplitude ~1: slip
        const ResolvedSlip resolved = ResolveReturnMapping(fourier, c, k, limit);
        const double scale = resolved.force.cwiseAbs().maxCoeff();
        const double coarse = (SampledCoefficients(set, 1 << 12, c, k, limit) - resolved.force)
                                  .cwiseAbs()
                                  .maxCoeff() /
                              scale;
        const double fine = (SampledCoefficients(set, 1 << 16, c, k, limit) - resolved.force)
                                .cwiseAbs()
                                .maxCoeff() /
                            scale;
        CAPTURE(coarse);
        CAPTURE(fine);
        CHECK(fine < 2e-3);
        CHECK(fine < 0.25 * coarse + 1e-9);  // converging, at least as 1/N_t
      }
    }
  }
}

// For u = U cos θ with U > μN/k_t the force traces Masing's loop, whose area (the energy
// dissipated per cycle) is 4F_s(U − F_s/k). The harmonic force gives it as ∮ f du = −πU·b_1.
// The resolved law integrates it exactly (the sampled one to O(1/N_t²)).
TEST_CASE("resolved return mapping: energy per cycle is the area of Masing's loop, exactly") {
  const HarmonicSet set(5, true, 32);
  const FourierTransform fourier(set);
  const double k = 4.0, limit = 3.0;
  for (double amplitude : {1.0, 2.5, 10.0}) {
    CAPTURE(amplitude);
    for (double phase : {0.0, 0.3, 2.0}) {
      CAPTURE(phase);
      Eigen::VectorXd c = Eigen::VectorXd::Zero(set.NumCoefficients());
      c(set.CosIndex(0)) = amplitude * std::cos(phase);
      c(set.SinIndex(0)) = amplitude * std::sin(phase);
      const ResolvedSlip slip = ResolveReturnMapping(fourier, c, k, limit);
      // ∮ f du over the period = π(a_1 of f · (−b_1 of u)... ): with u = U cos(θ − φ),
      // ∮ f du = −πU(b_1 cos φ − a_1 sin φ) for f's coefficients a_1, b_1.
      const double a1 = slip.force(set.CosIndex(0)), b1 = slip.force(set.SinIndex(0));
      const double dissipated = -kPi * amplitude * (b1 * std::cos(phase) - a1 * std::sin(phase));
      const double loop = 4.0 * limit * (amplitude - limit / k);
      CHECK(dissipated == doctest::Approx(loop).epsilon(1e-12));
      CHECK(slip.switches == 4);
    }
  }
}

// Below the slip limit: f = k(u − w), the slider where the passes from w = 0 leave it.
TEST_CASE("resolved return mapping: without slip, the spring k on u − clamp(0, ...)") {
  const HarmonicSet set(4, false, 32);
  const FourierTransform fourier(set);
  const double k = 5.0, limit = 10.0;  // play ±2
  Eigen::VectorXd c = Eigen::VectorXd::Zero(set.NumCoefficients());
  c(set.CosIndex(1)) = 0.5;  // u = a_0 + 0.5 cos θ: max − min = 1 < 2·play
  for (double a0 : {0.0, 1.0, 3.0, -3.0}) {
    CAPTURE(a0);
    c(set.CosIndex(0)) = a0;
    const ResolvedSlip slip = ResolveReturnMapping(fourier, c, k, limit);
    const double w = std::clamp(0.0, a0 + 0.5 - 2.0, a0 - 0.5 + 2.0);
    Eigen::VectorXd expected = k * c;
    expected(set.CosIndex(0)) -= k * w;
    CHECK((slip.force - expected).cwiseAbs().maxCoeff() < 1e-12);
    CHECK(slip.switches == 0);
  }
}

// ∂f̃/∂ũ against central differences: the resolved law is C¹ in ũ wherever no stick or slip
// phase is born or dies, so the differences agree to O(δ²) and rounding, also at k = 1e4
// (where the sampled law's Jacobian jumps by 2k/N_t at every sample switch).
TEST_CASE("resolved return mapping: Jacobian matches central differences") {
  std::mt19937 rng(7);
  for (bool odd_only : {true, false}) {
    CAPTURE(odd_only);
    const HarmonicSet set(7, odd_only, 64);
    const FourierTransform fourier(set);
    const int nc = set.NumCoefficients();
    for (double k : {3.0, 1e4}) {
      CAPTURE(k);
      for (int trial = 0; trial < 5; ++trial) {
        const Eigen::VectorXd c = RandomInput(set, rng, 1.0);
        const double limit = 0.2 * k;  // play 0.2 against an amplitude ~1: slip
        const ResolvedSlip slip = ResolveReturnMapping(fourier, c, k, limit);
        Eigen::MatrixXd differences(nc, nc);
        const double delta = 1e-6;
        for (int i = 0; i < nc; ++i) {
          Eigen::VectorXd plus = c, minus = c;
          plus(i) += delta;
          minus(i) -= delta;
          differences.col(i) = (ResolveReturnMapping(fourier, plus, k, limit).force -
                                ResolveReturnMapping(fourier, minus, k, limit).force) /
                               (2.0 * delta);
        }
        const double error = (differences - slip.jacobian).cwiseAbs().maxCoeff() /
                             slip.jacobian.cwiseAbs().maxCoeff();
        CAPTURE(error);
        CHECK(slip.switches >= 2);
        CHECK(error < 1e-6);
      }
    }
  }
}

// The force is continuous where a pair of turning points is born between two samples (u' dips
// to zero inside a sample interval): a short stick phase grows from zero length instead of
// appearing with the length of a sample interval.
TEST_CASE("resolved return mapping: continuous where a stick phase is born between samples") {
  const HarmonicSet set(5, false, 16);  // coarse: the birth lies well inside an interval
  const FourierTransform fourier(set);
  const double k = 1e3, limit = 1.0;
  // u = sin(θ − s) + a sin 3(θ − s): u' = cos(θ − s) + 3a cos 3(θ − s) has a double root at
  // θ = s for a = −1/3 (u' ≈ 4(θ − s)² there) and two roots near s below. s = π/16 puts the
  // birth half-way between two of the 16 samples.
  const double s = kPi / 16.0;
  auto force = [&](double a) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(set.NumCoefficients());
    c(set.CosIndex(1)) = -std::sin(s);
    c(set.SinIndex(1)) = std::cos(s);
    c(set.CosIndex(3)) = -a * std::sin(3.0 * s);
    c(set.SinIndex(3)) = a * std::cos(3.0 * s);
    return ResolveReturnMapping(fourier, c, k, limit);
  };
  const double birth = -1.0 / 3.0;
  double largest_jump = 0.0;
  const double da = 1e-6;
  for (double a = birth + 50 * da; a > birth - 50 * da; a -= da) {
    largest_jump = std::max(largest_jump, (force(a - da).force - force(a).force).norm());
  }
  MESSAGE("largest change of f over a step of " << da
                                                << " in a across the birth: " << largest_jump);
  CHECK(force(birth - 50 * da).switches > force(birth + 50 * da).switches);
  CHECK(largest_jump < 1e-3);
}

}  // namespace
}  // namespace nfrc
