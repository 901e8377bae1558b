#include <memory>
#include <stdexcept>
#include <vector>

#include "core/condensation_impl.h"

namespace nfrc {

using internal::DerivativeWeights;
using internal::StiffnessWeights;

void Condensation::Impl::PrepareSplit(int num_positions) {
  split_prepared = true;
  split = false;
  if (!split_requested || n_l == 0) return;
  ll.Values(Weights{1.0, 0.0, 0.0}, values);
  std::unique_ptr<internal::LuFactorization> static_lu;
  try {
    static_lu =
        dense ? internal::DenseLu(ll.Dense(values), 0, 0.0) : analysis->Factorize(values, 0, 0.0);
  } catch (const std::runtime_error&) {
    return;  // K_ll singular (a mechanism once the retained DOFs are held): direct form
  }
  Eigen::MatrixXcd rhs = Eigen::MatrixXcd::Zero(n_l, n_r);
  for (const Entry& e : lr) rhs(e.row, e.col) -= e.stiffness;
  static_lu->Solve(rhs, false);
  phi = rhs.real();
  Eigen::MatrixXd psi;
  if (!symmetric) {
    rhs.setZero(n_l, n_r);
    for (const Entry& e : rl) rhs(e.col, e.row) -= e.stiffness;
    static_lu->Solve(rhs, true);
    psi = rhs.real();
  }
  const Eigen::MatrixXd& left = symmetric ? phi : psi;
  s0 = rr_stiffness;
  for (const Entry& e : rl) s0.row(e.row) += e.stiffness * phi.row(e.col);

  // X_lr + X_ll Φ and X_rlᵀ + X_llᵀ Ψ for X = M, C, with X_ll applied through the pattern.
  std::vector<Complex> m_values, c_values;
  ll.Values(Weights{0.0, 1.0, 0.0}, m_values);
  ll.Values(Weights{0.0, 0.0, 1.0}, c_values);  // i·C
  auto interior = [&](const Eigen::MatrixXd& modes, bool transposed, bool mass_part) {
    Eigen::MatrixXcd product_ll;
    ll.Multiply(mass_part ? m_values : c_values, modes.cast<Complex>(), product_ll, transposed);
    Eigen::MatrixXd out =
        mass_part ? Eigen::MatrixXd(product_ll.real()) : Eigen::MatrixXd(product_ll.imag());
    for (const Entry& e : transposed ? rl : lr) {
      const double value = mass_part ? e.mass : e.damping;
      if (transposed) {
        out(e.col, e.row) += value;
      } else {
        out(e.row, e.col) += value;
      }
    }
    return out;
  };
  c_mass = interior(phi, false, true);
  c_damping = interior(phi, false, false);
  if (!symmetric) {
    bt_mass = interior(psi, true, true);
    bt_damping = interior(psi, true, false);
  }
  // T̃ᵀXT = X_rr + X_rl Φ + Ψᵀ(X_lr + X_ll Φ).
  a_mass = rr_mass + left.transpose() * c_mass;
  a_damping = rr_damping + left.transpose() * c_damping;
  for (const Entry& e : rl) {
    a_mass.row(e.row) += e.mass * phi.row(e.col);
    a_damping.row(e.row) += e.damping * phi.row(e.col);
  }
  forcing_static.assign(num_positions, Eigen::VectorXcd::Zero(n_r));
  for (int p = 0; p < num_positions; ++p) {
    for (const auto& [i, value] : forcing_l[p]) {
      forcing_static[p] += value * left.row(i).transpose().cast<Complex>();
    }
  }
  split = true;
}

void Condensation::Impl::CondenseSplit(int p, int k, double omega) {
  const Weights w = StiffnessWeights(k, omega);
  const Weights dw = DerivativeWeights(k, omega);
  const internal::LuFactorization& lu = *factors[p];
  // [Y Y_F] = Z_ll⁻¹ [EᵀDT F_l].
  // For a symmetric model the left rows T̃ᵀDE are (EᵀDT)ᵀ: one combination serves both.
  InteriorRhs(p, w, &solution);
  const Eigen::MatrixXcd c = solution.leftCols(n_r);
  lu.Solve(solution, false);
  const auto y = solution.leftCols(n_r);
  const auto y_f = solution.col(n_r);
  const Eigen::MatrixXcd bt_own = symmetric ? Eigen::MatrixXcd() : Combine(w, bt_mass, bt_damping);
  const Eigen::MatrixXcd& bt = symmetric ? c : bt_own;
  z[p] = s0.cast<Complex>() + Combine(w, a_mass, a_damping) - bt.transpose() * y;
  f[p] = forcing_r[p] + forcing_static[p] - bt.transpose() * y_f;
  dz[p] = Eigen::MatrixXcd::Zero(n_r, n_r);
  df[p] = Eigen::VectorXcd::Zero(n_r);
  if (k == 0) return;  // D = 0: Z_0 = S0 does not depend on ω

  // With Ỹ = Z_ll⁻ᵀ (T̃ᵀDE)ᵀ (= Y for a symmetric model) and dZ_ll = dD_ll:
  //   dZ_red = T̃ᵀdDT − (T̃ᵀdDE) Y − Ỹᵀ (EᵀdDT − dD_ll Y),  dF_red = −(T̃ᵀdDE) Y_F + Ỹᵀ dD_ll Y_F.
  if (!symmetric) {
    solution_t = bt;
    lu.Solve(solution_t, true);
  }
  const auto y_t = symmetric ? solution.leftCols(n_r) : solution_t.leftCols(n_r);
  const Eigen::MatrixXcd dc = Combine(dw, c_mass, c_damping);
  const Eigen::MatrixXcd dbt_own =
      symmetric ? Eigen::MatrixXcd() : Combine(dw, bt_mass, bt_damping);
  const Eigen::MatrixXcd& dbt = symmetric ? dc : dbt_own;
  ll.Values(dw, values);
  ll.Multiply(values, solution, product);  // dD_ll [Y Y_F]
  dz[p] = Combine(dw, a_mass, a_damping) - dbt.transpose() * y -
          y_t.transpose() * (dc - product.leftCols(n_r));
  df[p] = -dbt.transpose() * y_f + y_t.transpose() * product.col(n_r);
}

}  // namespace nfrc
