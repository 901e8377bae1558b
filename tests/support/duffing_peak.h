#pragma once

// The peak of the one-harmonic Duffing oscillator ẍ + cẋ + kx + k₃x³ = P cos ωt (unit mass),
// an independent reference for sweeps: on the amplitude equation
// [(k + βA² − ω²)² + (cω)²]A² = P², β = ¾k₃, the bracket is smallest at
// ω² = k + βA² − c²/2, where it is c²(k + βA²) − c⁴/4, so the largest A on the curve solves
// A² = P²/(c²(k + βA²) − c⁴/4) (a fixed point, converged long before 200 iterations).

#include <cmath>

namespace nfrc {
namespace testing {

inline double DuffingPeakAmplitude(double force, double c, double k3, double k = 1.0) {
  const double beta = 0.75 * k3;
  double amplitude = force / c;
  for (int i = 0; i < 200; ++i) {
    amplitude =
        force / std::sqrt(c * c * (k + beta * amplitude * amplitude) - 0.25 * c * c * c * c);
  }
  return amplitude;
}

}  // namespace testing
}  // namespace nfrc
