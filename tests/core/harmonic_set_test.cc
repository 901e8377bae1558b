#include "core/harmonic_set.h"

#include <doctest/doctest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace nfrc {
namespace {

// Runs `f`, expecting std::invalid_argument whose message contains `field`.
template <typename F>
void CheckInvalid(F f, const std::string& field) {
  try {
    f();
    FAIL("expected std::invalid_argument naming " << field);
  } catch (const std::invalid_argument& e) {
    CHECK_MESSAGE(std::string(e.what()).find(field) != std::string::npos, e.what());
  }
}

// The rotation that gives the basis accumulates ~k·eps of rounding per harmonic: 1e-12 covers
// k = 199 with margin.
constexpr double kBasisTolerance = 1e-12;

TEST_CASE("HarmonicSet basis at theta is 1, cos k theta, sin k theta in the layout") {
  for (const HarmonicSet& set : {HarmonicSet(199, false), HarmonicSet(59, true)}) {
    for (const double theta : {0.0, 0.37, 2.9, -4.1, 11.5}) {
      const Eigen::VectorXd basis = set.Basis(theta);
      REQUIRE(basis.size() == set.NumCoefficients());
      for (int p = 0; p < set.num_harmonics(); ++p) {
        const int k = set.harmonics()[static_cast<size_t>(p)];
        CAPTURE(k);
        CAPTURE(theta);
        CHECK(std::abs(basis(set.CosIndex(p)) - std::cos(k * theta)) < kBasisTolerance);
        if (k > 0) CHECK(std::abs(basis(set.SinIndex(p)) - std::sin(k * theta)) < kBasisTolerance);
      }
    }
  }
}

TEST_CASE("HarmonicSet full set layout") {
  const HarmonicSet set(3, false, 16);
  CHECK(set.harmonics() == std::vector<int>{0, 1, 2, 3});
  CHECK(set.num_harmonics() == 4);
  CHECK(set.has_constant());
  CHECK_FALSE(set.odd_only());
  CHECK(set.max_harmonic() == 3);
  CHECK(set.num_samples() == 16);
  CHECK(set.NumCoefficients() == 7);
  // [a0, a1, b1, a2, b2, a3, b3]
  CHECK(set.CosIndex(0) == 0);
  CHECK(set.SinIndex(0) == 0);
  CHECK(set.CosIndex(1) == 1);
  CHECK(set.SinIndex(1) == 2);
  CHECK(set.CosIndex(2) == 3);
  CHECK(set.SinIndex(2) == 4);
  CHECK(set.CosIndex(3) == 5);
  CHECK(set.SinIndex(3) == 6);
}

TEST_CASE("HarmonicSet odd set layout") {
  const HarmonicSet set(5, true, 11);
  CHECK(set.harmonics() == std::vector<int>{1, 3, 5});
  CHECK_FALSE(set.has_constant());
  CHECK(set.NumCoefficients() == 6);
  // [a1, b1, a3, b3, a5, b5]
  CHECK(set.CosIndex(0) == 0);
  CHECK(set.SinIndex(0) == 1);
  CHECK(set.CosIndex(1) == 2);
  CHECK(set.SinIndex(1) == 3);
  CHECK(set.CosIndex(2) == 4);
  CHECK(set.SinIndex(2) == 5);
  // An even maximum stops at the odd harmonic below it.
  CHECK(HarmonicSet(4, true).harmonics() == std::vector<int>{1, 3});
  CHECK(HarmonicSet(1, true).harmonics() == std::vector<int>{1});
}

TEST_CASE("HarmonicSet indices cover every coefficient exactly once") {
  for (bool odd : {false, true}) {
    for (int h : {1, 2, 5, 8}) {
      const HarmonicSet set(h, odd);
      std::set<int> seen;
      for (int p = 0; p < set.num_harmonics(); ++p) {
        seen.insert(set.CosIndex(p));
        seen.insert(set.SinIndex(p));
      }
      CHECK(static_cast<int>(seen.size()) == set.NumCoefficients());
      CHECK(*seen.begin() == 0);
      CHECK(*seen.rbegin() == set.NumCoefficients() - 1);
    }
  }
}

TEST_CASE("HarmonicSet default number of samples") {
  // Smallest power of two >= max(4H + 1, 16).
  CHECK(HarmonicSet::DefaultNumSamples(1) == 16);
  CHECK(HarmonicSet::DefaultNumSamples(3) == 16);
  CHECK(HarmonicSet::DefaultNumSamples(4) == 32);
  CHECK(HarmonicSet::DefaultNumSamples(7) == 32);
  CHECK(HarmonicSet::DefaultNumSamples(8) == 64);
  CHECK(HarmonicSet::DefaultNumSamples(20) == 128);
  CHECK(HarmonicSet(20, false).num_samples() == 128);
  CHECK(HarmonicSet(20, true, 0).num_samples() == 128);
  // An explicit count is kept, odd or not a power of two.
  CHECK(HarmonicSet(7, false, 15).num_samples() == 15);
  CHECK(HarmonicSet(7, true, 30).num_samples() == 30);
}

TEST_CASE("HarmonicSet validation names the field") {
  CheckInvalid([] { HarmonicSet(0, false); }, "max_harmonic");
  CheckInvalid([] { HarmonicSet(-2, true); }, "max_harmonic");
  CheckInvalid([] { HarmonicSet::DefaultNumSamples(0); }, "max_harmonic");
  CheckInvalid([] { HarmonicSet(7, false, 10); }, "num_samples");
  CheckInvalid([] { HarmonicSet(7, false, 14); }, "num_samples");
  CheckInvalid([] { HarmonicSet(2, true, -1); }, "num_samples");
  // The message states the bound and the value.
  try {
    HarmonicSet(7, false, 10);
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("15") != std::string::npos);
    CHECK(std::string(e.what()).find("10") != std::string::npos);
  }
  const HarmonicSet set(3, false);
  CheckInvalid([&] { (void)set.CosIndex(4); }, "position");
  CheckInvalid([&] { (void)set.SinIndex(-1); }, "position");
}

}  // namespace
}  // namespace nfrc

namespace nfrc {
namespace {

TEST_CASE("ChangeHarmonicSet copies shared harmonics of every block and zero-fills the rest") {
  const HarmonicSet coarse(3, true);  // harmonics 1, 3
  const HarmonicSet fine(7, true);    // harmonics 1, 3, 5, 7
  Eigen::VectorXd two_signals(8);
  two_signals << 1, 2, 3, 4, 5, 6, 7, 8;  // (a1 b1 a3 b3) for two signals
  const Eigen::VectorXd up = ChangeHarmonicSet(two_signals, coarse, fine);
  REQUIRE(up.size() == 16);
  Eigen::VectorXd expected(16);
  expected << 1, 2, 3, 4, 0, 0, 0, 0, 5, 6, 7, 8, 0, 0, 0, 0;
  CHECK(up == expected);
  // And back down: truncation recovers the original.
  CHECK(ChangeHarmonicSet(up, fine, coarse) == two_signals);
  // Full set with a constant: a0 is carried, harmonics absent from the odd set are zero.
  const HarmonicSet full(2, false);  // 0, 1, 2 → a0 a1 b1 a2 b2
  Eigen::VectorXd odd(2);
  odd << 9, -9;
  Eigen::VectorXd full_expected(5);
  full_expected << 0, 9, -9, 0, 0;
  CHECK(ChangeHarmonicSet(odd, HarmonicSet(1, true), full) == full_expected);
  CHECK_THROWS_AS(ChangeHarmonicSet(Eigen::VectorXd(3), coarse, fine), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
