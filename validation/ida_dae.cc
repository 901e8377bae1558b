#include "validation/ida_dae.h"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>

namespace nfrc {
namespace {

// Mode iterations at one time before the switch is declared unsettled.
constexpr int kMaxModeRounds = 8;
constexpr int kConsistentIterations = 3;  // F is affine in the unknowns: 1 suffices, 2 checks
// Newton iterations of the projection onto the undifferentiated rows (affine for friction and
// linear springs: 1 suffices; a polynomial spring on the row needs a few).
constexpr int kProjectionIterations = 20;

// Entries of a matrix as triplets shifted by (rows, columns).
IdaDae::Triplets Shifted(const Eigen::SparseMatrix<double>& matrix, int rows, int columns) {
  IdaDae::Triplets entries;
  for (int k = 0; k < matrix.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, k); it; ++it) {
      entries.emplace_back(rows + it.row(), columns + it.col(), it.value());
    }
  }
  return entries;
}

}  // namespace

IdaDae::IdaDae(TransientModel& model, const Excitation& excitation)
    : model_(model), excitation_(excitation) {
  n_ = model.num_dofs();
  int offset = 2 * n_;
  for (const auto& law : model.laws) {
    TimeLawLayout layout;
    layout.num_dofs = n_;
    layout.own_offset = offset;
    layouts_.push_back(layout);
    offset += law->NumOwn();
    root_offsets_.push_back(num_roots_);
    num_roots_ += law->NumRoots();
  }
  q_ = offset;
  size_ = q_ + kNumQuadratures;
  stiffness_ = Shifted(model.model.stiffness, n_, 0);
  damping_ = Shifted(model.model.damping, n_, n_);
  mass_ = Shifted(model.model.mass, n_, n_);
  k_sym_ = 0.5 *
           (model.model.stiffness + Eigen::SparseMatrix<double>(model.model.stiffness.transpose()));
  m_sym_ = 0.5 * (model.model.mass + Eigen::SparseMatrix<double>(model.model.mass.transpose()));
  c_sym_ = model.model.damping + Eigen::SparseMatrix<double>(model.model.damping.transpose());
  differential_.assign(size_, true);
  for (int i = 0; i < n_; ++i) differential_[n_ + i] = !model.massless[i];
  for (size_t l = 0; l < model.laws.size(); ++l) {
    for (int k = 0; k < model.laws[l]->NumOwn(); ++k) {
      differential_[layouts_[l].Own(k)] = model.laws[l]->OwnIsDifferential(k);
    }
  }
  force_.resize(n_);
  f_nl_.resize(n_);
  scratch_.resize(n_);
  FindReducedRows();
}

bool IdaDae::Fail(const std::string& message) {
  message_ = message;
  return false;
}

DaeView IdaDae::View(size_t l, double t, const double* y, const double* yp) const {
  DaeView s;
  s.t = t;
  s.phase = excitation_.Phase(t);
  s.num_dofs = n_;
  const int own = layouts_[l].own_offset;
  const int num_own = model_.laws[l]->NumOwn();
  new (&s.x) Eigen::Map<const Eigen::VectorXd>(y, n_);
  new (&s.v) Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
  new (&s.xdot) Eigen::Map<const Eigen::VectorXd>(yp, n_);
  new (&s.a) Eigen::Map<const Eigen::VectorXd>(yp + n_, n_);
  new (&s.own) Eigen::Map<const Eigen::VectorXd>(y + own, num_own);
  new (&s.own_dot) Eigen::Map<const Eigen::VectorXd>(yp + own, num_own);
  return s;
}

void IdaDae::Forces(double t, const double* y, const double* yp) const {
  force_.setZero();
  excitation_.AddForce(t, force_);
  f_nl_.setZero();
  for (size_t l = 0; l < model_.laws.size(); ++l) {
    scratch_.setZero();
    model_.laws[l]->Force(layouts_[l], View(l, t, y, yp), scratch_);
    f_nl_ += scratch_;
  }
}

