#include "validation/central_difference_scheme.h"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>
#include <utility>

#include "core/lemke.h"

namespace nfrc {
namespace {

// Dense LU of the step matrix up to this many DOFs, sparse LU beyond.
constexpr int kDenseLimit = 200;
// Reciprocal condition number below which the step matrix counts as singular.
constexpr double kSingularRcond = 1e-14;

// Adds the contact force λ (N) as the residual sees it: +nλ on the DOF, −nλ on the other.
void AddContactForce(const ContactGeometry& contact, double lambda, Eigen::VectorXd* force) {
  (*force)(contact.dof) += contact.direction * lambda;
  if (contact.other >= 0) (*force)(contact.other) -= contact.direction * lambda;
}

}  // namespace

double InitialGap(const ContactGeometry& contact, double phase) {
  double gap = contact.gap;
  for (const auto& h : contact.gap_harmonics) {
    gap += h.cos * std::cos(h.harmonic * phase) + h.sin * std::sin(h.harmonic * phase);
  }
  return gap;
}

double Approach(const ContactGeometry& contact, const Eigen::VectorXd& x) {
  double relative = x(contact.dof);
  if (contact.other >= 0) relative -= x(contact.other);
  return contact.direction * relative;
}

// LU factorisation of a square sparse matrix, dense for small sizes.
class CentralDifferenceScheme::LuSolver {
 public:
  bool Factorize(const Eigen::SparseMatrix<double>& a) {
    dense_ = a.rows() <= kDenseLimit;
    if (dense_) {
      const Eigen::MatrixXd dense = Eigen::MatrixXd(a);
      dense_lu_.compute(dense);
      // The determinant would overflow for large n with M/h² entries; the condition estimate
      // does not.
      const double rcond = dense_lu_.rcond();
      return std::isfinite(rcond) && rcond > kSingularRcond;
    }
    sparse_ = a;
    sparse_.makeCompressed();
    sparse_lu_ = std::make_unique<Eigen::SparseLU<Eigen::SparseMatrix<double>>>();
    sparse_lu_->compute(sparse_);
    return sparse_lu_->info() == Eigen::Success;
  }
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const {
    if (dense_) return dense_lu_.solve(b);
    return sparse_lu_->solve(b);
  }

 private:
  bool dense_ = true;
  Eigen::PartialPivLU<Eigen::MatrixXd> dense_lu_;
  Eigen::SparseMatrix<double> sparse_;
  std::unique_ptr<Eigen::SparseLU<Eigen::SparseMatrix<double>>> sparse_lu_;
};

CentralDifferenceScheme::CentralDifferenceScheme(const TransientModel& model, double h)
    : model_(model), h_(h), step_lu_(std::make_unique<LuSolver>()) {
  n_ = model.num_dofs();
  const auto& m = model.model.mass;
  const auto& c = model.model.damping;
  Eigen::SparseMatrix<double> a = m / (h * h) + c / (2.0 * h);
  ok_ = step_lu_->Factorize(a);
  const int nc = static_cast<int>(model.rigid_contacts.size());
  ainv_gt_.resize(n_, nc);
  for (int k = 0; k < nc; ++k) {
    Eigen::VectorXd column = Eigen::VectorXd::Zero(n_);
    AddContactForce(model.rigid_contacts[k], 1.0, &column);
    ainv_gt_.col(k) = step_lu_->Solve(column);
  }
  w_.resize(nc, nc);
  for (int j = 0; j < nc; ++j) {
    for (int i = 0; i < nc; ++i) {
      // Gap rows are −n(x_dof − x_other), so the gap grows by +G A⁻¹Gᵀλ.
      w_(i, j) = Approach(model.rigid_contacts[i], ainv_gt_.col(j));
    }
  }
  f_.setZero(n_);
  f_nl_.setZero(n_);
  force_laws_.setZero(n_);
  lambda_.setZero(nc);
  gap_hat_.setZero(nc);
}

CentralDifferenceScheme::~CentralDifferenceScheme() = default;

bool CentralDifferenceScheme::Start(const Excitation& excitation, const Eigen::VectorXd& x0,
                                    const Eigen::VectorXd& v0, std::string* message) {
  if (!ok_) {
    *message = "the step matrix M/h² + C/2h is singular";
    return false;
  }
  const auto& model = model_.model;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_);
  excitation.AddForce(0.0, rhs);
  Eigen::VectorXd f_nl = Eigen::VectorXd::Zero(n_);
  AddExplicitForces(excitation.Phase(0.0), x0, v0, &f_nl);
  rhs -= model.damping * v0 + model.stiffness * x0 + f_nl;
  LuSolver mass_lu;
  if (!mass_lu.Factorize(model.mass)) {
    *message = "the mass matrix could not be factorised";
    return false;
  }
  const Eigen::VectorXd a0 = mass_lu.Solve(rhs);
  x_ = x0;
  x_prev_ = x0 - h_ * v0 + 0.5 * h_ * h_ * a0;
  return true;
}

