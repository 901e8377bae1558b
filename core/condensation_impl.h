#pragma once

// Private to core/condensation*.cc: the state of a Condensation (Condensation::Impl) and the
// pieces its translation units share (the direct form and the static split in
// condensation.cc, the static split's set-up and condensation in condensation_split.cc).

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <complex>
#include <memory>
#include <utility>
#include <vector>

#include "core/condensation.h"
#include "core/lu_factorization.h"
#include "core/modal_receptance.h"

namespace nfrc {
namespace internal {

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

inline Weights StiffnessWeights(int k, double omega) {
  return {1.0, -k * omega * k * omega, k * omega};
}
inline Weights DerivativeWeights(int k, double omega) {
  return {0.0, -2.0 * k * k * omega, 1.0 * k};
}

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

}  // namespace internal

struct Condensation::Impl {
  using Complex = internal::Complex;
  using Entry = internal::Entry;
  using Pattern = internal::Pattern;
  using Weights = internal::Weights;

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

}  // namespace nfrc
