#include "models/craig_bampton.h"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

namespace nfrc {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Cholesky = Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower>;

// Pencils up to this size are solved densely (Eigen's generalized solver, O(n³)): below it a
// dense solve takes milliseconds, and Lanczos cannot return all n eigenpairs (nev < n).
constexpr int kDenseEigenLimit = 400;
// Lanczos convergence tolerance on the Ritz values (relative), and its iteration cap.
constexpr double kLanczosTolerance = 1e-10;
constexpr int kLanczosMaxIterations = 1000;
// First batch of fixed-interface modes when their number comes from a frequency band; the
// batch doubles until a mode lies above the band.
constexpr int kFirstBandBatch = 16;

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// (A − σB)⁻¹ for Spectra's SymGEigsShiftSolver in shift-invert mode, on a CHOLMOD Cholesky
// factor (A − σB must be positive definite). The shift is fixed at construction: set_shift
// only checks it, so one factor serves the eigensolver and any other solve (constraint modes).
class CholmodShiftInvert {
 public:
  using Scalar = double;

  CholmodShiftInvert(const SparseMatrix& a, const SparseMatrix& b, double sigma)
      : sigma_(sigma), n_(a.rows()), factor_(std::make_unique<Cholesky>()) {
    // Failures are reported by the exception below, not by CHOLMOD printing on stdout. LLᵀ:
    // it fails where the matrix is not positive definite (the automatic mode may pick a
    // simplicial LDLᵀ that factorises an indefinite one without a word).
    factor_->cholmod().print = 0;
    factor_->setMode(Eigen::CholmodSupernodalLLt);
    const SparseMatrix shifted = sigma == 0.0 ? a : SparseMatrix(a - sigma * b);
    factor_->compute(shifted);
    if (factor_->info() != Eigen::Success) {
      throw std::runtime_error("the matrix K − σM (σ = " + std::to_string(sigma) +
                               ") is not positive definite: CHOLMOD could not factorise it");
    }
  }

  Eigen::Index rows() const { return n_; }
  Eigen::Index cols() const { return n_; }
  void set_shift(double sigma) {
    if (sigma != sigma_) throw std::logic_error("CholmodShiftInvert: the shift is fixed");
  }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, n_);
    Eigen::Map<Eigen::VectorXd>(y_out, n_) = factor_->solve(x);
  }
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& rhs) const { return factor_->solve(rhs); }

 private:
  double sigma_;
  Eigen::Index n_;
  std::unique_ptr<Cholesky> factor_;
};

// M-normalises each column of `vectors` (vᵀMv = 1).
void MassNormalise(const SparseMatrix& mass, Eigen::MatrixXd& vectors) {
  for (Eigen::Index j = 0; j < vectors.cols(); ++j) {
    const double norm = std::sqrt(vectors.col(j).dot(mass * vectors.col(j)));
    if (norm > 0.0) vectors.col(j) /= norm;
  }
}

// Lowest `count` eigenpairs of (K, M) through an existing shift-invert operator.
Eigen::VectorXd LanczosLowest(CholmodShiftInvert& op, const SparseMatrix& mass, double sigma,
                              int count, Eigen::MatrixXd* vectors) {
  using BOp = Spectra::SparseSymMatProd<double>;
  BOp b_op(mass);
  const Eigen::Index n = mass.rows();
  // Krylov dimension: the usual 2·nev + 1, at least nev + 20 for few modes, at most n.
  const Eigen::Index ncv = std::min<Eigen::Index>(n, std::max(2 * count + 1, count + 20));
  Spectra::SymGEigsShiftSolver<CholmodShiftInvert, BOp, Spectra::GEigsMode::ShiftInvert> solver(
      op, b_op, count, ncv, sigma);
  solver.init();
  solver.compute(Spectra::SortRule::LargestMagn, kLanczosMaxIterations, kLanczosTolerance,
                 Spectra::SortRule::SmallestAlge);
  if (solver.info() != Spectra::CompInfo::Successful) {
    throw std::runtime_error("the shift-invert Lanczos eigensolver did not converge for " +
                             std::to_string(count) + " modes of a " + std::to_string(n) +
                             "-DOF model");
  }
  Eigen::VectorXd values = solver.eigenvalues();
  Eigen::MatrixXd modes;
  if (vectors != nullptr) modes = solver.eigenvectors();
  // Ascending order, whatever order the solver returns.
  std::vector<int> order(static_cast<size_t>(values.size()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values(a) < values(b); });
  Eigen::VectorXd sorted(values.size());
  for (size_t k = 0; k < order.size(); ++k) sorted(static_cast<Eigen::Index>(k)) = values(order[k]);
  if (vectors != nullptr) {
    vectors->resize(n, values.size());
    for (size_t k = 0; k < order.size(); ++k) {
      vectors->col(static_cast<Eigen::Index>(k)) = modes.col(order[k]);
    }
    MassNormalise(mass, *vectors);
  }
  return sorted;
}

