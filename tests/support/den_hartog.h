#pragma once

// Den Hartog's closed form of the steady continuous sliding of the forced Coulomb oscillator
//   ẍ + cẋ + kx = f cos(ωt + φ) − limit·sign(ẋ)   (unit mass),
// an independent reference for the harmonic balance and the transient integrators.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace nfrc {
namespace testing {

struct HalfPeriod {
  using Complex = std::complex<double>;
  double omega, c, k, f, limit;  // ẍ + cẋ + kx = f cos(ωt + φ) − limit (ẋ > 0)
  double x0, phi;                // x(0) = −x0, ẋ(0) = 0
  Complex particular;            // P with x_p = Re(P e^{iωt}) − limit/k
  double sigma, omega_d, a, b;   // homogeneous part e^{−σt}(a cos ω_d t + b sin ω_d t)

  HalfPeriod(double omega_, double c_, double k_, double f_, double limit_, double x0_, double phi_)
      : omega(omega_), c(c_), k(k_), f(f_), limit(limit_), x0(x0_), phi(phi_) {
    particular = f * std::polar(1.0, phi) / Complex(k - omega * omega, c * omega);
    sigma = c / 2;
    omega_d = std::sqrt(k - sigma * sigma);
    a = -x0 - (particular.real() - limit / k);
    const double v_p0 = (Complex(0, omega) * particular).real();
    b = (-v_p0 + sigma * a) / omega_d;
  }
  double X(double t) const {
    return (particular * std::polar(1.0, omega * t)).real() - limit / k +
           std::exp(-sigma * t) * (a * std::cos(omega_d * t) + b * std::sin(omega_d * t));
  }
  double V(double t) const {
    return (Complex(0, omega) * particular * std::polar(1.0, omega * t)).real() +
           std::exp(-sigma * t) * ((-sigma * a + omega_d * b) * std::cos(omega_d * t) +
                                   (-sigma * b - omega_d * a) * std::sin(omega_d * t));
  }
};

struct DenHartog {
  double amplitude = 0, phi = 0;
  bool converged = false;
  bool continuous_sliding = false;  // ẋ > 0 strictly inside the half period
  double min_interior_velocity = 0;
};

// Solves x(T/2) = X, ẋ(T/2) = 0 for (X, φ) by Newton, from the describing-function guess.
inline DenHartog SolveDenHartog(double omega, double c, double k, double f, double limit) {
  const double half = std::numbers::pi / omega;
  // Describing function: X²(k − ω²)² + (cωX + 4·limit/π)² = f².
  const double q = 4 * limit / std::numbers::pi;
  const double qa = std::pow(k - omega * omega, 2) + std::pow(c * omega, 2);
  const double qb = 2 * c * omega * q, qc = q * q - f * f;
  DenHartog out;
  if (qb * qb - 4 * qa * qc < 0) return out;  // friction too strong to slide: no guess
  double x = (-qb + std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);
  double phi = std::arg(-x * std::complex<double>(k - omega * omega, c * omega + q / x));
  auto g = [&](double xx, double pp) {
    const HalfPeriod h(omega, c, k, f, limit, xx, pp);
    return Eigen::Vector2d(h.X(half) - xx, h.V(half));
  };
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector2d r = g(x, phi);
    Eigen::Matrix2d j;
    const double hx = 1e-6 * std::max(1.0, x), hp = 1e-6;
    j.col(0) = (g(x + hx, phi) - g(x - hx, phi)) / (2 * hx);
    j.col(1) = (g(x, phi + hp) - g(x, phi - hp)) / (2 * hp);
    const Eigen::Vector2d d = j.partialPivLu().solve(-r);
    x += d(0);
    phi += d(1);
    if (d.norm() < 1e-14 * (1 + x)) {
      out.converged = g(x, phi).norm() < 1e-11 * (1 + x);
      break;
    }
  }
  out.amplitude = x;
  out.phi = phi;
  const HalfPeriod h(omega, c, k, f, limit, x, phi);
  constexpr int kGrid = 4000;
  out.min_interior_velocity = INFINITY;
  for (int i = 1; i < kGrid; ++i) {
    out.min_interior_velocity = std::min(out.min_interior_velocity, h.V(half * i / kGrid));
  }
  // Leaving the reversal at once needs ẍ(0) = f cos φ − limit + kX > 0.
  const double accel0 = f * std::cos(phi) - limit + k * x;
  out.continuous_sliding = out.min_interior_velocity > 0 && accel0 > 0;
  return out;
}

}  // namespace testing
}  // namespace nfrc
