#include "core/condensation.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/lu_factorization.h"
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

  // y = A·x for the matrix A with these values.
  void Multiply(const std::vector<Complex>& values, const Eigen::MatrixXcd& x,
                Eigen::MatrixXcd& y) const {
    y.setZero(csc.n, x.cols());
    for (Eigen::Index c = 0; c < x.cols(); ++c) {
      for (int j = 0; j < csc.n; ++j) {
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
  // Work arrays of size ~n_l reused across harmonics and frequencies.
  std::vector<Complex> values;
  Eigen::MatrixXcd solution, solution_t, product;

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
};

void Condensation::Impl::Condense(int p, int k, double omega) {
  const Weights w = StiffnessWeights(k, omega);
  const Weights dw = DerivativeWeights(k, omega);
  z[p] = Retained(w);
  dz[p] = Retained(dw);
  f[p] = forcing_r[p];
  df[p] = Eigen::VectorXcd::Zero(n_r);
  if (n_l == 0) return;
  ll.Values(w, values);
  // Reuse the previous frequency's pivot order when still stable, else factorise afresh.
  if (!factors[p] || !factors[p]->Refactor(values)) {
    factors[p].reset();
    factors[p] = dense ? internal::DenseLu(ll.Dense(values), k, omega)
                       : analysis->Factorize(values, k, omega);
  }
  const internal::LuFactorization& lu = *factors[p];

  // [X W] = Z_ll⁻¹ [Z_lr F_l].
  solution.setZero(n_l, n_r + 1);
  for (const Entry& e : lr) solution(e.row, e.col) += e.Value(w);
  CondensedRhs(p, w, Eigen::VectorXcd(), solution, n_r);
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
               (method_ == Method::kAuto && (n < kDenseLimit || density > kDenseFill));
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
  if (impl.n_l > 0 && !impl.dense && !impl.analysis) {
    impl.analysis = std::make_unique<internal::SparseAnalysis>(impl.ll.csc);
  }
  for (int p = 0; p < num_positions; ++p) {
    impl.Condense(p, set_.harmonics()[p], omega);
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

namespace {

// Real DOF-major form of per-harmonic complex blocks: [[Re, Im], [−Im, Re]] on (a_k, b_k),
// only Re for k = 0.
Eigen::MatrixXd RealBlocks(const HarmonicSet& set, const std::vector<Eigen::MatrixXcd>& blocks,
                           int num_retained) {
  const int n_c = set.NumCoefficients();
  Eigen::MatrixXd real = Eigen::MatrixXd::Zero(num_retained * n_c, num_retained * n_c);
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int ic = set.CosIndex(p);
    const int is = set.SinIndex(p);
    for (int i = 0; i < num_retained; ++i) {
      for (int j = 0; j < num_retained; ++j) {
        const Complex z = blocks[p](i, j);
        real(i * n_c + ic, j * n_c + ic) = z.real();
        if (set.harmonics()[p] == 0) continue;
        real(i * n_c + ic, j * n_c + is) = z.imag();
        real(i * n_c + is, j * n_c + ic) = -z.imag();
        real(i * n_c + is, j * n_c + is) = z.real();
      }
    }
  }
  return real;
}

// Real forcing (a, b) = (Re F, −Im F) per harmonic; a_0 = Re F_0.
Eigen::VectorXd RealVector(const HarmonicSet& set, const std::vector<Eigen::VectorXcd>& vectors,
                           int num_retained) {
  const int n_c = set.NumCoefficients();
  Eigen::VectorXd real = Eigen::VectorXd::Zero(num_retained * n_c);
  for (int p = 0; p < set.num_harmonics(); ++p) {
    for (int i = 0; i < num_retained; ++i) {
      real(i * n_c + set.CosIndex(p)) = vectors[p](i).real();
      if (set.harmonics()[p] != 0) real(i * n_c + set.SinIndex(p)) = -vectors[p](i).imag();
    }
  }
  return real;
}

}  // namespace

Eigen::MatrixXd Condensation::RealOperator() const {
  CheckAccess(impl_->updated, 0, set_.num_harmonics());
  return RealBlocks(set_, impl_->z, num_retained());
}

Eigen::MatrixXd Condensation::RealOperatorDerivative() const {
  CheckAccess(impl_->updated, 0, set_.num_harmonics());
  return RealBlocks(set_, impl_->dz, num_retained());
}

Eigen::VectorXd Condensation::RealForcing() const {
  CheckAccess(impl_->updated, 0, set_.num_harmonics());
  return RealVector(set_, impl_->f, num_retained());
}

Eigen::VectorXd Condensation::RealForcingDerivative() const {
  CheckAccess(impl_->updated, 0, set_.num_harmonics());
  return RealVector(set_, impl_->df, num_retained());
}

Eigen::MatrixXd Condensation::RealOperatorRows(int i, bool derivative) const {
  CheckAccess(impl_->updated, 0, set_.num_harmonics());
  if (i < 0 || i >= num_retained()) throw std::invalid_argument("i: not a retained DOF index");
  const std::vector<Eigen::MatrixXcd>& blocks = derivative ? impl_->dz : impl_->z;
  const int n_c = set_.NumCoefficients();
  Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(n_c, num_unknowns());
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    const int ic = set_.CosIndex(p);
    const int is = set_.SinIndex(p);
    for (int j = 0; j < num_retained(); ++j) {
      const Complex z = blocks[p](i, j);
      rows(ic, j * n_c + ic) = z.real();
      if (set_.harmonics()[p] == 0) continue;
      rows(ic, j * n_c + is) = z.imag();
      rows(is, j * n_c + ic) = -z.imag();
      rows(is, j * n_c + is) = z.real();
    }
  }
  return rows;
}

Eigen::VectorXd Condensation::RealForcingRows(int i, bool derivative) const {
  CheckAccess(impl_->updated, 0, set_.num_harmonics());
  if (i < 0 || i >= num_retained()) throw std::invalid_argument("i: not a retained DOF index");
  const std::vector<Eigen::VectorXcd>& vectors = derivative ? impl_->df : impl_->f;
  const int n_c = set_.NumCoefficients();
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(n_c);
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    rows(set_.CosIndex(p)) = vectors[p](i).real();
    if (set_.harmonics()[p] != 0) rows(set_.SinIndex(p)) = -vectors[p](i).imag();
  }
  return rows;
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
    impl.CondensedRhs(p, StiffnessWeights(k, omega_), x_r, x_l, 0);
    impl.factors[p]->Solve(x_l, false);
    for (int l = 0; l < impl.n_l; ++l) {
      result(impl.condensed[l], ic) = x_l(l).real();
      if (k != 0) result(impl.condensed[l], is) = -x_l(l).imag();
    }
  }
  return result;
}

}  // namespace nfrc
