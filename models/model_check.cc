#include "models/model_check.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "core/errors.h"

namespace nfrc {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

std::string Text(double value) {
  std::ostringstream text;
  text.precision(3);
  text << value;
  return text.str();
}

// ‖A − Aᵀ‖_F / ‖A‖_F (0 for a zero matrix).
double Asymmetry(const SparseMatrix& a) {
  const double norm = a.norm();
  if (norm == 0.0) return 0.0;
  const SparseMatrix transposed = a.transpose();
  return (a - transposed).norm() / norm;
}

// The eigenvalues of the symmetric part of a, or what its inertia says of them.
struct Spectrum {
  int negative = 0;      // eigenvalues below −tolerance × the largest |eigenvalue|
  double lowest = 0.0;   // the most negative one (dense), or 0 where only counted
  double largest = 0.0;  // the largest |eigenvalue| (dense) or |pivot| (sparse)
};

// The inertia of (A + Aᵀ)/2 by dense eigenvalues up to kDenseCheckDofs, else by a sparse LDLᵀ
// of the part shifted by tolerance × its largest diagonal entry (so that a singular positive
// semidefinite part factorises); nullopt where that factorisation breaks down.
std::optional<Spectrum> SymmetricSpectrum(const SparseMatrix& a) {
  const SparseMatrix sym = 0.5 * (a + SparseMatrix(a.transpose()));
  Spectrum spectrum;
  if (a.rows() <= kDenseCheckDofs) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(Eigen::MatrixXd(sym),
                                                                Eigen::EigenvaluesOnly);
    if (solver.info() != Eigen::Success) return std::nullopt;
    const Eigen::VectorXd& values = solver.eigenvalues();
    spectrum.largest = values.cwiseAbs().maxCoeff();
    spectrum.lowest = values.minCoeff();
    for (Eigen::Index i = 0; i < values.size(); ++i) {
      spectrum.negative += values(i) < -kDefinitenessTolerance * spectrum.largest;
    }
    return spectrum;
  }
  double diagonal = 0.0;
  for (Eigen::Index i = 0; i < sym.rows(); ++i)
    diagonal = std::max(diagonal, std::abs(sym.coeff(i, i)));
  SparseMatrix shift(sym.rows(), sym.cols());
  shift.setIdentity();
  const SparseMatrix shifted = sym + kDefinitenessTolerance * diagonal * shift;
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(shifted);
  if (ldlt.info() != Eigen::Success) return std::nullopt;
  const Eigen::VectorXd d = ldlt.vectorD();
  spectrum.largest = d.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < d.size(); ++i) spectrum.negative += d(i) < 0.0;
  return spectrum;
}

std::string Eigenvalues(const Spectrum& spectrum) {
  std::string text = std::to_string(spectrum.negative) + " negative eigenvalue" +
                     (spectrum.negative == 1 ? "" : "s");
  if (spectrum.lowest < 0.0) text += " (the lowest " + Text(spectrum.lowest) + ")";
  return text;
}

// The undamped modes (symmetric parts of K and M, M positive definite) whose modal damping
// φᵀCφ is negative, as "mode j (ω = ..., ζ = ...)"; empty if none or not computable.
std::string NegativelyDampedModes(const LinearModel& model) {
  const Eigen::MatrixXd k = Eigen::MatrixXd(model.stiffness);
  const Eigen::MatrixXd m = Eigen::MatrixXd(model.mass);
  const Eigen::MatrixXd c = Eigen::MatrixXd(model.damping);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(0.5 * (k + k.transpose()),
                                                                        0.5 * (m + m.transpose()));
  if (modes.info() != Eigen::Success) return "";
  const Eigen::MatrixXd modal = modes.eigenvectors().transpose() * c * modes.eigenvectors();
  std::string list;
  int count = 0;
  for (Eigen::Index j = 0; j < modal.rows(); ++j) {
    if (!(modal(j, j) < 0.0)) continue;
    if (++count > 3) continue;  // the first few say enough
    const double omega = std::sqrt(std::max(0.0, modes.eigenvalues()(j)));
    list += (list.empty() ? "" : ", ") + std::string("mode ") + std::to_string(j + 1) + " (omega " +
            Text(omega) + ", damping ratio " +
            (omega > 0.0 ? Text(modal(j, j) / (2.0 * omega)) : std::string("-")) + ")";
  }
  if (count > 3) list += " and " + std::to_string(count - 3) + " more";
  return list;
}

