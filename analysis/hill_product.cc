#include "analysis/hill_product.h"

#include <cassert>

namespace nfrc {
namespace {

// result += x·a_t, a_t = Aᵀ stored: (A ⊗ I) vec(x) = vec(x Aᵀ). Column axpys of nc entries,
// which vectorise.
void AddTimesTransposed(const Eigen::Ref<const Eigen::MatrixXd>& x,
                        const Eigen::SparseMatrix<double>& a_t, Eigen::MatrixXd* result) {
  for (int j = 0; j < a_t.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a_t, j); it; ++it) {
      result->col(j) += it.value() * x.col(it.row());
    }
  }
}

}  // namespace

HillProduct::HillProduct(const HillPencil& pencil) : pencil_(pencil) {
  if (!pencil.factors) return;
  num_dofs_ = static_cast<int>(pencil.factors->damping_t.rows());
  nc_ = static_cast<int>(pencil.factors->derivative.rows());
  assert(num_dofs_ * nc_ <= pencil.d1.rows());
  dq_.resize(nc_, num_dofs_);
  moved_.resize(nc_, num_dofs_);
  result_.resize(nc_, num_dofs_);
  combined_.resize(nc_);
  force_.resize(nc_);
}

void HillProduct::Apply(const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& w, Eigen::VectorXd* y) const {
  const Eigen::Index n = pencil_.d1.rows();
  assert(q.size() == n && w.size() == n);
  y->resize(n);
  if (!pencil_.factors) {
    y->noalias() = pencil_.d1 * q;
    y->noalias() += pencil_.d2 * w;
    return;
  }
  const HillFactors& factors = *pencil_.factors;
  const Eigen::Index dofs = static_cast<Eigen::Index>(num_dofs_) * nc_;
  const Eigen::Map<const Eigen::MatrixXd> q_dofs(q.data(), nc_, num_dofs_);
  const Eigen::Map<const Eigen::MatrixXd> w_dofs(w.data(), nc_, num_dofs_);
  // (C⊗I) q + (M⊗(2ω D)) q + (M⊗I) w = vec(Q Cᵀ + (2ω D Q + W) Mᵀ).
  dq_.noalias() = factors.derivative * q_dofs;
  moved_ = (2.0 * pencil_.omega) * dq_ + w_dofs;
  result_.setZero();
  AddTimesTransposed(q_dofs, factors.damping_t, &result_);
  AddTimesTransposed(moved_, factors.mass_t, &result_);
  y->head(dofs) = Eigen::Map<const Eigen::VectorXd>(result_.data(), dofs);
  y->tail(n - dofs).setZero();
  for (const HillFactors::RowDependence& dependence : factors.dependences) {
    combined_.setZero();
    for (const auto& [dof, coefficient] : dependence.terms)
      combined_ += coefficient * result_.col(dof);
    force_.noalias() = dependence.weights * combined_;
    for (const auto& [first, sign] : dependence.rows) y->segment(first, nc_) += sign * force_;
  }
  if (factors.laws_d1_block) {
    const HillFactors::DenseBlock& block = *factors.laws_d1_block;
    y->segment(block.row, block.values.rows()).noalias() +=
        block.values * q.segment(block.col, block.values.cols());
  }
  if (factors.laws_d1.nonZeros() > 0) y->noalias() += factors.laws_d1 * q;
  if (factors.laws_d2.nonZeros() > 0) y->noalias() += factors.laws_d2 * w;
}

}  // namespace nfrc
