#include "core/fourier_transform.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace nfrc {
namespace {

// Transforms sum at most a few dozen O(1) terms; FFT and dense sums agree to ~3e-14
// (measured), far below this bound, while any index or sign error is O(1).
constexpr double kTol = 1e-12;

struct Case {
  int max_harmonic;
  bool odd_only;
  int num_samples;
};

// Every set shape: full/odd, several H, odd and even N_t, powers of two and not.
std::vector<Case> Cases() {
  std::vector<Case> cases;
  for (bool odd : {false, true}) {
    for (int h : {1, 3, 7, 10}) {
      for (int n : {2 * h + 1, 2 * h + 2, 4 * h + 3, HarmonicSet::DefaultNumSamples(h)}) {
        cases.push_back({h, odd, n});
      }
    }
  }
  return cases;
}

double Theta(int j, int n) { return 2.0 * std::numbers::pi * j / n; }

// Dense DFT matrices straight from the documented formulas.
Eigen::MatrixXd ReferenceSample(const HarmonicSet& set) {
  const int n = set.num_samples();
  Eigen::MatrixXd e(n, set.NumCoefficients());
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int k = set.harmonics()[p];
    for (int j = 0; j < n; ++j) {
      if (k == 0) {
        e(j, set.CosIndex(p)) = 1.0;
      } else {
        e(j, set.CosIndex(p)) = std::cos(k * Theta(j, n));
        e(j, set.SinIndex(p)) = std::sin(k * Theta(j, n));
      }
    }
  }
  return e;
}

Eigen::MatrixXd ReferenceProjection(const HarmonicSet& set) {
  const int n = set.num_samples();
  Eigen::MatrixXd p_ref(set.NumCoefficients(), n);
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int k = set.harmonics()[p];
    for (int j = 0; j < n; ++j) {
      if (k == 0) {
        p_ref(set.CosIndex(p), j) = 1.0 / n;
      } else {
        p_ref(set.CosIndex(p), j) = 2.0 / n * std::cos(k * Theta(j, n));
        p_ref(set.SinIndex(p), j) = 2.0 / n * std::sin(k * Theta(j, n));
      }
    }
  }
  return p_ref;
}

std::string Describe(const Case& c) {
  return "H=" + std::to_string(c.max_harmonic) + (c.odd_only ? " odd" : " full") +
         " N=" + std::to_string(c.num_samples);
}

TEST_CASE("FourierTransform matches dense DFT matrices") {
  for (const Case& c : Cases()) {
    INFO(Describe(c));
    const HarmonicSet set(c.max_harmonic, c.odd_only, c.num_samples);
    const FourierTransform transform(set);
    const Eigen::MatrixXd e = ReferenceSample(set);
    const Eigen::MatrixXd p = ReferenceProjection(set);
    CHECK((transform.SampleMatrix() - e).cwiseAbs().maxCoeff() < kTol);
    CHECK((transform.ProjectionMatrix() - p).cwiseAbs().maxCoeff() < kTol);

    const Eigen::MatrixXd coefficients = Eigen::MatrixXd::Random(set.NumCoefficients(), 3);
    const Eigen::MatrixXd samples = transform.ToTime(coefficients);
    REQUIRE(samples.rows() == set.num_samples());
    CHECK((samples - e * coefficients).cwiseAbs().maxCoeff() < kTol);

    const Eigen::MatrixXd signals = Eigen::MatrixXd::Random(set.num_samples(), 3);
    const Eigen::MatrixXd projected = transform.ToCoefficients(signals);
    CHECK((projected - p * signals).cwiseAbs().maxCoeff() < kTol);

    // Round trip and P·E = I (exact in exact arithmetic since N_t ≥ 2H + 1).
    CHECK((transform.ToCoefficients(samples) - coefficients).cwiseAbs().maxCoeff() < kTol);
    const Eigen::MatrixXd identity =
        Eigen::MatrixXd::Identity(set.NumCoefficients(), set.NumCoefficients());
    CHECK(
        (transform.ProjectionMatrix() * transform.SampleMatrix() - identity).cwiseAbs().maxCoeff() <
        kTol);
  }
}