bool CentralDifferenceScheme::Step(const Excitation& excitation, long n,
                                   CentralDifferenceNode* node, std::string* message) {
  const auto& model = model_.model;
  const double t = static_cast<double>(n) * h_;
  const double phase = excitation.Phase(t);
  f_.setZero();
  excitation.AddForce(t, f_);
  // Explicit laws see x_n and the half-step velocity (x_n − x_{n−1})/h, which is known.
  v_half_ = (x_ - x_prev_) / h_;
  f_nl_.setZero();
  AddExplicitForces(phase, x_, v_half_, &f_nl_);
  rhs_ = f_ - model.stiffness * x_ - f_nl_ + model.mass * ((2.0 * x_ - x_prev_) / (h_ * h_)) +
         model.damping * (x_prev_ / (2.0 * h_));
  x_next_ = step_lu_->Solve(rhs_);

  const int nc = static_cast<int>(model_.rigid_contacts.size());
  lambda_.setZero();
  if (nc > 0) {
    const double next_phase = excitation.Phase(t + h_);
    bool any_penetration = false;
    for (int c = 0; c < nc; ++c) {
      const ContactGeometry& contact = model_.rigid_contacts[c];
      gap_hat_(c) = InitialGap(contact, next_phase) - Approach(contact, x_next_);
      any_penetration = any_penetration || gap_hat_(c) < 0.0;
    }
    if (any_penetration && !SolveMultipliers(message)) return false;
    if (any_penetration) x_next_ -= ainv_gt_ * lambda_;
  }
  if (!x_next_.allFinite()) {
    std::ostringstream out;
    out << "the displacement is not finite at t = " << t + h_;
    *message = out.str();
    return false;
  }

  node->t = t;
  node->phase = phase;
  node->x = x_;
  node->v = (x_next_ - x_prev_) / (2.0 * h_);
  node->lambda = lambda_;
  node->energy = 0.5 * node->v.dot(model.mass * node->v) + 0.5 * x_.dot(model.stiffness * x_);
  force_laws_ = f_nl_;
  for (int c = 0; c < nc; ++c) AddContactForce(model_.rigid_contacts[c], lambda_(c), &force_laws_);
  node->power_input = f_.dot(node->v);
  node->power_damping = node->v.dot(model.damping * node->v);
  node->power_laws = force_laws_.dot(node->v);
  std::swap(x_prev_, x_);
  std::swap(x_, x_next_);
  return true;
}

void CentralDifferenceScheme::AddExplicitForces(double phase, const Eigen::VectorXd& x,
                                                const Eigen::VectorXd& v,
                                                Eigen::VectorXd* f_nl) const {
  for (const auto& law : model_.laws) {
    const bool explicit_force = law->ExplicitForce(phase, x, v, *f_nl);
    assert(explicit_force && "laws were checked by the stepper's constructor");
    (void)explicit_force;
  }
}

bool CentralDifferenceScheme::SolveMultipliers(std::string* message) {
  if (gap_hat_.size() == 1) {
    lambda_(0) = std::max(0.0, -gap_hat_(0) / w_(0, 0));
    return true;
  }
  LemkeOptions options;
  options.warm_basis = warm_basis_;
  const LemkeResult result = SolveLcp(w_, gap_hat_, options);
  if (!result.ok()) {
    *message =
        "contact multipliers: Lemke " + ToString(result.status) + " (" + result.message + ")";
    return false;
  }
  lambda_ = result.z.cwiseMax(0.0);
  warm_basis_ = result.basic_z;
  return true;
}

}  // namespace nfrc
