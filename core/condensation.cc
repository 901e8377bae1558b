#include "core/condensation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/lu_factorization.h"
#include "core/modal_receptance.h"
#include "core/relative_coordinates.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;
using SparseReal = Eigen::SparseMatrix<double>;

// Weights of a combination w_k K + w_m M + i·w_c C: Z_k(ω) uses (1, −(kω)², kω) and
// dZ_k/dω uses (0, −2k²ω, k).
struct Weights {
  double stiffness;
  double mass;
  double damping;

  Complex operator()(double k, double m, double c) const {
    return {stiffness * k + mass * m, damping * c};
  }
};

Weights StiffnessWeights(int k, double omega) { return {1.0, -k * omega * k * omega, k * omega}; }
Weights DerivativeWeights(int k, double omega) { return {0.0, -2.0 * k * k * omega, 1.0 * k}; }

// One entry of K, M or C in an off-diagonal block (lr or rl), in local block indices. These
// blocks couple few DOFs, so entry lists beat sparse-matrix expressions over n_l columns.
struct Entry {
  int row;
  int col;
  double stiffness;
  double mass;
  double damping;

  Complex Value(const Weights& w) const { return w(stiffness, mass, damping); }
};

// Z_ll on the union pattern of its K, M and C parts, so that one symbolic analysis serves
// every harmonic and frequency.
struct Pattern {
  internal::CscPattern csc;
  std::vector<double> stiffness, mass, damping;  // aligned with csc.row_index

  void Values(const Weights& w, std::vector<Complex>& values) const {
    values.resize(csc.row_index.size());
    for (size_t e = 0; e < values.size(); ++e) values[e] = w(stiffness[e], mass[e], damping[e]);
  }

  Eigen::MatrixXcd Dense(const std::vector<Complex>& values) const {
    Eigen::MatrixXcd dense = Eigen::MatrixXcd::Zero(csc.n, csc.n);
    for (int j = 0; j < csc.n; ++j) {
      for (auto e = csc.col_start[j]; e < csc.col_start[j + 1]; ++e) {
        dense(csc.row_index[e], j) = values[e];
      }
    }
    return dense;
  }

  // y = A·x, or Aᵀ·x if `transposed`, for the matrix A with these values.
  void Multiply(const std::vector<Complex>& values, const Eigen::MatrixXcd& x, Eigen::MatrixXcd& y,
                bool transposed = false) const {
    y.setZero(csc.n, x.cols());
    for (Eigen::Index c = 0; c < x.cols(); ++c) {
      for (int j = 0; j < csc.n; ++j) {
        if (transposed) {
          Complex sum = 0.0;
          for (auto e = csc.col_start[j]; e < csc.col_start[j + 1]; ++e) {
            sum += values[e] * x(csc.row_index[e], c);
          }
          y(j, c) = sum;
          continue;
        }
        const Complex xj = x(j, c);
        for (auto e = csc.col_start[j]; e < csc.col_start[j + 1]; ++e) {
          y(csc.row_index[e], c) += values[e] * xj;
        }
      }
    }
  }
};

std::vector<double> ValuesOnPattern(const SparseReal& pattern, const SparseReal& matrix) {
  std::vector<double> values(pattern.nonZeros(), 0.0);
  std::vector<Eigen::Index> slot(pattern.rows(), -1);
  for (int j = 0; j < pattern.cols(); ++j) {
    for (auto e = pattern.outerIndexPtr()[j]; e < pattern.outerIndexPtr()[j + 1]; ++e) {
      slot[pattern.innerIndexPtr()[e]] = e;
    }
    for (SparseReal::InnerIterator it(matrix, j); it; ++it) values[slot[it.row()]] += it.value();
  }
  return values;
}

bool IsSymmetric(const SparseReal& a) {
  const SparseReal transpose = a.transpose();
  // Exact: a rounding-level asymmetry would make the transposed-solve shortcut inexact.
  return (a - transpose).cwiseAbs().sum() == 0.0;
}

void CheckAccess(bool updated, int position, int num_positions) {
  if (!updated) throw std::logic_error("Condensation: call Update(omega) first");
  if (position < 0 || position >= num_positions) {
    throw std::invalid_argument("position: must be in [0, " + std::to_string(num_positions) +
                                "), got " + std::to_string(position));
  }
}

}  // namespace

