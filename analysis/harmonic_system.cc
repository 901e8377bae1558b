#include "analysis/harmonic_system.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "continuation/dense_lu.h"
#include "core/errors.h"

namespace nfrc {
namespace {

std::vector<int> RetainedDofs(const std::vector<std::unique_ptr<Nonlinearity>>& laws,
                              const std::vector<int>& output_dofs,
                              const std::vector<ForcingTerm>& forcing) {
  std::vector<int> retained;
  auto add = [&](int dof) {
    if (std::find(retained.begin(), retained.end(), dof) == retained.end()) {
      retained.push_back(dof);
    }
  };
  for (const auto& law : laws) {
    for (int dof : law->Dofs()) add(dof);
  }
  // Without laws the problem is linear: keep the outputs (or the forced DOFs) as unknowns.
  // With laws, outputs are recovered after each solve rather than carried as unknowns.
  if (retained.empty()) {
    for (int dof : output_dofs) add(dof);
  }
  if (retained.empty()) {
    for (const ForcingTerm& term : forcing) add(term.dof);
  }
  if (retained.empty()) add(0);
  return retained;
}

}  // namespace

HarmonicSystem::HarmonicSystem(ModelDefinition model, HarmonicSet set,
                               std::vector<std::unique_ptr<Nonlinearity>> laws,
                               std::vector<int> output_dofs, Condensation::Method method)
    : model_(model.model),
      fourier_(set),
      laws_(std::move(laws)),
      retained_(RetainedDofs(laws_, output_dofs, model.forcing)),
      condensation_(std::move(model.model), retained_, set, std::move(model.forcing), method),
      cached_omega_(std::numeric_limits<double>::quiet_NaN()) {
  const int nc = set.NumCoefficients();
  num_displacement_unknowns_ = static_cast<int>(retained_.size()) * nc;
  int offset = num_displacement_unknowns_;
  for (const auto& law : laws_) {
    NonlinearityContext ctx;
    ctx.fourier = &fourier_;
    ctx.condensation = &condensation_;
    for (int dof : law->Dofs()) {
      ctx.local_dofs.push_back(
          static_cast<int>(std::find(retained_.begin(), retained_.end(), dof) - retained_.begin()));
    }
    ctx.own_offset = offset;
    offset += law->NumOwnUnknowns(set);
    contexts_.push_back(ctx);
  }
  num_unknowns_ = offset;

  // Obstacles: one per DOF, and no other law may act on an obstacle's DOF, whose unknown is
  // then a relative displacement.
  std::vector<double> compliance(retained_.size(), 0.0);
  bool any = false;
  for (size_t i = 0; i < laws_.size(); ++i) {
    const std::vector<double> law_compliance = laws_[i]->ObstacleCompliance();
    for (size_t j = 0; j < law_compliance.size(); ++j) {
      if (law_compliance[j] == 0.0) continue;
      const int local = contexts_[i].local_dofs[j];
      for (size_t other = 0; other < laws_.size(); ++other) {
        if (other == i) continue;
        const auto& dofs = contexts_[other].local_dofs;
        if (std::find(dofs.begin(), dofs.end(), local) != dofs.end()) {
          throw InputError("nonlinearities[" + std::to_string(other) +
                           "]: acts on the DOF that nonlinearities[" + std::to_string(i) +
                           "] backs with a flexible obstacle; an obstacle DOF takes one law");
        }
      }
      compliance[local] = law_compliance[j];
      any = true;
    }
  }
  if (any) {
    condensation_.SetObstacleCompliance(compliance);
    has_obstacles_ = true;
  }
}

void HarmonicSystem::BindLaws() {
  for (size_t i = 0; i < laws_.size(); ++i) {
    try {
      laws_[i]->Bind(contexts_[i]);
    } catch (const std::invalid_argument& error) {
      throw InputError("nonlinearities[" + std::to_string(i) + "]." + error.what());
    }
  }
  bound_ = true;
}

void HarmonicSystem::MoveTo(double omega) {
  // The condensation may have moved alone (Recover's callers need no real forms).
  if (omega == cached_omega_ && condensation_.omega() == omega) return;
  condensation_.Update(omega);
  if (!bound_) BindLaws();
  const int n = condensation_.num_unknowns();
  if (z_.rows() != n) {
    // Zeroed once: WriteRealOperator refreshes only the entries the layout can fill.
    z_.setZero(n, n);
    dz_.setZero(n, n);
  }
  condensation_.WriteRealOperator(false, z_);
  condensation_.WriteRealOperator(true, dz_);
  f_ = condensation_.RealForcing();
  df_ = condensation_.RealForcingDerivative();
  cached_omega_ = omega;
}

void HarmonicSystem::ApplyOperator(bool derivative, const Eigen::Ref<const Eigen::VectorXd>& x,
                                   Eigen::Ref<Eigen::VectorXd> out) const {
  // One retained DOF (a friction contact): its blocks alone, the same bits as the dense
  // product (see ApplyRealOperator), which passed over nx² entries, mostly zeros. With more,
  // the dense product: its blocking fixes the order of each row's sum, which the traces keep.
  if (condensation_.num_retained() == 1) {
    condensation_.ApplyRealOperator(derivative, x, out);
  } else {
    out.noalias() = (derivative ? dz_ : z_) * x;
  }
}

bool HarmonicSystem::Prepare(double omega) {
  try {
    MoveTo(omega);
    return true;
  } catch (const std::runtime_error& error) {
    last_error_ = error.what();  // as in Evaluate: a singular condensed operator
    return false;
  }
}

bool HarmonicSystem::Evaluate(const Eigen::VectorXd& y, double omega, Eigen::VectorXd* residual,
                              Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_omega) {
  if (!Prepare(omega)) return false;
  try {
    const int nx = num_displacement_unknowns_;
    const auto x = y.head(nx);
    residual->setZero(num_unknowns_);
    ApplyOperator(false, x, residual->head(nx));
    residual->head(nx) -= f_;
    if (jacobian_y != nullptr) {
      // z_'s entries outside the layout's blocks are zero: one fill, then the blocks (not a
      // copy of z_, most of which is zeros when harmonics do not couple).
      jacobian_y->setZero(num_unknowns_, num_unknowns_);
      condensation_.WriteRealOperator(false, jacobian_y->topLeftCorner(nx, nx));
    }
    if (jacobian_omega != nullptr) {
      jacobian_omega->setZero(num_unknowns_);
      ApplyOperator(true, x, jacobian_omega->head(nx));
      jacobian_omega->head(nx) -= df_;
    }
    for (size_t i = 0; i < laws_.size(); ++i) {
      laws_[i]->Evaluate(contexts_[i], y, omega, *residual, jacobian_y, jacobian_omega);
    }
    // An overflow (absurd coefficients, a diverging iterate) is a numerical failure with a
    // cause, not a silent one.
    const char* what = !AllFinite(*residual)                              ? "residual"
                       : jacobian_y != nullptr && !AllFinite(*jacobian_y) ? "Jacobian"
                       : jacobian_omega != nullptr && !AllFinite(*jacobian_omega)
                           ? "omega-derivative"
                           : nullptr;
    if (what != nullptr) {
      last_error_ = std::string(what) + " is not finite at omega = " + std::to_string(omega) +
                    " (overflow: check the magnitudes of the case's coefficients)";
      return false;
    }
    return true;
  } catch (const std::runtime_error& error) {
    // Numerical failures only (a singular condensed operator): the step is cut and retried.
    // Input errors and broken invariants (logic_error) propagate to the caller.
    last_error_ = error.what();
    return false;
  }
}

std::vector<std::vector<int>> HarmonicSystem::EliminationBlocks() const {
  if (num_unknowns_ == num_displacement_unknowns_) return {};
  for (const auto& law : laws_) {
    if (law->WritesDisplacementBlock()) return {};
  }
  const HarmonicSet& set = harmonic_set();
  const int nc = set.NumCoefficients();
  const int nr = num_displacement_unknowns_ / nc;
  std::vector<std::vector<int>> blocks;
  for (int p = 0; p < set.num_harmonics(); ++p) {
    std::vector<int> block;
    for (int r = 0; r < nr; ++r) {
      block.push_back(r * nc + set.CosIndex(p));
      if (set.harmonics()[p] != 0) block.push_back(r * nc + set.SinIndex(p));
    }
    blocks.push_back(std::move(block));
  }
  return blocks;
}

double HarmonicSystem::ResidualNoise(const Eigen::VectorXd& y, double omega) {
  try {
    MoveTo(omega);
    const Condensation::Rounding rounding = condensation_.EstimateRounding();
    const HarmonicSet& set = harmonic_set();
    const int nc = set.NumCoefficients();
    const int nr = condensation_.num_retained();
    double sum = 0.0;
    for (int p = 0; p < set.num_harmonics(); ++p) {
      const bool constant = set.harmonics()[p] == 0;
      Eigen::VectorXd amplitude(nr);  // |X| = √(a² + b²) of each retained DOF
      for (int j = 0; j < nr; ++j) {
        const double a = y(j * nc + set.CosIndex(p));
        const double b = constant ? 0.0 : y(j * nc + set.SinIndex(p));
        amplitude(j) = std::hypot(a, b);
      }
      sum += (rounding.z[p] * amplitude + rounding.f[p]).squaredNorm();
    }
    return std::sqrt(sum);
  } catch (const std::runtime_error&) {
    return 0.0;  // no estimate where the operator cannot be formed
  }
}

std::vector<int> HarmonicSystem::ScaleGroups() const {
  std::vector<int> groups(num_unknowns_, 0);
  for (size_t i = 0; i < laws_.size(); ++i) {
    const int count = laws_[i]->NumOwnUnknowns(harmonic_set());
    const int group = laws_[i]->OwnUnknownsScaleLikeDisplacements() ? 0 : static_cast<int>(i) + 1;
    std::fill_n(groups.begin() + contexts_[i].own_offset, count, group);
  }
  return groups;
}

void HarmonicSystem::set_own_step_weight(double weight) {
  if (!(weight >= 0.0 && weight <= 1.0)) {
    throw std::invalid_argument("own_step_weight: must lie in [0, 1]");
  }
  own_step_weight_ = weight;
}

Eigen::VectorXd HarmonicSystem::StepWeights() const {
  Eigen::VectorXd weights = Eigen::VectorXd::Constant(num_unknowns_, own_step_weight_);
  weights.head(num_displacement_unknowns_).setOnes();
  return weights;
}

Eigen::VectorXd HarmonicSystem::InitialGuess(double omega) {
  try {
    MoveTo(omega);
  } catch (const std::runtime_error& error) {
    throw InputError(std::string("model: the linear part cannot be condensed at omega_start: ") +
                     error.what());
  }
  // Partial pivoting sees a singular Z as a FullPivLU would (a DOF without stiffness or mass
  // leaves a pivot at rounding level; the threshold is FullPivLU's default, ε·n·max pivot)
  // and is blocked (LAPACK's at 1 280 unknowns in Z, N_φ = 640: DenseLu).
  const DenseLu lu(z_);
  if (!PivotsAbove(lu, std::numeric_limits<double>::epsilon() * static_cast<double>(z_.rows()))) {
    throw InputError("model: the linear dynamic stiffness is singular at omega_start = " +
                     std::to_string(omega) +
                     " (a DOF without stiffness or mass, or a rigid-body mode with harmonic 0?)");
  }
  Eigen::VectorXd y = Eigen::VectorXd::Zero(num_unknowns_);
  y.head(num_displacement_unknowns_) = lu.Solve(f_);
  for (size_t i = 0; i < laws_.size(); ++i) {
    const int count = laws_[i]->NumOwnUnknowns(harmonic_set());
    if (count > 0) {
      laws_[i]->InitialOwnUnknowns(contexts_[i], y, omega,
                                   y.segment(contexts_[i].own_offset, count));
    }
  }
  return y;
}

const Eigen::MatrixXd& HarmonicSystem::LinearOperator(double omega) {
  MoveTo(omega);
  return z_;
}

const Eigen::VectorXd& HarmonicSystem::LinearForcing(double omega) {
  MoveTo(omega);
  return f_;
}

Eigen::VectorXd HarmonicSystem::DofCoefficients(const Eigen::VectorXd& y, double omega, int dof) {
  const int nc = harmonic_set().NumCoefficients();
  const auto found = std::find(retained_.begin(), retained_.end(), dof);
  // With obstacles the retained unknowns are relative displacements: recover absolute ones.
  if (found != retained_.end() && !has_obstacles_) {
    return y.segment(static_cast<int>(found - retained_.begin()) * nc, nc);
  }
  condensation_.Update(omega);
  return condensation_.Recover(y.head(num_displacement_unknowns_)).row(dof).transpose();
}

Eigen::MatrixXd HarmonicSystem::AllDofCoefficients(const Eigen::VectorXd& y, double omega) {
  condensation_.Update(omega);
  return condensation_.Recover(y.head(num_displacement_unknowns_));
}

}  // namespace nfrc