// The exponents s of the linear structure alone (M s² + C s + K) x = 0 with a positive real
// part, as a warning; empty where there is none or M is singular (massless DOFs).
std::string UnstableExponents(const LinearModel& model) {
  const Eigen::Index n = model.num_dofs();
  const Eigen::MatrixXd m = Eigen::MatrixXd(model.mass);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(m);
  if (!(std::abs(lu.determinant()) > 0.0) || lu.rcond() < kDefinitenessTolerance) return "";
  Eigen::MatrixXd state = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  state.topRightCorner(n, n).setIdentity();
  state.bottomLeftCorner(n, n) = -lu.solve(Eigen::MatrixXd(model.stiffness));
  state.bottomRightCorner(n, n) = -lu.solve(Eigen::MatrixXd(model.damping));
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(state, /*computeEigenvectors=*/false);
  if (solver.info() != Eigen::Success) return "";
  const Eigen::VectorXcd exponents = solver.eigenvalues();
  const double scale = exponents.cwiseAbs().maxCoeff();
  int growing = 0;
  double fastest = 0.0;
  for (Eigen::Index i = 0; i < exponents.size(); ++i) {
    if (exponents(i).real() > kDefinitenessTolerance * scale) {
      ++growing;
      fastest = std::max(fastest, exponents(i).real());
    }
  }
  if (growing == 0) return "";
  return "model: the linear structure alone (without the laws) is unstable: " +
         std::to_string(growing) + " exponent" + (growing == 1 ? "" : "s") +
         " of M s^2 + C s + K with a positive real part (the largest growth rate " + Text(fastest) +
         " per time unit); unless the laws stabilise it, every point is unstable";
}

}  // namespace

ModelCheck CheckLinearModel(const LinearModel& model) {
  ModelCheck check;
  const double mass_asymmetry = Asymmetry(model.mass);
  if (mass_asymmetry > kDefinitenessTolerance) {
    throw InputError("model.M: not symmetric (|M - M^T| is " + Text(mass_asymmetry) +
                     " of |M|): a mass matrix is symmetric");
  }
  const std::optional<Spectrum> mass = SymmetricSpectrum(model.mass);
  if (mass && mass->negative > 0) {
    throw InputError("model.M: not positive semidefinite, " + Eigenvalues(*mass) +
                     ": a negative mass cannot be meant");
  }
  const double stiffness_asymmetry = Asymmetry(model.stiffness);
  if (stiffness_asymmetry > kDefinitenessTolerance) {
    check.warnings.push_back(
        "model.K: not symmetric (|K - K^T| is " + Text(stiffness_asymmetry) +
        " of |K|): circulatory forces, which can destabilise the structure (flutter) whatever "
        "the laws do");
  }
  if (const std::optional<Spectrum> stiffness = SymmetricSpectrum(model.stiffness);
      stiffness && stiffness->negative > 0) {
    check.warnings.push_back("model.K: indefinite, " + Eigenvalues(*stiffness) +
                             ": the structure is statically unstable without the laws (meant "
                             "for a bistable or buckled structure?)");
  }
  if (model.damping.nonZeros() > 0) {
    const std::optional<Spectrum> damping = SymmetricSpectrum(model.damping);
    if (damping && damping->negative > 0) {
      std::string warning = "model.C: its symmetric part is indefinite, " + Eigenvalues(*damping) +
                            ": negative damping feeds energy in along some motions";
      if (model.num_dofs() <= kDenseCheckDofs && mass && mass->negative == 0) {
        const std::string modes = NegativelyDampedModes(model);
        warning += modes.empty() ? " (no undamped mode has negative modal damping)"
                                 : "; negatively damped: " + modes;
      }
      check.warnings.push_back(warning + "; unstable points may be its, not the laws'");
    }
  }
  if (model.num_dofs() <= kStateCheckDofs && mass && mass->negative == 0) {
    const std::string unstable = UnstableExponents(model);
    if (!unstable.empty()) check.warnings.push_back(unstable);
  }
  return check;
}

}  // namespace nfrc