struct Condensation::Impl {
  int n_l = 0;
  int n_r = 0;
  std::vector<int> condensed;  // global indices of the condensed DOFs, ascending
  bool dense = false;
  bool symmetric = false;
  Pattern ll;
  std::vector<Entry> lr, rl;  // Z_lr and Z_rl entries
  Eigen::MatrixXd rr_stiffness, rr_mass, rr_damping;
  // Complex forcing per harmonic position: retained part dense, condensed part as (local, F).
  std::vector<Eigen::VectorXcd> forcing_r;
  std::vector<std::vector<std::pair<int, Complex>>> forcing_l;
  // Declared before the factorisations, which refer to it, so that it is destroyed after them.
  std::unique_ptr<internal::SparseAnalysis> analysis;
  std::vector<std::unique_ptr<internal::LuFactorization>> factors;
  std::vector<Eigen::MatrixXcd> z, dz;
  std::vector<Eigen::VectorXcd> f, df;
  bool updated = false;
  // The modal form (Method::kModal), Φᵀ F per harmonic position, and per position whether
  // the last Update used it.
  std::unique_ptr<internal::ModalReceptance> modal;
  std::vector<Eigen::VectorXcd> modal_forcing;
  std::vector<char> modal_used;
  std::vector<Eigen::VectorXcd> modal_inverse;  // 1/d_m per position where used
  // With obstacles, copies of the modal form's Z_red and F_red before the transform.
  bool keep_absolute = false;
  std::vector<Eigen::MatrixXcd> z_absolute;
  std::vector<Eigen::VectorXcd> f_absolute;
  // Work arrays of size ~n_l reused across harmonics and frequencies.
  std::vector<Complex> values;
  Eigen::MatrixXcd solution, solution_t, product;

  // The static split, prepared at the first Update when K_ll is regular. With the static
  // modes Φ = −K_ll⁻¹K_lr (right) and Ψ = −K_ll⁻ᵀK_rlᵀ (left), T = [I; Φ], T̃ = [I; Ψ] and
  // D = Z − K = −Ω²M + iΩC, the Schur complement is exactly
  //   Z_red = S0 + T̃ᵀDT − (T̃ᵀDE) Z_ll⁻¹ (EᵀDT),   S0 = K_rr + K_rl Φ (E: the interior rows),
  // because K T has no interior rows. Only D enters the ω-dependent terms, so the
  // cancellation of K_rr against K_rl K_ll⁻¹ K_lr (relative rounding ~ n·eps·‖K‖/‖Z_red‖,
  // 3e-5 on a 10⁵-element rod) happens once, in S0: a fixed perturbation of the model, not
  // noise that moves with ω under the corrector.
  bool split_requested = true;
  bool split_prepared = false;
  bool split = false;
  Eigen::MatrixXd phi;                  // n_l × n_r
  Eigen::MatrixXd s0;                   // n_r × n_r
  Eigen::MatrixXd a_mass, a_damping;    // T̃ᵀMT, T̃ᵀCT (n_r × n_r)
  Eigen::MatrixXd c_mass, c_damping;    // EᵀMT = M_lr + M_ll Φ, likewise C (n_l × n_r)
  Eigen::MatrixXd bt_mass, bt_damping;  // (T̃ᵀME)ᵀ = M_rlᵀ + M_llᵀ Ψ (empty if symmetric)
  std::vector<Eigen::VectorXcd> forcing_static;  // Ψᵀ F_l per harmonic position

  // D-part of the split matrices at weights w: w.mass·X_M + i·w.damping·X_C.
  static Eigen::MatrixXcd Combine(const Weights& w, const Eigen::MatrixXd& mass,
                                  const Eigen::MatrixXd& damping) {
    Eigen::MatrixXcd out(mass.rows(), mass.cols());
    out.real() = w.mass * mass;
    out.imag() = w.damping * damping;
    return out;
  }
  const Eigen::MatrixXd& BtMass() const { return symmetric ? c_mass : bt_mass; }
  const Eigen::MatrixXd& BtDamping() const { return symmetric ? c_damping : bt_damping; }

