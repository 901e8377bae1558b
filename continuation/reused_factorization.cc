#include "continuation/reused_factorization.h"

#include <algorithm>
#include <cmath>

#include "continuation/bordered_view.h"

namespace nfrc {

bool ReusedFactorization::Refactor(const Eigen::MatrixXd& schur, const Eigen::VectorXd& rhs,
                                   Eigen::VectorXd* rest_solution) {
  base_ = schur;
  base_norm_ = base_.norm();
  base_lu_.Compute(base_);
  ++counts_.factorisations;
  if (!RegularForElimination(base_lu_)) {
    elimination_.reset();
    return false;
  }
  *rest_solution = base_lu_.Solve(rhs);
  return true;
}

bool ReusedFactorization::LowRank(const Eigen::MatrixXd& delta, int max_rank, Eigen::MatrixXd* q,
                                  Eigen::MatrixXd* b) {
  const Eigen::Index n = delta.rows();
  const double tolerance = kRangeTolerance * base_norm_;
  std::normal_distribution<double> normal;
  q->resize(n, 0);
  while (true) {
    Eigen::MatrixXd probes(n, kProbes);
    for (Eigen::Index j = 0; j < kProbes; ++j) {
      for (Eigen::Index i = 0; i < n; ++i) probes(i, j) = normal(random_);
    }
    // ‖ΔS ω‖ for a Gaussian ω is ~‖ΔS‖_F: what the projection leaves of it bounds the rest.
    Eigen::MatrixXd y = delta * probes;
    for (int pass = 0; pass < 2 && q->cols() > 0; ++pass) y -= *q * (q->transpose() * y);
    const double largest = y.colwise().norm().maxCoeff();
    if (largest <= tolerance) break;
    // Overflowed entries (a law's parameter far outside its range) give no basis: a new LU.
    if (!std::isfinite(largest)) return false;
    // Directions whose pivot is below the tolerance are rounding: not kept.
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(y);
    qr.setThreshold(tolerance / largest);
    const Eigen::Index rank = qr.rank();
    // Each round adds a direction or ends: the loop is bounded by max_rank rounds.
    if (rank == 0 || q->cols() + rank > max_rank) return false;
    const Eigen::MatrixXd basis = qr.householderQ() * Eigen::MatrixXd::Identity(n, rank);
    q->conservativeResize(n, q->cols() + rank);
    q->rightCols(rank) = basis;
  }
  *b = q->transpose() * delta;
  return true;
}

template <typename Matrix>
bool ReusedFactorization::Solve(const Matrix& a, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  const bool kept = elimination_ && elimination_->SameBlockRows(a);
  if (!kept) {
    elimination_ = BlockElimination::Factor(a, blocks_);
    if (!elimination_) return false;
  }
  Eigen::MatrixXd schur;
  Eigen::VectorXd rhs, rest_solution;
  const Eigen::VectorXd block_solutions = elimination_->BlockSolutions(b);
  elimination_->Reduce(a, b, block_solutions, &schur, &rhs);
  if (!(kept && Update(schur, rhs, &rest_solution)) && !Refactor(schur, rhs, &rest_solution)) {
    return false;
  }
  elimination_->BackSubstitute(block_solutions, rest_solution, x);
  return x->allFinite();
}

bool ReusedFactorization::Update(const Eigen::MatrixXd& schur, const Eigen::VectorXd& rhs,
                                 Eigen::VectorXd* rest_solution) {
  const int n = static_cast<int>(schur.rows());
  Eigen::MatrixXd q, coefficients;
  if (!LowRank(schur - base_, static_cast<int>(kMaxRankFraction * n), &q, &coefficients)) {
    return false;
  }
  // (S₀ + Q B)⁻¹ r = z − W (I + B W)⁻¹ B z, with z = S₀⁻¹ r and W = S₀⁻¹ Q.
  *rest_solution = base_lu_.Solve(rhs);
  const int k = static_cast<int>(q.cols());
  if (k > 0) {
    const Eigen::MatrixXd w = base_lu_.Solve(q);
    const Eigen::MatrixXd capacitance = Eigen::MatrixXd::Identity(k, k) + coefficients * w;
    *rest_solution -= w * capacitance.partialPivLu().solve(coefficients * *rest_solution);
  }
  const double backward = (schur * *rest_solution - rhs).lpNorm<Eigen::Infinity>();
  const double scale = schur.lpNorm<Eigen::Infinity>() * rest_solution->lpNorm<Eigen::Infinity>() +
                       rhs.lpNorm<Eigen::Infinity>();
  if (!rest_solution->allFinite() || !(backward <= kMaxBackwardError * scale)) return false;
  ++counts_.updates;
  counts_.largest_rank = std::max(counts_.largest_rank, k);
  return true;
}

template bool ReusedFactorization::Solve(const Eigen::MatrixXd&, const Eigen::VectorXd&,
                                         Eigen::VectorXd*);
template bool ReusedFactorization::Solve(const BorderedView&, const Eigen::VectorXd&,
                                         Eigen::VectorXd*);

}  // namespace nfrc
