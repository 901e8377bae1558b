#pragma once

#include <Eigen/Dense>
#include <algorithm>

namespace nfrc {

// The scaled bordered matrix A = [[R_y D_y, R_λ s_λ] / r; cᵀ] of a Newton step, read in place
// from the Jacobians: A(i, j) = (R_y(i, j)·s_j)/r, A(i, n) = R_λ(i)·(s_λ/r), A(n, j) = c_j,
// rounded exactly as Materialize (and so AugmentedMatrix) writes them. The block elimination reads
// each entry it needs once, so the (n + 1)² copy (9 % of the N_φ = 160 friction curve) is not made.
// Holds references: the Jacobians, scales and row must outlive it.
class BorderedView {
 public:
  BorderedView(const Eigen::MatrixXd& jacobian_y, const Eigen::VectorXd& jacobian_lambda,
               const Eigen::VectorXd& scales, double residual_scale,
               const Eigen::VectorXd& last_row)
      : jacobian_y_(jacobian_y),
        jacobian_lambda_(jacobian_lambda),
        scales_(scales),
        residual_scale_(residual_scale),
        lambda_factor_(scales(jacobian_y.cols()) / residual_scale),
        last_row_(last_row),
        n_(jacobian_y.cols()) {}

  Eigen::Index rows() const { return n_ + 1; }
  const Eigen::VectorXd& last_row() const { return last_row_; }

  double operator()(Eigen::Index i, Eigen::Index j) const {
    if (i == n_) return last_row_(j);
    if (j == n_) return jacobian_lambda_(i) * lambda_factor_;
    return jacobian_y_(i, j) * scales_(j) / residual_scale_;
  }

  // Rows [start, start + length) of column j into `out` (size length).
  void ReadColumn(Eigen::Index j, Eigen::Index start, Eigen::Index length,
                  Eigen::Ref<Eigen::VectorXd> out) const {
    const Eigen::Index top = std::max<Eigen::Index>(0, std::min(length, n_ - start));
    if (top > 0) {
      if (j == n_) {
        out.head(top) = jacobian_lambda_.segment(start, top) * lambda_factor_;
      } else {
        out.head(top) = jacobian_y_.col(j).segment(start, top) * scales_(j) / residual_scale_;
      }
    }
    if (top < length) out(length - 1) = last_row_(j);  // the border row, n = start + length − 1
  }

  // Column j's unscaled entries above the border row (R_y's column, or R_λ for j = n): their
  // zeros are the scaled matrix's (the scales are finite and positive; an entry whose scaled
  // value underflows to 0 counts as nonzero here), so a zero pattern is read without scaling.
  const double* UnscaledColumn(Eigen::Index j) const {
    return j == n_ ? jacobian_lambda_.data() : jacobian_y_.col(j).data();
  }

  // The whole matrix (AugmentedMatrix, and where the elimination gives way).
  void Materialize(Eigen::MatrixXd* a) const {
    a->resize(n_ + 1, n_ + 1);
    a->topLeftCorner(n_, n_).noalias() =
        jacobian_y_ * scales_.head(n_).asDiagonal() / residual_scale_;
    a->topRightCorner(n_, 1) = jacobian_lambda_ * lambda_factor_;
    a->bottomRows(1) = last_row_.transpose();
  }

 private:
  const Eigen::MatrixXd& jacobian_y_;
  const Eigen::VectorXd& jacobian_lambda_;
  const Eigen::VectorXd& scales_;
  double residual_scale_;
  double lambda_factor_;  // s_λ / r
  const Eigen::VectorXd& last_row_;
  Eigen::Index n_;
};

}  // namespace nfrc