TEST_CASE("FourierTransform writes into a block of a larger matrix") {
  const HarmonicSet set(4, false, 13);
  const FourierTransform transform(set);
  const Eigen::MatrixXd coefficients = Eigen::MatrixXd::Random(set.NumCoefficients(), 2);
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(20, 5);
  transform.ToTime(coefficients, big.block(3, 1, 13, 2));
  CHECK((big.block(3, 1, 13, 2) - ReferenceSample(set) * coefficients).cwiseAbs().maxCoeff() <
        kTol);
  CHECK(big.col(0).isZero(0.0));
  CHECK(big.topRows(3).isZero(0.0));
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(set.NumCoefficients() + 2, 2);
  transform.ToCoefficients(big.block(3, 1, 13, 2), out.middleRows(1, set.NumCoefficients()));
  CHECK((out.middleRows(1, set.NumCoefficients()) - coefficients).cwiseAbs().maxCoeff() < kTol);
}

TEST_CASE("FourierTransform differentiates like the analytic signal") {
  for (bool odd : {false, true}) {
    const HarmonicSet set(5, odd, 23);
    const FourierTransform transform(set);
    const int n = set.num_samples();
    // x(θ) = Σ_k (cos kθ·(k + 1) + sin kθ / (k + 2)) + 0.5, x'(θ) written out by hand.
    Eigen::VectorXd c = Eigen::VectorXd::Zero(set.NumCoefficients());
    Eigen::VectorXd x_prime(n);
    x_prime.setZero();
    for (int p = 0; p < set.num_harmonics(); ++p) {
      const int k = set.harmonics()[p];
      if (k == 0) {
        c(set.CosIndex(p)) = 0.5;
        continue;
      }
      const double a = k + 1.0;
      const double b = 1.0 / (k + 2.0);
      c(set.CosIndex(p)) = a;
      c(set.SinIndex(p)) = b;
      for (int j = 0; j < n; ++j) {
        x_prime(j) += -k * a * std::sin(k * Theta(j, n)) + k * b * std::cos(k * Theta(j, n));
      }
    }
    Eigen::VectorXd dc(set.NumCoefficients());
    transform.Differentiate(c, dc);
    // x' samples reach ~100 (k·a_k summed), so the absolute bound scales up accordingly.
    CHECK((transform.ToTime(dc) - x_prime).cwiseAbs().maxCoeff() < kTol * 100);
    CHECK((transform.DerivativeMatrix() * c - dc).cwiseAbs().maxCoeff() == 0.0);
    // m·D by column operations equals the dense product exactly (one product per entry).
    const Eigen::MatrixXd m = Eigen::MatrixXd::Random(3, set.NumCoefficients());
    CHECK((transform.TimesDerivative(m) - m * transform.DerivativeMatrix()).cwiseAbs().maxCoeff() ==
          0.0);
    // D² = −k² on each harmonic.
    Eigen::VectorXd ddc(set.NumCoefficients());
    transform.Differentiate(dc, ddc);
    for (int p = 0; p < set.num_harmonics(); ++p) {
      const int k = set.harmonics()[p];
      CHECK(ddc(set.CosIndex(p)) == doctest::Approx(-k * k * c(set.CosIndex(p))));
      CHECK(ddc(set.SinIndex(p)) == doctest::Approx(-k * k * c(set.SinIndex(p))));
    }
  }
}