  void PrepareSplit(int num_positions);
  void CondenseSplit(int position, int k, double omega);
  // Factorises Z_ll at harmonic k into factors[p], reusing the previous frequency's pivot
  // order when it is still stable.
  void Factor(int p, const Weights& w, int k, double omega);
  // b = [B F_l] (n_l × (n_r + 1)): the interior right-hand sides of the condensation, with
  // B = EᵀDT for the static split and Z_lr for the direct form.
  void InteriorRhs(int p, const Weights& w, Eigen::MatrixXcd* b) const;

  // Z_rr(w) as a dense n_r × n_r matrix.
  Eigen::MatrixXcd Retained(const Weights& w) const {
    return (w.stiffness * rr_stiffness + w.mass * rr_mass).cast<Complex>() +
           Complex(0.0, w.damping) * rr_damping.cast<Complex>();
  }

  // Column `col` of b = F_l − Z_lr x_r for harmonic `position` (x_r may be empty: 0).
  void CondensedRhs(int position, const Weights& w, const Eigen::VectorXcd& x_r,
                    Eigen::MatrixXcd& b, int col) const {
    b.col(col).setZero();
    for (const auto& [i, value] : forcing_l[position]) b(i, col) += value;
    if (x_r.size() == 0) return;
    for (const Entry& e : lr) b(e.row, col) -= e.Value(w) * x_r(e.col);
  }

  void Condense(int position, int k, double omega);

  // Z_red and F_red of a harmonic the modal form served, in absolute coordinates (before
  // any obstacle's transform), for Recover and EstimateRounding.
  const Eigen::MatrixXcd& ModalZ(int p) const { return keep_absolute ? z_absolute[p] : z[p]; }
  const Eigen::VectorXcd& ModalF(int p) const { return keep_absolute ? f_absolute[p] : f[p]; }
};

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

void Condensation::Impl::Factor(int p, const Weights& w, int k, double omega) {
  ll.Values(w, values);
  if (!factors[p] || !factors[p]->Refactor(values)) {
    factors[p].reset();
    factors[p] = dense ? internal::DenseLu(ll.Dense(values), k, omega)
                       : analysis->Factorize(values, k, omega);
  }
}

void Condensation::Impl::InteriorRhs(int p, const Weights& w, Eigen::MatrixXcd* b) const {
  b->setZero(n_l, n_r + 1);
  if (split) {
    b->leftCols(n_r) = Combine(w, c_mass, c_damping);
  } else {
    for (const Entry& e : lr) (*b)(e.row, e.col) += e.Value(w);
  }
  CondensedRhs(p, w, Eigen::VectorXcd(), *b, n_r);
}

void Condensation::Impl::Condense(int p, int k, double omega) {
  const Weights w = StiffnessWeights(k, omega);
  const Weights dw = DerivativeWeights(k, omega);
  if (n_l > 0) Factor(p, w, k, omega);
  if (split && n_l > 0) {
    CondenseSplit(p, k, omega);
    return;
  }
  z[p] = Retained(w);
  dz[p] = Retained(dw);
  f[p] = forcing_r[p];
  df[p] = Eigen::VectorXcd::Zero(n_r);
  if (n_l == 0) return;
  const internal::LuFactorization& lu = *factors[p];

  // [X W] = Z_ll⁻¹ [Z_lr F_l].
  InteriorRhs(p, w, &solution);
  lu.Solve(solution, false);
  const auto x = solution.leftCols(n_r);
  const auto w_l = solution.col(n_r);

  // Z_red = Z_rr − Z_rl X and F_red = F_r − Z_rl W; dZ_rl terms of the derivatives alike.
  for (const Entry& e : rl) {
    const Complex value = e.Value(w);
    const Complex d_value = e.Value(dw);
    z[p].row(e.row) -= value * x.row(e.col);
    f[p](e.row) -= value * w_l(e.col);
    dz[p].row(e.row) -= d_value * x.row(e.col);
    df[p](e.row) -= d_value * w_l(e.col);
  }
  if (k == 0) return;  // Z_0 = K does not depend on ω

  // Y = Z_ll⁻ᵀ Z_rlᵀ; for symmetric M, C, K, Z is complex symmetric and Y = X.
  if (!symmetric) {
    solution_t.setZero(n_l, n_r);
    for (const Entry& e : rl) solution_t(e.col, e.row) += e.Value(w);
    lu.Solve(solution_t, true);
  }
  const auto y = symmetric ? solution.leftCols(n_r) : solution_t.leftCols(n_r);
  // dZ_red = dZ_rr − dZ_rl X − Yᵀ dZ_lr + Yᵀ dZ_ll X, dF_red = −dZ_rl W + Yᵀ dZ_ll W.
  for (const Entry& e : lr) dz[p].col(e.col) -= y.row(e.row).transpose() * e.Value(dw);
  ll.Values(dw, values);  // the factorisation no longer reads Z_ll (UMFPACK keeps a copy)
  ll.Multiply(values, solution, product);
  dz[p] += y.transpose() * product.leftCols(n_r);
  df[p] += y.transpose() * product.col(n_r);
}