// Which momentum rows are differentiated: those of massless DOFs with a zero damping row on
// which a law's differential own unknown acts (∂F/∂own ≠ 0). Without such an unknown an
// undamped massless row is left alone: K x = f of a linear row is then refused as
// inconsistent (its index-2 velocity is not this reduction's business).
void IdaDae::FindReducedRows() {
  std::vector<bool> damped(n_, false);
  const Eigen::SparseMatrix<double>& damping = model_.model.damping;
  for (int k = 0; k < damping.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(damping, k); it; ++it) {
      if (it.value() != 0.0) damped[it.row()] = true;
    }
  }
  // The pattern of the laws' ∂F/∂y at a zero state (the momentum-row entries of own
  // unknowns do not depend on the state).
  const std::vector<double> zeros(size_, 0.0);
  Triplets entries;
  for (size_t l = 0; l < model_.laws.size(); ++l) {
    model_.laws[l]->Jacobian(layouts_[l], View(l, 0.0, zeros.data(), zeros.data()), 0.0, &entries);
  }
  reduced_index_.assign(n_, -1);
  for (const auto& e : entries) {
    const int dof = e.row() - n_;
    if (dof < 0 || dof >= n_ || e.value() == 0.0 || e.col() < 2 * n_ || e.col() >= q_ ||
        !differential_[e.col()] || !model_.massless[dof] || damped[dof]) {
      continue;
    }
    if (reduced_index_[dof] < 0) {
      reduced_index_[dof] = static_cast<int>(reduced_.size());
      reduced_.push_back(dof);
      reduced_own_columns_.push_back(-1);
    }
    // One own unknown per row to start from (distinct), for SolveOriginalRows at t = 0.
    int& column = reduced_own_columns_[reduced_index_[dof]];
    if (column < 0 && std::find(reduced_own_columns_.begin(), reduced_own_columns_.end(),
                                e.col()) == reduced_own_columns_.end()) {
      column = e.col();
    }
  }
  for (size_t i = 0; i < reduced_.size(); ++i) {
    reduced_x_columns_.push_back(reduced_[i]);
    // Rows sharing one own unknown (relative friction between two such DOFs): the others
    // start from their own x instead.
    if (reduced_own_columns_[i] < 0) reduced_own_columns_[i] = reduced_[i];
  }
  reduced_rows_.assign(size_, false);
  for (int dof : reduced_) reduced_rows_[n_ + dof] = true;
  j0_.resize(static_cast<Eigen::Index>(reduced_.size()), size_);
  rate_.resize(n_);
}

// j0_ = ∂F/∂y of the reduced DOFs' original momentum rows at (t, y): their K rows and the
// laws' momentum-row entries (the mass and damping rows are zero).
void IdaDae::OriginalRowJacobian(double t, const double* y, const double* yp) const {
  j0_.setZero();
  for (const auto& e : stiffness_) {
    const int i = reduced_index_[e.row() - n_];
    if (i >= 0) j0_(i, e.col()) += e.value();
  }
  law_scratch_.clear();
  for (size_t l = 0; l < model_.laws.size(); ++l) {
    model_.laws[l]->Jacobian(layouts_[l], View(l, t, y, yp), 0.0, &law_scratch_);
  }
  for (const auto& e : law_scratch_) {
    if (e.row() < n_ || e.row() >= 2 * n_) continue;
    const int i = reduced_index_[e.row() - n_];
    if (i >= 0) j0_(i, e.col()) += e.value();
  }
}

// F with every momentum row in its original form, then the reduced ones differentiated:
// Σ_j J0(d, j) ẏ_j − ḟ_d(t), exactly d/dt of the original row.
void IdaDae::Residual(double t, const double* y, const double* yp, double* r) const {
  OriginalResidual(t, y, yp, r);
  if (reduced_.empty()) return;
  OriginalRowJacobian(t, y, yp);
  rate_.setZero();
  excitation_.AddForceRate(t, rate_);
  const Eigen::Map<const Eigen::VectorXd> ydot(yp, size_);
  for (size_t i = 0; i < reduced_.size(); ++i) {
    const int dof = reduced_[i];
    r[n_ + dof] = j0_.row(static_cast<Eigen::Index>(i)).dot(ydot) - rate_(dof);
  }
}

void IdaDae::OriginalResidual(double t, const double* y, const double* yp, double* r) const {
  Eigen::Map<const Eigen::VectorXd> x(y, n_), v(y + n_, n_), xdot(yp, n_), a(yp + n_, n_);
  Eigen::Map<Eigen::VectorXd> res(r, size_);
  res.setZero();
  Forces(t, y, yp);
  res.head(n_) = xdot - v;
  res.segment(n_, n_) =
      model_.model.mass * a + model_.model.damping * v + model_.model.stiffness * x - force_;
  for (size_t l = 0; l < model_.laws.size(); ++l) {
    model_.laws[l]->Residual(layouts_[l], View(l, t, y, yp), res);
  }
  const double energy =
      0.5 * v.dot(model_.model.mass * v) + 0.5 * x.dot(model_.model.stiffness * x);
  res(q_) = yp[q_] - energy;
  res(q_ + 1) = yp[q_ + 1] - force_.dot(v);
  res(q_ + 2) = yp[q_ + 2] - v.dot(model_.model.damping * v);
  res(q_ + 3) = yp[q_ + 3] - f_nl_.dot(v);
}

