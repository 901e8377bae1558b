#pragma once

#include <Eigen/Dense>

#include "analysis/hill.h"

namespace nfrc {

// y = Δ1 q + Δ2 w, the product of Hill's shift-invert operator (ShiftInvertOperator in
// analysis/hill.cc) that Arnoldi applies 30–100 times per point: through the pencil's factors
// when it has them, else through d1 and d2. No allocation once y has the pencil's size. The
// pencil must outlive the product.
class HillProduct {
 public:
  explicit HillProduct(const HillPencil& pencil);

  // q and w of the pencil's size (w: zero outside pencil.dynamic, as Δ2's other columns are).
  void Apply(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& w,
             Eigen::VectorXd* y) const;

 private:
  const HillPencil& pencil_;
  int num_dofs_ = 0;
  int nc_ = 0;
  // Work matrices of the factored product (nc × n): D Q, then 2ω D Q + W, then the result.
  mutable Eigen::MatrixXd dq_, moved_, result_;
  // A dependence's Σ c·(linear rows)·(q, w) and its force (nc).
  mutable Eigen::VectorXd combined_, force_;
};

}  // namespace nfrc