Condensation::Condensation(LinearModel model, std::vector<int> retained, HarmonicSet set,
                           std::vector<ForcingTerm> forcing, Method method)
    : model_(std::move(model)),
      retained_(std::move(retained)),
      set_(std::move(set)),
      forcing_(std::move(forcing)),
      method_(method),
      omega_(std::numeric_limits<double>::quiet_NaN()),
      impl_(std::make_unique<Impl>()) {
  model_.Validate();
  const int n = model_.num_dofs();
  if (retained_.empty()) throw std::invalid_argument("retained: must not be empty");
  // local[i] ≥ 0: position among retained; local[i] < 0: −1 − position among condensed.
  std::vector<int> local(n, std::numeric_limits<int>::min());
  for (int i = 0; i < num_retained(); ++i) {
    const int dof = retained_[i];
    if (dof < 0 || dof >= n) {
      throw std::invalid_argument("retained: DOF " + std::to_string(dof) + " out of range [0, " +
                                  std::to_string(n) + ")");
    }
    if (local[dof] >= 0) {
      throw std::invalid_argument("retained: DOF " + std::to_string(dof) + " repeated");
    }
    local[dof] = i;
  }
  Impl& impl = *impl_;
  for (int dof = 0; dof < n; ++dof) {
    if (local[dof] >= 0) continue;
    local[dof] = -1 - static_cast<int>(impl.condensed.size());
    impl.condensed.push_back(dof);
  }
  impl.n_r = num_retained();
  impl.n_l = static_cast<int>(impl.condensed.size());

  const int num_positions = set_.num_harmonics();
  impl.forcing_r.assign(num_positions, Eigen::VectorXcd::Zero(impl.n_r));
  impl.forcing_l.resize(num_positions);
  for (const ForcingTerm& term : forcing_) {
    if (term.dof < 0 || term.dof >= n) {
      throw std::invalid_argument("forcing: DOF " + std::to_string(term.dof) +
                                  " out of range [0, " + std::to_string(n) + ")");
    }
    int position = -1;
    for (int p = 0; p < num_positions; ++p) {
      if (set_.harmonics()[p] == term.harmonic) position = p;
    }
    if (position < 0) {
      throw std::invalid_argument("forcing: harmonic " + std::to_string(term.harmonic) +
                                  " is not in the harmonic set");
    }
    if (!std::isfinite(term.cos) || !std::isfinite(term.sin)) {
      throw std::invalid_argument("forcing: cos and sin amplitudes must be finite");
    }
    // F = f_cos − i·f_sin; a constant term has no sine part (sin 0θ = 0).
    const Complex value(term.cos, term.harmonic == 0 ? 0.0 : -term.sin);
    const int l = local[term.dof];
    if (l >= 0) {
      impl.forcing_r[position](l) += value;
    } else {
      impl.forcing_l[position].emplace_back(-1 - l, value);
    }
  }

  impl.symmetric =
      IsSymmetric(model_.stiffness) && IsSymmetric(model_.mass) && IsSymmetric(model_.damping);

  // Split K, M, C into the blocks of the partition: ll as triplets, the others directly.
  std::vector<Eigen::Triplet<double>> ll_triplets[3];
  impl.rr_stiffness.setZero(impl.n_r, impl.n_r);
  impl.rr_mass.setZero(impl.n_r, impl.n_r);
  impl.rr_damping.setZero(impl.n_r, impl.n_r);
  Eigen::MatrixXd* rr[3] = {&impl.rr_stiffness, &impl.rr_mass, &impl.rr_damping};
  const SparseReal* matrices[3] = {&model_.stiffness, &model_.mass, &model_.damping};
  for (int m = 0; m < 3; ++m) {
    for (int j = 0; j < n; ++j) {
      for (SparseReal::InnerIterator it(*matrices[m], j); it; ++it) {
        const int row = local[it.row()];
        const int col = local[j];
        if (row < 0 && col < 0) {
          ll_triplets[m].emplace_back(-1 - row, -1 - col, it.value());
        } else if (row >= 0 && col >= 0) {
          (*rr[m])(row, col) += it.value();
        } else {
          Entry entry{row >= 0 ? row : -1 - row, col >= 0 ? col : -1 - col, 0.0, 0.0, 0.0};
          (m == 0 ? entry.stiffness : m == 1 ? entry.mass : entry.damping) = it.value();
          (row >= 0 ? impl.rl : impl.lr).push_back(entry);
        }
      }
    }
  }
  SparseReal ll[3];
  for (int m = 0; m < 3; ++m) {
    ll[m].resize(impl.n_l, impl.n_l);
    ll[m].setFromTriplets(ll_triplets[m].begin(), ll_triplets[m].end());
  }
  SparseReal pattern = ll[0].cwiseAbs() + ll[1].cwiseAbs() + ll[2].cwiseAbs();
  pattern.makeCompressed();
  impl.ll.csc.n = impl.n_l;
  impl.ll.csc.col_start.assign(pattern.outerIndexPtr(), pattern.outerIndexPtr() + impl.n_l + 1);
  impl.ll.csc.row_index.assign(pattern.innerIndexPtr(),
                               pattern.innerIndexPtr() + pattern.nonZeros());
  impl.ll.stiffness = ValuesOnPattern(pattern, ll[0]);
  impl.ll.mass = ValuesOnPattern(pattern, ll[1]);
  impl.ll.damping = ValuesOnPattern(pattern, ll[2]);
  // Dense LU only pays where sparse bookkeeping dominates: small or densely coupled Z_ll
  // (e.g. modal damping). A banded 399-DOF rod took 0.75 s per update dense, 0.8 ms sparse.
  const double density = impl.n_l == 0 ? 1.0
                                       : static_cast<double>(pattern.nonZeros()) /
                                             (static_cast<double>(impl.n_l) * impl.n_l);
  impl.dense = method_ == Method::kDense ||
               (method_ != Method::kSparse && (n < kDenseLimit || density > kDenseFill));
  if (method_ == Method::kModal || (method_ == Method::kAuto && impl.n_l > 0)) {
    std::string reason;
    impl.modal = internal::ModalReceptance::Make(model_, retained_, &reason);
    if (!impl.modal && method_ == Method::kModal) {
      throw std::invalid_argument("method: modal condensation needs " + reason);
    }
  }
  if (impl.modal) {
    for (int p = 0; p < num_positions; ++p) {
      Eigen::VectorXcd full = Eigen::VectorXcd::Zero(n);
      for (int i = 0; i < impl.n_r; ++i) full(retained_[i]) = impl.forcing_r[p](i);
      for (const auto& [l, value] : impl.forcing_l[p]) full(impl.condensed[l]) += value;
      impl.modal_forcing.push_back(impl.modal->Project(full));
    }
  }
}