// The quadrature rows are dense. A differentiated row's entries are cj·J0 (its ∂J0/∂y·ẏ part
// is left out: zero for laws linear in y within a mode, as friction, penalty contact and
// linear springs are; only the Newton rate suffers otherwise).
void IdaDae::Assemble(double t, const double* y, const double* yp, double cj, Triplets* out) const {
  out->clear();
  for (int i = 0; i < n_; ++i) {
    out->emplace_back(i, i, cj);
    out->emplace_back(i, n_ + i, -1.0);
  }
  out->insert(out->end(), stiffness_.begin(), stiffness_.end());
  out->insert(out->end(), damping_.begin(), damping_.end());
  for (const auto& e : mass_) out->emplace_back(e.row(), e.col(), cj * e.value());
  const size_t law_begin = out->size();
  for (size_t l = 0; l < model_.laws.size(); ++l) {
    model_.laws[l]->Jacobian(layouts_[l], View(l, t, y, yp), cj, out);
  }
  const size_t law_end = out->size();
  Eigen::Map<const Eigen::VectorXd> x(y, n_), v(y + n_, n_);
  Forces(t, y, yp);
  const Eigen::VectorXd energy_x = k_sym_ * x;
  const Eigen::VectorXd energy_v = m_sym_ * v;
  const Eigen::VectorXd damping_v = c_sym_ * v;
  for (int k = 0; k < kNumQuadratures; ++k) out->emplace_back(q_ + k, q_ + k, cj);
  for (int j = 0; j < n_; ++j) {
    out->emplace_back(q_, j, -energy_x(j));
    out->emplace_back(q_, n_ + j, -energy_v(j));
    out->emplace_back(q_ + 1, n_ + j, -force_(j));
    out->emplace_back(q_ + 2, n_ + j, -damping_v(j));
    out->emplace_back(q_ + 3, n_ + j, -f_nl_(j));
  }
  // ∂(f_nlᵀv)/∂y through f_nl: the laws' momentum-row entries weighted by v.
  for (size_t k = law_begin; k < law_end; ++k) {
    const Eigen::Triplet<double> e = (*out)[k];
    if (e.row() >= n_ && e.row() < 2 * n_) {
      out->emplace_back(q_ + 3, e.col(), -v(e.row() - n_) * e.value());
    }
  }
  // The laws' momentum-row entries do not depend on cj (they are forces), so the entries of
  // a reduced row so far are J0's: scale them.
  if (reduced_.empty()) return;
  for (size_t k = 0; k < law_end; ++k) {
    const Eigen::Triplet<double> e = (*out)[k];
    if (reduced_rows_[e.row()])
      (*out)[k] = Eigen::Triplet<double>(e.row(), e.col(), cj * e.value());
  }
}

void IdaDae::Roots(double t, const double* y, const double* yp, double* g) const {
  for (size_t l = 0; l < model_.laws.size(); ++l) {
    model_.laws[l]->Roots(layouts_[l], View(l, t, y, yp), g + root_offsets_[l]);
  }
}

bool IdaDae::Initialise(double t, double* y, double* yp) {
  for (size_t l = 0; l < model_.laws.size(); ++l) {
    model_.laws[l]->InitMode(layouts_[l], View(l, t, y, yp));
  }
  // The differential own unknowns start at zero: take them from the undifferentiated rows
  // (a sticking force from the start's displacements); a sliding one is snapped later.
  if (!reduced_.empty() && !SolveOriginalRows(t, reduced_own_columns_, y, yp)) return false;
  return SettleModes(t, y, yp);
}

