#include "core/condensation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/condensation_impl.h"
#include "core/lu_factorization.h"
#include "core/modal_receptance.h"
#include "core/relative_coordinates.h"

namespace nfrc {

using internal::Complex;
using internal::DerivativeWeights;
using internal::Entry;
using internal::SparseReal;
using internal::StiffnessWeights;
using internal::Weights;

namespace {

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
  Eigen::VectorXcd x_r(impl.n_r), all;
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    const int k = set_.harmonics()[p];
    const int ic = set_.CosIndex(p);
    const int is = set_.SinIndex(p);
    // X_r = a − i·b (a_0 alone for k = 0), then x_l = Z_ll⁻¹ (F_l − Z_lr X_r).
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
      impl.modal->Recover(impl.modal_inverse[p], impl.modal_forcing[p], impl.ModalZ(p),
                          impl.ModalF(p), x_r, &all);
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
