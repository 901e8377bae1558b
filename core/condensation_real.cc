// The real, DOF-major layout of Condensation's per-harmonic complex operator and forcing:
// the form the harmonic-balance residual uses (coefficients a_k, b_k of each retained DOF).
#include <cassert>
#include <stdexcept>

#include "core/condensation.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;

// Writes the rows of retained DOF i at row offset `first_row` of `out`: each complex entry
// z of harmonic k becomes [[Re, Im], [−Im, Re]] on (a_k, b_k), only Re for k = 0.
template <typename Blocks, typename Out>
void PutRows(const HarmonicSet& set, int i, int num_retained, const Blocks& block, int first_row,
             Out* out) {
  const int n_c = set.NumCoefficients();
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int ic = set.CosIndex(p);
    const int is = set.SinIndex(p);
    const Eigen::MatrixXcd& z_p = block(p);
    for (int j = 0; j < num_retained; ++j) {
      const Complex z = z_p(i, j);
      (*out)(first_row + ic, j * n_c + ic) = z.real();
      if (set.harmonics()[p] == 0) continue;
      (*out)(first_row + ic, j * n_c + is) = z.imag();
      (*out)(first_row + is, j * n_c + ic) = -z.imag();
      (*out)(first_row + is, j * n_c + is) = z.real();
    }
  }
}

// The forcing's entries of DOF i, (a, b) = (Re F, −Im F) per harmonic, at `first_row`.
template <typename Vectors>
void PutEntries(const HarmonicSet& set, int i, const Vectors& vector, int first_row,
                Eigen::VectorXd* out) {
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const Complex f = vector(p)(i);
    (*out)(first_row + set.CosIndex(p)) = f.real();
    if (set.harmonics()[p] != 0) (*out)(first_row + set.SinIndex(p)) = -f.imag();
  }
}

// Every retained DOF's entries: the whole forcing in the real layout.
template <typename Vectors>
Eigen::VectorXd WholeVector(const HarmonicSet& set, int num_retained, const Vectors& vector) {
  Eigen::VectorXd real = Eigen::VectorXd::Zero(num_retained * set.NumCoefficients());
  for (int i = 0; i < num_retained; ++i) {
    PutEntries(set, i, vector, i * set.NumCoefficients(), &real);
  }
  return real;
}

void CheckRetained(int i, int num_retained) {
  if (i < 0 || i >= num_retained) throw std::invalid_argument("i: not a retained DOF index");
}

}  // namespace

Eigen::MatrixXd Condensation::RealOperator() const {
  Eigen::MatrixXd real = Eigen::MatrixXd::Zero(num_unknowns(), num_unknowns());
  WriteRealOperator(false, real);
  return real;
}

Eigen::MatrixXd Condensation::RealOperatorDerivative() const {
  Eigen::MatrixXd real = Eigen::MatrixXd::Zero(num_unknowns(), num_unknowns());
  WriteRealOperator(true, real);
  return real;
}

void Condensation::WriteRealOperator(bool derivative, Eigen::Ref<Eigen::MatrixXd> out) const {
  if (out.rows() != num_unknowns() || out.cols() != num_unknowns()) {
    throw std::invalid_argument("out: must be num_unknowns() square");
  }
  const auto block = [this, derivative](int p) -> const Eigen::MatrixXcd& {
    return derivative ? dZ(p) : Z(p);
  };
  for (int i = 0; i < num_retained(); ++i) {
    PutRows(set_, i, num_retained(), block, i * set_.NumCoefficients(), &out);
  }
}

void Condensation::ApplyRealOperator(bool derivative, const Eigen::Ref<const Eigen::VectorXd>& x,
                                     Eigen::Ref<Eigen::VectorXd> out) const {
  if (x.size() != num_unknowns() || out.size() != num_unknowns()) {
    throw std::invalid_argument("x, out: must have num_unknowns() entries");
  }
  const int n_c = set_.NumCoefficients();
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    const Eigen::MatrixXcd& z_p = derivative ? dZ(p) : Z(p);
    const int ic = set_.CosIndex(p);
    const int is = set_.SinIndex(p);
    assert(is == ic || is == ic + 1);
    const bool constant = set_.harmonics()[static_cast<size_t>(p)] == 0;
    for (int i = 0; i < num_retained(); ++i) {
      double cos_row = 0.0, sin_row = 0.0;
      for (int j = 0; j < num_retained(); ++j) {
        // PutRows's entries: row cos (Re, Im) and row sin (−Im, Re) on columns (cos, sin),
        // which are adjacent and in that order (is = ic + 1).
        const Complex z = z_p(i, j);
        const double a = x(static_cast<Eigen::Index>(j) * n_c + ic);
        cos_row += z.real() * a;
        if (constant) continue;
        const double b = x(static_cast<Eigen::Index>(j) * n_c + is);
        cos_row += z.imag() * b;
        sin_row += -z.imag() * a;
        sin_row += z.real() * b;
      }
      out(static_cast<Eigen::Index>(i) * n_c + ic) = cos_row;
      if (!constant) out(static_cast<Eigen::Index>(i) * n_c + is) = sin_row;
    }
  }
}

Eigen::VectorXd Condensation::RealForcing() const {
  return WholeVector(set_, num_retained(),
                     [this](int p) -> const Eigen::VectorXcd& { return F(p); });
}

Eigen::VectorXd Condensation::RealForcingDerivative() const {
  return WholeVector(set_, num_retained(),
                     [this](int p) -> const Eigen::VectorXcd& { return dF(p); });
}

Eigen::MatrixXd Condensation::RealOperatorRows(int i, bool derivative) const {
  CheckRetained(i, num_retained());
  Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(set_.NumCoefficients(), num_unknowns());
  const auto block = [this, derivative](int p) -> const Eigen::MatrixXcd& {
    return derivative ? dZ(p) : Z(p);
  };
  PutRows(set_, i, num_retained(), block, 0, &rows);
  return rows;
}

Eigen::VectorXd Condensation::RealForcingRows(int i, bool derivative) const {
  CheckRetained(i, num_retained());
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(set_.NumCoefficients());
  const auto vector = [this, derivative](int p) -> const Eigen::VectorXcd& {
    return derivative ? dF(p) : F(p);
  };
  PutEntries(set_, i, vector, 0, &rows);
  return rows;
}

}  // namespace nfrc