Condensation::~Condensation() = default;
Condensation::Condensation(Condensation&&) noexcept = default;
Condensation& Condensation::operator=(Condensation&&) noexcept = default;

void Condensation::Update(double omega) {
  if (!std::isfinite(omega)) {
    throw std::invalid_argument("omega: must be finite, got " + std::to_string(omega));
  }
  Impl& impl = *impl_;
  if (impl.updated && omega == omega_) return;
  impl.updated = false;
  omega_ = std::numeric_limits<double>::quiet_NaN();
  const int num_positions = set_.num_harmonics();
  impl.factors.resize(num_positions);
  impl.z.resize(num_positions);
  impl.dz.resize(num_positions);
  impl.f.resize(num_positions);
  impl.df.resize(num_positions);
  impl.modal_used.assign(num_positions, 0);
  impl.modal_inverse.resize(num_positions);
  impl.keep_absolute = impl.modal && !compliance_.empty();
  impl.z_absolute.resize(impl.keep_absolute ? num_positions : 0);
  impl.f_absolute.resize(impl.keep_absolute ? num_positions : 0);
  for (int p = 0; p < num_positions; ++p) {
    const int k = set_.harmonics()[p];
    if (impl.modal && impl.modal->Condense(k, omega, impl.modal_forcing[p], &impl.modal_inverse[p],
                                           &impl.z[p], &impl.dz[p], &impl.f[p], &impl.df[p])) {
      impl.modal_used[p] = 1;
      if (impl.keep_absolute) {
        impl.z_absolute[p] = impl.z[p];
        impl.f_absolute[p] = impl.f[p];
      }
    } else {
      // The direct form's set-up, once, and only if a harmonic needs it (the modal form
      // serves every harmonic of a qualifying model but at an undamped resonance).
      if (impl.n_l > 0 && !impl.dense && !impl.analysis) {
        impl.analysis = std::make_unique<internal::SparseAnalysis>(impl.ll.csc);
      }
      if (!impl.split_prepared) impl.PrepareSplit(num_positions);
      impl.Condense(p, k, omega);
    }
    if (!compliance_.empty()) {
      const Eigen::VectorXd d = Eigen::Map<const Eigen::VectorXd>(compliance_.data(), impl.n_r);
      RelativeBlock relative =
          ToRelativeCoordinates(d, impl.z[p], impl.dz[p], impl.f[p], impl.df[p]);
      impl.z[p] = std::move(relative.z);
      impl.dz[p] = std::move(relative.dz);
      impl.f[p] = std::move(relative.f);
      impl.df[p] = std::move(relative.df);
    }
  }
  impl.updated = true;
  omega_ = omega;
}