Eigen::VectorXd DenseLowest(const SparseMatrix& stiffness, const SparseMatrix& mass, int count,
                            Eigen::MatrixXd* vectors) {
  const Eigen::MatrixXd k = stiffness;
  const Eigen::MatrixXd m = mass;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(k, m);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error("the dense generalized eigensolver failed (is M positive definite?)");
  }
  if (vectors != nullptr) *vectors = solver.eigenvectors().leftCols(count);  // M-normalised
  return solver.eigenvalues().head(count);
}

// Lowest `count` eigenpairs (K, M) with K positive definite, through the factor of K.
Eigen::VectorXd Lowest(CholmodShiftInvert& op, const SparseMatrix& stiffness,
                       const SparseMatrix& mass, int count, Eigen::MatrixXd* vectors) {
  if (count <= 0) {
    if (vectors != nullptr) vectors->resize(mass.rows(), 0);
    return Eigen::VectorXd();
  }
  if (mass.rows() <= kDenseEigenLimit || count >= mass.rows() - 1) {
    return DenseLowest(stiffness, mass, count, vectors);
  }
  return LanczosLowest(op, mass, 0.0, count, vectors);
}

// Lowest eigenfrequencies (rad/s) of a small dense symmetric pencil.
Eigen::VectorXd DenseFrequencies(const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& mass) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(stiffness, mass,
                                                                   Eigen::EigenvaluesOnly);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error("the reduced mass matrix is not positive definite");
  }
  return solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace

Eigen::VectorXd LowestEigenpairs(const SparseMatrix& stiffness, const SparseMatrix& mass, int count,
                                 double sigma, Eigen::MatrixXd* vectors) {
  if (count <= 0) return Eigen::VectorXd();
  if (mass.rows() <= kDenseEigenLimit || count >= mass.rows() - 1) {
    return DenseLowest(stiffness, mass, std::min<int>(count, static_cast<int>(mass.rows())),
                       vectors);
  }
  CholmodShiftInvert op(stiffness, mass, sigma);
  return LanczosLowest(op, mass, sigma, count, vectors);
}

