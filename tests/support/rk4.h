#pragma once

namespace nfrc::testing {

// One classical RK4 step of length h for ẍ = accel(t, x, ẋ): the fixed-step reference the
// time-law tests integrate against (global error ~ (ωh)⁴).
template <typename Accel>
void Rk4Step(const Accel& accel, double t, double h, double* x, double* v) {
  const double k1x = *v, k1v = accel(t, *x, *v);
  const double k2x = *v + 0.5 * h * k1v, k2v = accel(t + 0.5 * h, *x + 0.5 * h * k1x, k2x);
  const double k3x = *v + 0.5 * h * k2v, k3v = accel(t + 0.5 * h, *x + 0.5 * h * k2x, k3x);
  const double k4x = *v + h * k3v, k4v = accel(t + h, *x + h * k3x, k4x);
  *x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
  *v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

}  // namespace nfrc::testing