void Condensation::set_static_split(bool on) {
  impl_->split_requested = on;
  impl_->split_prepared = false;
  impl_->factors.clear();
  impl_->updated = false;
  omega_ = std::numeric_limits<double>::quiet_NaN();
}

bool Condensation::static_split() const {
  const std::vector<char>& used = impl_->modal_used;
  return impl_->split && std::find(used.begin(), used.end(), 0) != used.end();
}

bool Condensation::modal() const {
  const std::vector<char>& used = impl_->modal_used;
  return impl_->updated && std::find(used.begin(), used.end(), 0) == used.end();
}

void Condensation::SetObstacleCompliance(std::vector<double> compliance) {
  if (static_cast<int>(compliance.size()) != num_retained()) {
    throw std::invalid_argument("compliance: need one entry per retained DOF (" +
                                std::to_string(num_retained()) + "), got " +
                                std::to_string(compliance.size()));
  }
  bool any = false;
  for (double d : compliance) {
    if (!std::isfinite(d) || d < 0.0) {
      throw std::invalid_argument("compliance: entries must be finite and >= 0, got " +
                                  std::to_string(d));
    }
    any = any || d > 0.0;
  }
  compliance_ = any ? std::move(compliance) : std::vector<double>();
  impl_->updated = false;
  omega_ = std::numeric_limits<double>::quiet_NaN();
}

const Eigen::MatrixXcd& Condensation::Z(int position) const {
  CheckAccess(impl_->updated, position, set_.num_harmonics());
  return impl_->z[position];
}

const Eigen::MatrixXcd& Condensation::dZ(int position) const {
  CheckAccess(impl_->updated, position, set_.num_harmonics());
  return impl_->dz[position];
}

const Eigen::VectorXcd& Condensation::F(int position) const {
  CheckAccess(impl_->updated, position, set_.num_harmonics());
  return impl_->f[position];
}

const Eigen::VectorXcd& Condensation::dF(int position) const {
  CheckAccess(impl_->updated, position, set_.num_harmonics());
  return impl_->df[position];
}