// Newton on the reduced DOFs' original (undifferentiated) momentum rows for the unknowns
// y[columns] (one per reduced DOF), the rest held.
bool IdaDae::SolveOriginalRows(double t, const std::vector<int>& columns, double* y,
                               const double* yp) {
  const int m = static_cast<int>(reduced_.size());
  Eigen::VectorXd residual(size_), g(m);
  Eigen::MatrixXd slope(m, m);
  for (int iteration = 0; iteration < kProjectionIterations; ++iteration) {
    OriginalResidual(t, y, yp, residual.data());
    OriginalRowJacobian(t, y, yp);
    for (int i = 0; i < m; ++i) {
      g(i) = residual(n_ + reduced_[i]);
      for (int c = 0; c < m; ++c) slope(i, c) = columns[c] >= 0 ? j0_(i, columns[c]) : 0.0;
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(slope);
    if (!lu.isInvertible()) {
      std::ostringstream out;
      out << "no consistent state at t = " << t
          << ": the massless DOFs' rows cannot be solved for their unknowns (singular)";
      return Fail(out.str());
    }
    const Eigen::VectorXd step = lu.solve(-g);
    if (!step.allFinite()) return Fail("no consistent state: non-finite projection");
    double largest = 0.0;
    for (int c = 0; c < m; ++c) {
      y[columns[c]] += step(c);
      largest = std::max(largest, std::abs(step(c)) / (1.0 + std::abs(y[columns[c]])));
    }
    if (largest <= 1e-15) break;
  }
  return true;
}

// The laws snap the differential own unknowns their modes fix (a sliding force to exactly
// ∓μN), so that they do not carry a root's location error into the mode; then, with reduced
// rows, Newton on x of the reduced DOFs brings the state back onto the undifferentiated rows
// (their drift under the differentiated ones).
bool IdaDae::SnapAndProject(double t, double* y, const double* yp) {
  for (size_t l = 0; l < model_.laws.size(); ++l) {
    const int num_own = model_.laws[l]->NumOwn();
    if (num_own == 0) continue;
    Eigen::Map<Eigen::VectorXd> own(y + layouts_[l].own_offset, num_own);
    model_.laws[l]->SnapOwn(layouts_[l], View(l, t, y, yp), own);
  }
  return reduced_.empty() || SolveOriginalRows(t, reduced_x_columns_, y, yp);
}

// F is affine in ẏ and the algebraic unknowns, so one Newton step solves it; a second checks.
bool IdaDae::MakeConsistent(double t, double* y, double* yp) {
  if (!SnapAndProject(t, y, yp)) return false;
  Eigen::VectorXd residual(size_);
  Triplets slope, value;
  for (int iteration = 0; iteration < kConsistentIterations; ++iteration) {
    Residual(t, y, yp, residual.data());
    Assemble(t, y, yp, 0.0, &value);
    Assemble(t, y, yp, 1.0, &slope);
    Triplets entries;
    for (const auto& e : value) {
      if (!differential_[e.col()]) entries.push_back(e);
    }
    for (const auto& e : slope) {
      if (differential_[e.col()]) entries.push_back(e);
    }
    for (const auto& e : value) {  // slope − value = ∂F/∂ẏ
      if (differential_[e.col()]) entries.emplace_back(e.row(), e.col(), -e.value());
    }
    Eigen::SparseMatrix<double> matrix(size_, size_);
    matrix.setFromTriplets(entries.begin(), entries.end());
    matrix.makeCompressed();
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.compute(matrix);
    if (lu.info() != Eigen::Success) {
      std::ostringstream out;
      out << "no consistent state at t = " << t << ": singular matrix (" << lu.lastErrorMessage()
          << ")";
      return Fail(out.str());
    }
    const Eigen::VectorXd step = lu.solve(-residual);
    if (!step.allFinite()) return Fail("no consistent state: non-finite solution");
    double largest = 0.0;
    for (int j = 0; j < size_; ++j) {
      double& unknown = differential_[j] ? yp[j] : y[j];
      unknown += step(j);
      largest = std::max(largest, std::abs(step(j)) / (1.0 + std::abs(unknown)));
    }
    if (largest <= 1e-13) break;
  }
  return true;
}

bool IdaDae::SettleModes(double t, double* y, double* yp) {
  for (int round = 0; round < kMaxModeRounds; ++round) {
    if (!MakeConsistent(t, y, yp)) return false;
    bool admissible = true;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      if (!model_.laws[l]->Admissible(layouts_[l], View(l, t, y, yp))) admissible = false;
    }
    if (admissible) return true;
  }
  std::ostringstream out;
  out << "mode iteration did not settle in " << kMaxModeRounds << " rounds at t = " << t;
  return Fail(out.str());
}

}  // namespace nfrc
