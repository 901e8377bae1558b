#include "validation/linear_response.h"

#include <doctest/doctest.h>

#include <complex>

namespace nfrc {
namespace {

TEST_CASE("Linear response: amplitude sums the harmonics' responses") {
  // m ẍ + c ẋ + k x = cos ωt + 0.5 sin 3ωt: |X_h| = |F_h| / |k − (hω)²m + ihωc|.
  LinearModel model;
  model.mass = Eigen::MatrixXd::Constant(1, 1, 2.0).sparseView();       // kg
  model.damping = Eigen::MatrixXd::Constant(1, 1, 0.1).sparseView();    // N·s/m
  model.stiffness = Eigen::MatrixXd::Constant(1, 1, 3.0).sparseView();  // N/m
  const std::vector<ForcingTerm> terms = {ForcingTerm{0, 1, 1.0, 0.0}, ForcingTerm{0, 3, 0.0, 0.5}};
  const double omega = 0.7;
  auto response = [&](int h, double force) {
    const double w = h * omega;
    return force / std::abs(std::complex<double>(3.0 - 2.0 * w * w, 0.1 * w));
  };
  CHECK(LinearAmplitude(model, terms, omega) ==
        doctest::Approx(response(1, 1.0) + response(3, 0.5)).epsilon(1e-14));
  CHECK(LinearAmplitude(model, {}, omega) == 0.0);
}

}  // namespace
}  // namespace nfrc