TEST_CASE("FourierTransform projects products without aliasing at the default N_t") {
  SUBCASE("cos^3 and sin^3 on an odd set") {
    const HarmonicSet set(3, true);
    const FourierTransform transform(set);
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(set.NumCoefficients(), 2);
    c(set.CosIndex(0), 0) = 1.0;  // cos θ
    c(set.SinIndex(0), 1) = 1.0;  // sin θ
    const Eigen::MatrixXd cubes = transform.ToCoefficients(transform.ToTime(c).array().cube());
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(set.NumCoefficients(), 2);
    expected(set.CosIndex(0), 0) = 0.75;  // cos³θ = 3/4 cos θ + 1/4 cos 3θ
    expected(set.CosIndex(1), 0) = 0.25;
    expected(set.SinIndex(0), 1) = 0.75;  // sin³θ = 3/4 sin θ − 1/4 sin 3θ
    expected(set.SinIndex(1), 1) = -0.25;
    CHECK((cubes - expected).cwiseAbs().maxCoeff() < kTol);
  }
  SUBCASE("cube of a full-band signal equals the exact truncated product") {
    // x = 1 + cos θ + sin 2θ with H = 2: x³ has harmonics up to 6; the default N_t = 16 > 4H
    // keeps harmonics ≤ 2 exact. Reference: projection with many samples (no aliasing).
    const HarmonicSet set(2, false);
    const HarmonicSet fine(2, false, 64);
    Eigen::VectorXd c = Eigen::VectorXd::Zero(set.NumCoefficients());
    c(set.CosIndex(0)) = 1.0;
    c(set.CosIndex(1)) = 1.0;
    c(set.SinIndex(2)) = 1.0;
    const FourierTransform transform(set);
    const FourierTransform reference(fine);
    const Eigen::VectorXd cube = transform.ToCoefficients(transform.ToTime(c).array().cube());
    const Eigen::VectorXd exact = reference.ToCoefficients(reference.ToTime(c).array().cube());
    CHECK((cube - exact).cwiseAbs().maxCoeff() < kTol);
    // The minimal N_t = 5 aliases harmonic 6 and 3 onto the kept ones: the check can fail.
    const HarmonicSet coarse(2, false, 5);
    const FourierTransform aliased(coarse);
    const Eigen::VectorXd wrong = aliased.ToCoefficients(aliased.ToTime(c).array().cube());
    CHECK((wrong - exact).cwiseAbs().maxCoeff() > 0.1);
  }
}

TEST_CASE("FourierTransform is movable and rejects bad shapes") {
  const HarmonicSet set(3, false, 9);
  FourierTransform moved(FourierTransform{set});
  const Eigen::VectorXd c = Eigen::VectorXd::Random(set.NumCoefficients());
  CHECK((moved.ToTime(c) - ReferenceSample(set) * c).cwiseAbs().maxCoeff() < kTol);

  Eigen::MatrixXd samples(9, 1);
  const Eigen::MatrixXd too_short = Eigen::MatrixXd::Zero(set.NumCoefficients() - 1, 1);
  CHECK_THROWS_WITH_AS(moved.ToTime(too_short, samples), doctest::Contains("coefficients"),
                       std::invalid_argument);
  Eigen::MatrixXd wrong_samples(8, 1);
  CHECK_THROWS_WITH_AS(moved.ToTime(c, wrong_samples), doctest::Contains("samples"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(moved.ToCoefficients(wrong_samples), doctest::Contains("samples"),
                       std::invalid_argument);
}

}  // namespace
}  // namespace nfrc

