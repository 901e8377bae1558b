#include "core/dynamic_stiffness.h"

namespace nfrc {

SparseComplex DynamicStiffness(const LinearModel& model, int harmonic, double omega) {
  using Complex = std::complex<double>;
  const double frequency = harmonic * omega;  // kω, rad per unit time
  SparseComplex z = model.stiffness.cast<Complex>() -
                    Complex(frequency * frequency, 0.0) * model.mass.cast<Complex>() +
                    Complex(0.0, frequency) * model.damping.cast<Complex>();
  return z;
}

SparseComplex DynamicStiffnessDerivative(const LinearModel& model, int harmonic, double omega) {
  using Complex = std::complex<double>;
  const double k = harmonic;
  SparseComplex dz = Complex(-2.0 * k * k * omega, 0.0) * model.mass.cast<Complex>() +
                     Complex(0.0, k) * model.damping.cast<Complex>();
  return dz;
}

}  // namespace nfrc