Condensation::Rounding Condensation::EstimateRounding() const {
  CheckAccess(impl_->updated, 0, set_.num_harmonics());
  const Impl& impl = *impl_;
  Rounding rounding;
  std::vector<Complex> values;
  Eigen::MatrixXcd product;
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    rounding.z.push_back(Eigen::MatrixXd::Zero(impl.n_r, impl.n_r));
    rounding.f.push_back(Eigen::VectorXd::Zero(impl.n_r));
    if (impl.n_l == 0) continue;
    if (impl.modal_used[p]) {
      impl.modal->Rounding(impl.modal_inverse[p], impl.modal_forcing[p], impl.ModalZ(p),
                           &rounding.z[p], &rounding.f[p]);
      continue;
    }
    const Weights w = StiffnessWeights(set_.harmonics()[p], omega_);
    // The right-hand sides b as Condense has them.
    Eigen::MatrixXcd b;
    impl.InteriorRhs(p, w, &b);
    Eigen::MatrixXcd y = b;
    impl.factors[p]->Solve(y, false);
    impl.ll.Values(w, values);
    impl.ll.Multiply(values, y, product);
    Eigen::MatrixXcd error = b - product;
    impl.factors[p]->Solve(error, false);
    Eigen::MatrixXcd rows = Eigen::MatrixXcd::Zero(impl.n_r, impl.n_r + 1);
    if (impl.split) {
      rows = Impl::Combine(w, impl.BtMass(), impl.BtDamping()).transpose() * error;
    } else {
      for (const Entry& e : impl.rl) rows.row(e.row) += e.Value(w) * error.row(e.col);
    }
    rounding.z[p] = rows.leftCols(impl.n_r).cwiseAbs();
    rounding.f[p] = rows.col(impl.n_r).cwiseAbs();
  }
  return rounding;
}

Eigen::MatrixXd Condensation::Recover(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  CheckAccess(impl_->updated, 0, set_.num_harmonics());
  if (x.size() != num_unknowns()) {
    throw std::invalid_argument("x: must have num_unknowns() = " + std::to_string(num_unknowns()) +
                                " entries, got " + std::to_string(x.size()));
  }
  const Impl& impl = *impl_;
  const int n_c = set_.NumCoefficients();
  Eigen::MatrixXd result(model_.num_dofs(), n_c);
  Eigen::MatrixXcd x_l(impl.n_l, 1);
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    const int k = set_.harmonics()[p];
    const int ic = set_.CosIndex(p);
    const int is = set_.SinIndex(p);
    // X_r = a − i·b (a_0 alone for k = 0), then x_l = Z_ll⁻¹ (F_l − Z_lr X_r).
    Eigen::VectorXcd x_r(impl.n_r);
    for (int i = 0; i < impl.n_r; ++i) {
      x_r(i) = Complex(x(i * n_c + ic), k == 0 ? 0.0 : -x(i * n_c + is));
    }
    if (!compliance_.empty()) {
      const Eigen::VectorXd d = Eigen::Map<const Eigen::VectorXd>(compliance_.data(), impl.n_r);
      x_r =
          AbsoluteFromRelative(d, RelativeBlock{impl.z[p], impl.dz[p], impl.f[p], impl.df[p]}, x_r);
    }
    for (int i = 0; i < impl.n_r; ++i) {
      result(retained_[i], ic) = x_r(i).real();
      if (k != 0) result(retained_[i], is) = -x_r(i).imag();
    }
    if (impl.n_l == 0) continue;
    const Weights w = StiffnessWeights(k, omega_);
    if (impl.modal_used[p]) {
      const Eigen::VectorXcd all = impl.modal->Recover(impl.modal_inverse[p], impl.modal_forcing[p],
                                                       impl.ModalZ(p), impl.ModalF(p), x_r);
      for (int l = 0; l < impl.n_l; ++l) x_l(l) = all(impl.condensed[l]);
    } else if (impl.split) {
      // x_l = Φ x_r + Z_ll⁻¹ (F_l − EᵀDT x_r): Z_lr = EᵀDT − Z_ll Φ.
      x_l.setZero(impl.n_l, 1);
      impl.CondensedRhs(p, w, Eigen::VectorXcd(), x_l, 0);
      x_l.col(0) -= Impl::Combine(w, impl.c_mass, impl.c_damping) * x_r;
      impl.factors[p]->Solve(x_l, false);
      x_l.col(0) += impl.phi.cast<Complex>() * x_r;
    } else {
      impl.CondensedRhs(p, w, x_r, x_l, 0);
      impl.factors[p]->Solve(x_l, false);
    }
    for (int l = 0; l < impl.n_l; ++l) {
      result(impl.condensed[l], ic) = x_l(l).real();
      if (k != 0) result(impl.condensed[l], is) = -x_l(l).imag();
    }
  }
  return result;
}

}  // namespace nfrc