namespace nfrc {
namespace {

TEST_CASE("WeightedProduct equals the dense P diag(w) E for full and odd sets, any N_t") {
  // Both are sums of the same N_t products; they differ by round-off only (~N_t·1e-16).
  constexpr double kTolerance = 1e-12;
  for (bool odd : {false, true}) {
    for (int samples : {0, 15, 33, 64}) {
      const HarmonicSet set(7, odd, samples);
      const FourierTransform fourier(set);
      const Eigen::VectorXd w = Eigen::VectorXd::Random(set.num_samples());
      const Eigen::MatrixXd dense =
          fourier.ProjectionMatrix() * w.asDiagonal() * fourier.SampleMatrix();
      CAPTURE(odd);
      CAPTURE(samples);
      CHECK((fourier.WeightedProduct(w) - dense).cwiseAbs().maxCoeff() < kTolerance);
      // Into a buffer of another size, then again into the same one (its tables reused).
      Eigen::MatrixXd product = Eigen::MatrixXd::Constant(3, 5, 7.0);
      fourier.WeightedProduct(-w, &product);
      CHECK((product + dense).cwiseAbs().maxCoeff() < kTolerance);
      fourier.WeightedProduct(w, &product);
      CHECK((product - dense).cwiseAbs().maxCoeff() < kTolerance);
    }
  }
}

TEST_CASE("AddWeightedProduct adds scale P diag(w) E (and its D) in place, to the bit") {
  // Against the dense product (an independent sum) and, bit for bit, against the two-step
  // path it replaces in the friction law (WeightedProduct, then AddTimesDerivative or +=).
  constexpr double kTolerance = 1e-12;
  constexpr double kScale = -0.37;
  for (bool odd : {false, true}) {
    for (int samples : {0, 33}) {
      const HarmonicSet set(7, odd, samples);
      const FourierTransform fourier(set);
      const int nc = set.NumCoefficients();
      const Eigen::VectorXd w = Eigen::VectorXd::Random(set.num_samples());
      const Eigen::MatrixXd dense =
          fourier.ProjectionMatrix() * w.asDiagonal() * fourier.SampleMatrix();
      const Eigen::MatrixXd start = Eigen::MatrixXd::Random(nc + 2, nc + 3);
      CAPTURE(odd);
      CAPTURE(samples);
      for (bool derivative : {false, true}) {
        CAPTURE(derivative);
        Eigen::MatrixXd fused = start;
        fourier.AddWeightedProduct(w, kScale, derivative, fused.block(1, 2, nc, nc));
        Eigen::MatrixXd two_step = start;
        const Eigen::MatrixXd product = fourier.WeightedProduct(w);
        if (derivative) {
          fourier.AddTimesDerivative(product, kScale, two_step.block(1, 2, nc, nc));
        } else {
          two_step.block(1, 2, nc, nc) += kScale * product;
        }
        CHECK(fused == two_step);
        Eigen::MatrixXd expected = start;
        expected.block(1, 2, nc, nc) +=
            kScale * (derivative ? Eigen::MatrixXd(dense * fourier.DerivativeMatrix()) : dense);
        CHECK((fused - expected).cwiseAbs().maxCoeff() < kTolerance);
      }
    }
  }
}

TEST_CASE("AddTimesDerivative adds scale m D in place, rounded as the product added") {
  for (bool odd : {false, true}) {
    const HarmonicSet set(6, odd);
    const FourierTransform fourier(set);
    const int nc = set.NumCoefficients();
    const Eigen::MatrixXd m = Eigen::MatrixXd::Random(nc, nc);
    const Eigen::MatrixXd start = Eigen::MatrixXd::Random(nc + 3, nc + 2);
    constexpr double kScale = -0.731;
    // Into a block of a larger matrix, as a law's Jacobian block is assembled.
    Eigen::MatrixXd target = start;
    fourier.AddTimesDerivative(m, kScale, target.block(2, 1, nc, nc));
    Eigen::MatrixXd expected = start;
    expected.block(2, 1, nc, nc) += kScale * (m * fourier.DerivativeMatrix());
    CAPTURE(odd);
    // m·D has one product per entry, so the two agree exactly, and outside the block too.
    CHECK((target - expected).cwiseAbs().maxCoeff() == 0.0);
    CHECK_THROWS_AS(fourier.AddTimesDerivative(m, 1.0, target.block(0, 0, nc, nc + 1)),
                    std::invalid_argument);
  }
}

}  // namespace
}  // namespace nfrc
