#include "validation/central_difference_stepper.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "core/errors.h"
#include "validation/time_law_check.h"

namespace nfrc {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// A time within this many steps of a node is that node (period boundaries computed as p·T
// differ from the node times p·(T/steps)·steps by round-off).
constexpr double kNodeSnap = 1e-6;
// The wall clock is read every this many steps.
constexpr long kClockInterval = 1024;

}  // namespace

CentralDifferenceStepper::CentralDifferenceStepper(const TransientModel& model,
                                                   const TransientOptions& options)
    : model_(model), options_(options) {
  const int n = model_.num_dofs();
  if (n == 0) throw InputError("model: the explicit scheme needs at least one DOF");
  const std::string mass_error =
      "model.M: the explicit scheme needs a positive definite mass matrix";
  for (bool massless : model_.massless) {
    if (massless) throw InputError(mass_error);
  }
  Eigen::VectorXd scratch_x = Eigen::VectorXd::Zero(n), scratch_f = Eigen::VectorXd::Zero(n);
  for (size_t i = 0; i < model_.laws.size(); ++i) {
    if (!model_.laws[i]->ExplicitForce(0.0, scratch_x, scratch_x, scratch_f)) {
      const std::string path = i < model_.law_paths.size()
                                   ? model_.law_paths[i]
                                   : "nonlinearities[" + std::to_string(i) + "]";
      throw InputError(path + ": the " + model_.laws[i]->type() +
                       " law has no explicit force; the central-difference scheme cannot use it");
    }
  }
  for ([[maybe_unused]] const ContactGeometry& c : model_.rigid_contacts) {
    assert(c.dof >= 0 && c.dof < n && c.other < n);
  }

  // ω_max² is the largest eigenvalue of (K + the laws' stiffness bounds, M), symmetric parts.
  const Eigen::MatrixXd mass = Eigen::MatrixXd(model_.model.mass);
  const Eigen::MatrixXd mass_sym = 0.5 * (mass + mass.transpose());
  if (mass_sym.llt().info() != Eigen::Success) throw InputError(mass_error);
  const Eigen::MatrixXd stiffness = Eigen::MatrixXd(model_.model.stiffness);
  Eigen::MatrixXd stiffness_sym = 0.5 * (stiffness + stiffness.transpose());
  for (const auto& law : model_.laws) {
    for (const auto& [dof, k] : law->StiffnessBound()) stiffness_sym(dof, dof) += k;
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eigen(stiffness_sym, mass_sym,
                                                                  Eigen::EigenvaluesOnly);
  if (eigen.info() != Eigen::Success) throw InputError(mass_error);
  omega_max_ = std::sqrt(std::max(0.0, eigen.eigenvalues().maxCoeff()));
}

CentralDifferenceStepper::~CentralDifferenceStepper() = default;

double CentralDifferenceStepper::StepFor(double omega, int samples) const {
  if (!(omega > 0.0) || !std::isfinite(omega)) throw InputError("omega: must be positive");
  const double period = kTwoPi / omega;
  // Without stiffness there is no stability limit: one step per recorded sample.
  if (omega_max_ <= 0.0) return period / samples;
  const double largest = options_.explicit_step_fraction * 2.0 / omega_max_;
  const double steps = std::max(1.0, std::ceil(period / largest * (1.0 - 1e-12)));
  return period / steps;
}

bool CentralDifferenceStepper::Start(const StepperStart& start) {
  excitation_ = *start.excitation;
  deadline_ = start.deadline;
  statistics_ = TransientStatistics();
  message_.clear();
  if (excitation_.chirp) {
    const double omega_high = std::max(excitation_.omega, excitation_.omega_end);
    double largest = kTwoPi / (omega_high * start.samples_per_cycle);
    if (omega_max_ > 0.0) {
      largest = std::min(largest, options_.explicit_step_fraction * 2.0 / omega_max_);
    }
    const double steps = std::max(1.0, std::ceil(excitation_.duration / largest));
    h_ = excitation_.duration / steps;
  } else {
    h_ = StepFor(excitation_.omega, start.samples_per_cycle);
  }
  scheme_ = std::make_unique<CentralDifferenceScheme>(model_, h_);
  t_ = 0.0;
  if (!scheme_->Start(excitation_, start.x, start.v, &message_)) return false;
  if (!scheme_->Step(excitation_, 0, &current_, &message_)) return false;
  statistics_.steps = 1;
  next_ = 1;
  previous_ = current_;
  theta_ = 1.0;
  x_ = current_.x;
  v_ = current_.v;
  to_current_ = StepperQuadratures();
  segment_end_ = std::numeric_limits<double>::infinity();
  logs_.clear();
  for (int c = 0; c < static_cast<int>(model_.rigid_contacts.size()); ++c) {
    logs_.push_back({"rigid_contact", "contact", current_.InContact(c), {}});
  }
  for (const auto& law : model_.laws) logs_.push_back({law->type(), "", false, {}});
  return true;
}

bool CentralDifferenceStepper::StepOnce() {
  // The new node overwrites the oldest one's storage.
  if (!scheme_->Step(excitation_, next_, &previous_, &message_)) return false;
  std::swap(previous_, current_);
  ++next_;
  ++statistics_.steps;
  const CentralDifferenceNode& a = previous_;
  const CentralDifferenceNode& b = current_;
  const double h = b.t - a.t;
  to_current_.energy += 0.5 * h * (a.energy + b.energy);
  to_current_.work_input += 0.5 * h * (a.power_input + b.power_input);
  to_current_.work_damping += 0.5 * h * (a.power_damping + b.power_damping);
  to_current_.work_laws += 0.5 * h * (a.power_laws + b.power_laws);
  for (int c = 0; c < static_cast<int>(model_.rigid_contacts.size()); ++c) {
    if (a.InContact(c) == b.InContact(c)) continue;
    ++statistics_.events;
    // A switch at the segment's end node belongs to the next segment.
    if (b.t < segment_end_ - kNodeSnap * h_) logs_[c].changes.push_back({b.t, b.InContact(c)});
  }
  return true;
}

StepOutcome CentralDifferenceStepper::AdvanceTo(double t) {
  const double snap = kNodeSnap * h_;
  for (long count = 1; current_.t < t - snap; ++count) {
    if (!StepOnce()) return StepOutcome::kFailed;
    if (count % kClockInterval == 0 && Clock::now() > deadline_) {
      t_ = current_.t;
      theta_ = 1.0;
      x_ = current_.x;
      v_ = current_.v;
      return StepOutcome::kOutOfTime;
    }
  }
  t_ = t;
  if (t >= current_.t - snap) {
    theta_ = 1.0;
    x_ = current_.x;
    v_ = current_.v;
  } else {
    theta_ = (t - previous_.t) / (current_.t - previous_.t);
    x_ = (1.0 - theta_) * previous_.x + theta_ * current_.x;
    v_ = (1.0 - theta_) * previous_.v + theta_ * current_.v;
  }
  return StepOutcome::kOk;
}

bool CentralDifferenceStepper::BeginSegment(double t_end) {
  segment_end_ = t_end;
  // Between nodes, the phase is the last node's; the next node's switch, if any, is ahead.
  const CentralDifferenceNode& here = theta_ < 1.0 ? previous_ : current_;
  for (int c = 0; c < static_cast<int>(model_.rigid_contacts.size()); ++c) {
    logs_[c].in_phase_at_start = here.InContact(c);
    logs_[c].changes.clear();
    if (theta_ < 1.0 && here.InContact(c) != current_.InContact(c)) {
      logs_[c].changes.push_back({current_.t, current_.InContact(c)});
    }
  }
  return true;
}

StepperQuadratures CentralDifferenceStepper::Remainder() const {
  StepperQuadratures r;
  if (theta_ >= 1.0) return r;
  const CentralDifferenceNode& a = previous_;
  const CentralDifferenceNode& b = current_;
  const double w = 0.5 * (b.t - t_);
  auto at_t = [&](double value_a, double value_b) {
    return (1.0 - theta_) * value_a + theta_ * value_b;
  };
  r.energy = w * (at_t(a.energy, b.energy) + b.energy);
  r.work_input = w * (at_t(a.power_input, b.power_input) + b.power_input);
  r.work_damping = w * (at_t(a.power_damping, b.power_damping) + b.power_damping);
  r.work_laws = w * (at_t(a.power_laws, b.power_laws) + b.power_laws);
  return r;
}

StepperQuadratures CentralDifferenceStepper::Quadratures() const {
  const StepperQuadratures r = Remainder();
  return {to_current_.energy - r.energy, to_current_.work_input - r.work_input,
          to_current_.work_damping - r.work_damping, to_current_.work_laws - r.work_laws};
}

bool CentralDifferenceStepper::ResetQuadratures() {
  to_current_ = Remainder();
  return true;
}

LawSignalValues CentralDifferenceStepper::Signals() const {
  const int n = model_.num_dofs();
  const double phase = excitation_.Phase(t_);
  LawSignalValues signals;
  for (int c = 0; c < static_cast<int>(model_.rigid_contacts.size()); ++c) {
    const ContactGeometry& contact = model_.rigid_contacts[c];
    const double lambda = (1.0 - theta_) * previous_.lambda(c) + theta_ * current_.lambda(c);
    signals.push_back(
        {{"gap", InitialGap(contact, phase) - Approach(contact, x_)}, {"force", lambda}});
  }
  if (model_.laws.empty()) return signals;
  Eigen::VectorXd y(2 * n), yp = Eigen::VectorXd::Zero(2 * n);
  y << x_, v_;
  yp.head(n) = v_;
  TimeLawLayout layout;
  layout.num_dofs = n;
  layout.own_offset = 2 * n;
  for (const auto& law : model_.laws) {
    // The scheme keeps no modes; a law's signals may depend on its mode (a penalty contact
    // reports its force only when closed), so the mode is first set from the state.
    const DaeView view = MakeDaeView(*law, layout, t_, phase, y, yp);
    law->InitMode(layout, view);
    signals.push_back(law->Signals(layout, view));
  }
  return signals;
}

}  // namespace nfrc