CraigBamptonModel ReduceCraigBampton(const LinearModel& full, const std::vector<int>& boundary,
                                     const CraigBamptonOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int n = full.num_dofs();
  if (boundary.empty()) throw std::invalid_argument("boundary: no boundary DOF to reduce onto");
  // Position of every DOF in its set: boundary (≥ 0 in `local`, is_boundary) or interior.
  std::vector<int> local(static_cast<size_t>(n), -1);
  std::vector<char> is_boundary(static_cast<size_t>(n), 0);
  for (size_t k = 0; k < boundary.size(); ++k) {
    const int dof = boundary[k];
    if (dof < 0 || dof >= n) {
      throw std::invalid_argument("boundary: DOF " + std::to_string(dof) + " is not in the " +
                                  std::to_string(n) + "-DOF model");
    }
    if (is_boundary[static_cast<size_t>(dof)]) {
      throw std::invalid_argument("boundary: DOF " + std::to_string(dof) + " is repeated");
    }
    is_boundary[static_cast<size_t>(dof)] = 1;
    local[static_cast<size_t>(dof)] = static_cast<int>(k);
  }
  std::vector<int> interior;
  interior.reserve(static_cast<size_t>(n) - boundary.size());
  for (int dof = 0; dof < n; ++dof) {
    if (!is_boundary[static_cast<size_t>(dof)]) {
      local[static_cast<size_t>(dof)] = static_cast<int>(interior.size());
      interior.push_back(dof);
    }
  }
  const int nb = static_cast<int>(boundary.size());
  const int ni = static_cast<int>(interior.size());
  // Nothing to reduce: CHOLMOD would be handed an empty K_ii.
  if (ni == 0) {
    throw std::invalid_argument("boundary: every one of the model's " + std::to_string(n) +
                                " DOFs is a boundary DOF (a law's, a forced or an output DOF): "
                                "there is no interior to reduce (remove the reduction)");
  }
  if (options.modes > ni) {
    throw std::invalid_argument("modes: " + std::to_string(options.modes) +
                                " fixed-interface modes asked, the interior has " +
                                std::to_string(ni) + " DOFs");
  }
  if (options.modes > kMaxReductionModes) {
    throw std::invalid_argument("modes: at most " + std::to_string(kMaxReductionModes));
  }
  if (options.modes < 0 && !(options.max_frequency > 0.0 && std::isfinite(options.max_frequency))) {
    throw std::invalid_argument("max_frequency: must be positive (or give modes)");
  }

  // Interior–interior blocks of K and M and the interior–boundary block of K, in one pass.
  auto split = [&](const SparseMatrix& matrix, SparseMatrix* ii, SparseMatrix* ib) {
    std::vector<Eigen::Triplet<double>> inner, coupling;
    inner.reserve(static_cast<size_t>(matrix.nonZeros()));
    for (int col = 0; col < matrix.outerSize(); ++col) {
      for (SparseMatrix::InnerIterator it(matrix, col); it; ++it) {
        const auto r = static_cast<size_t>(it.row());
        const auto c = static_cast<size_t>(col);
        if (is_boundary[r]) continue;
        if (!is_boundary[c]) {
          inner.emplace_back(local[r], local[c], it.value());
        } else if (ib != nullptr) {
          coupling.emplace_back(local[r], local[c], it.value());
        }
      }
    }
    ii->resize(ni, ni);
    ii->setFromTriplets(inner.begin(), inner.end());
    if (ib != nullptr) {
      ib->resize(ni, nb);
      ib->setFromTriplets(coupling.begin(), coupling.end());
    }
  };
  SparseMatrix k_ii, m_ii, k_ib;
  split(full.stiffness, &k_ii, &k_ib);
  split(full.mass, &m_ii, nullptr);
  // The fixed-interface modes are those of (K_ii, M_ii): M_ii must be positive definite, or
  // the eigensolvers return modes of a pencil that has no physical meaning.
  {
    Cholesky mass_factor;
    mass_factor.cholmod().print = 0;
    // LLᵀ, which fails on a matrix that is not positive definite (CHOLMOD's automatic mode may
    // pick a simplicial LDLᵀ that factorises an indefinite one).
    mass_factor.setMode(Eigen::CholmodSupernodalLLt);
    mass_factor.compute(m_ii);
    if (mass_factor.info() != Eigen::Success) {
      throw std::runtime_error(
          "the interior mass M_ii is not positive definite (a negative or zero mass among the "
          "interior DOFs): the fixed-interface modes need a positive definite mass");
    }
  }

  CraigBamptonModel result;
  ReductionReport& report = result.report;
  report.full_dofs = n;
  report.boundary_dofs = nb;

  // One factor of K_ii: constraint modes and the fixed-interface eigenproblem (σ = 0). Freed
  // before the check factorises the full K (two Cholesky factors at once would double the peak
  // memory).
  auto op = [&] {
    try {
      return std::make_unique<CholmodShiftInvert>(k_ii, m_ii, 0.0);
    } catch (const std::runtime_error&) {
      throw std::runtime_error(
          "the interior stiffness K_ii is not positive definite: the boundary DOFs and the "
          "model's clamps must remove every rigid-body motion of the interior");
    }
  }();
  const Eigen::MatrixXd psi = -op->Solve(Eigen::MatrixXd(k_ib));  // ni × nb
  report.factor_s = Seconds(start);
  const auto modes_start = std::chrono::steady_clock::now();

  Eigen::MatrixXd phi;
  Eigen::VectorXd lambda;
  if (options.modes >= 0) {
    lambda = Lowest(*op, k_ii, m_ii, options.modes, &phi);
  } else {
    // Every mode below the band: batches doubling until one lies above it.
    const double limit = std::pow(kBandFactor * options.max_frequency, 2);
    int batch = std::min(kFirstBandBatch, ni);
    while (true) {
      lambda = Lowest(*op, k_ii, m_ii, batch, &phi);
      const bool above = lambda.size() > 0 && lambda(lambda.size() - 1) > limit;
      if (above || batch >= ni) break;
      if (batch >= kMaxReductionModes) {
        throw std::invalid_argument(
            "max_frequency: more than " + std::to_string(kMaxReductionModes) +
            " fixed-interface modes lie below " + std::to_string(kBandFactor) + " × max_frequency");
      }
      batch = std::min({2 * batch, ni, kMaxReductionModes});
    }
    int kept = 0;
    while (kept < lambda.size() && lambda(kept) <= limit) ++kept;
    lambda.conservativeResize(kept);
    phi.conservativeResize(Eigen::NoChange, kept);
  }
  op.reset();
  k_ii = SparseMatrix();
  m_ii = SparseMatrix();
  k_ib = SparseMatrix();
  const int m = static_cast<int>(lambda.size());
  report.modes = m;
  report.modes_s = Seconds(modes_start);
  for (Eigen::Index j = 0; j < m; ++j) {
    report.fixed_interface_frequencies.push_back(std::sqrt(std::max(0.0, lambda(j))));
  }

  // T in the full DOF order (N × (nb + m)); nothing N × N is formed.
  const int r = nb + m;
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(n, r);
  for (int k = 0; k < nb; ++k) t(boundary[static_cast<size_t>(k)], k) = 1.0;
  for (int k = 0; k < ni; ++k) {
    const int dof = interior[static_cast<size_t>(k)];
    t.row(dof).head(nb) = psi.row(k);
    if (m > 0) t.row(dof).tail(m) = phi.row(k);
  }
  auto project = [&](const SparseMatrix& matrix) {
    Eigen::MatrixXd reduced = t.transpose() * (matrix * t);
    return Eigen::MatrixXd(0.5 * (reduced + reduced.transpose()));  // symmetric to round-off
  };
  // The reduced model is dense; sparseView keeps every entry (no threshold) so Tᵀ K T is exact.
  LinearModel& reduced = result.model;
  reduced.stiffness = project(full.stiffness).sparseView(1.0, 0.0);
  reduced.mass = project(full.mass).sparseView(1.0, 0.0);
  reduced.damping = full.damping.nonZeros() == 0
                        ? SparseMatrix(r, r)
                        : SparseMatrix(project(full.damping).sparseView(1.0, 0.0));
  for (int k = 0; k < nb; ++k) {
    const int dof = boundary[static_cast<size_t>(k)];
    reduced.dof_names.push_back(full.dof_names.empty() ? std::to_string(dof)
                                                       : full.dof_names[static_cast<size_t>(dof)]);
  }
  for (int j = 0; j < m; ++j) reduced.dof_names.push_back("cb_mode_" + std::to_string(j + 1));
  if (options.keep_recovery) result.recovery = std::move(t);
  report.time_s = Seconds(start);

  // The check: lowest eigenfrequencies of the reduced model against the full model's. The full
  // model may be free (K singular), so its shift is below zero, at 1 % of the reduced model's
  // lowest positive eigenvalue (an upper bound of the full one's, Rayleigh–Ritz).
  // An explicit count above the reduced size would compare frequencies the reduced model does
  // not have; the default is clipped to it.
  if (options.check_frequencies > r) {
    throw std::invalid_argument("check_frequencies: " + std::to_string(options.check_frequencies) +
                                " asked, the reduced model has " + std::to_string(r) + " DOFs (" +
                                std::to_string(nb) + " boundary + " + std::to_string(m) +
                                " modes)");
  }
  const int checks = options.check_frequencies >= 0 ? options.check_frequencies
                                                    : std::min({kDefaultCheckFrequencies, r, n});
  if (checks > 0) {
    const auto check_start = std::chrono::steady_clock::now();
    const Eigen::VectorXd reduced_frequencies =
        DenseFrequencies(Eigen::MatrixXd(reduced.stiffness), Eigen::MatrixXd(reduced.mass));
    double lowest = 0.0;
    for (Eigen::Index j = 0; j < reduced_frequencies.size() && lowest == 0.0; ++j) {
      if (reduced_frequencies(j) > 1e-6 * reduced_frequencies.maxCoeff()) {
        lowest = reduced_frequencies(j) * reduced_frequencies(j);
      }
    }
    const double sigma = lowest > 0.0 ? -0.01 * lowest : -1.0;
    const Eigen::VectorXd full_lambda =
        LowestEigenpairs(full.stiffness, full.mass, checks, sigma, nullptr);
    for (int j = 0; j < checks; ++j) {
      EigenfrequencyCheck check;
      check.full = std::sqrt(std::max(0.0, full_lambda(j)));
      check.reduced = reduced_frequencies(j);
      check.relative_error = check.full > 0.0 ? (check.reduced - check.full) / check.full : 0.0;
      report.eigenfrequencies.push_back(check);
    }
    report.check_time_s = Seconds(check_start);
  }
  return result;
}

}  // namespace nfrc
