#include "validation/contact_time_law.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace nfrc {

ContactTimeLaw::ContactTimeLaw(std::string type, ContactGeometry geometry, double stiffness)
    : type_(std::move(type)), geometry_(std::move(geometry)), stiffness_(stiffness) {
  if (!(stiffness_ > 0.0) || !std::isfinite(stiffness_)) {
    throw std::invalid_argument("contact: obstacle stiffness must be finite and > 0");
  }
  if (geometry_.dof < 0 || geometry_.dof == geometry_.other) {
    throw std::invalid_argument("contact: bad dof/other");
  }
}

namespace {

// g = g0(φ) − n (x_dof − x_other), on any vector expression (no copy of a DaeView's map).
double GapOf(const ContactGeometry& geometry, double phase,
             const Eigen::Ref<const Eigen::VectorXd>& x) {
  double g0 = geometry.gap;
  for (const auto& h : geometry.gap_harmonics) {
    g0 += h.cos * std::cos(h.harmonic * phase) + h.sin * std::sin(h.harmonic * phase);
  }
  const double relative = x(geometry.dof) - (geometry.other >= 0 ? x(geometry.other) : 0.0);
  return g0 - geometry.direction * relative;
}

}  // namespace

double ContactTimeLaw::Gap(double phase, const Eigen::VectorXd& x) const {
  return GapOf(geometry_, phase, x);
}

void ContactTimeLaw::Residual(const TimeLawLayout& layout, const DaeView& s,
                              Eigen::Ref<Eigen::VectorXd> residual) const {
  if (!closed_) return;
  // Closed: λ = −k g without the max, so the residual is smooth within the mode.
  const double lambda = -stiffness_ * GapOf(geometry_, s.phase, s.x);
  residual(layout.Momentum(geometry_.dof)) += geometry_.direction * lambda;
  if (geometry_.other >= 0)
    residual(layout.Momentum(geometry_.other)) -= geometry_.direction * lambda;
}

void ContactTimeLaw::Jacobian(const TimeLawLayout& layout, const DaeView& /*s*/, double /*cj*/,
                              std::vector<Eigen::Triplet<double>>* entries) const {
  if (!closed_) return;
  // ∂(n λ)/∂x_dof = n·k·n = k since n² = 1.
  const int dof = geometry_.dof;
  const int other = geometry_.other;
  entries->emplace_back(layout.Momentum(dof), layout.X(dof), stiffness_);
  if (other < 0) return;
  entries->emplace_back(layout.Momentum(dof), layout.X(other), -stiffness_);
  entries->emplace_back(layout.Momentum(other), layout.X(dof), -stiffness_);
  entries->emplace_back(layout.Momentum(other), layout.X(other), stiffness_);
}

void ContactTimeLaw::Roots(const TimeLawLayout& /*layout*/, const DaeView& s, double* g) const {
  g[0] = GapOf(geometry_, s.phase, s.x);
}

void ContactTimeLaw::InitMode(const TimeLawLayout& /*layout*/, const DaeView& s) {
  closed_ = GapOf(geometry_, s.phase, s.x) < 0.0;
}

void ContactTimeLaw::OnRoot(const TimeLawLayout& /*layout*/, const DaeView& s, int /*root*/) {
  // The integrator stops just past the crossing, so the gap already has the new sign: follow
  // it, which is a toggle for a genuine crossing and harmless if a crossing is reported twice.
  const double g = GapOf(geometry_, s.phase, s.x);
  if (g < 0.0) {
    closed_ = true;
  } else if (g > 0.0) {
    closed_ = false;
  } else {
    closed_ = !closed_;
  }
}

bool ContactTimeLaw::Admissible(const TimeLawLayout& /*layout*/, const DaeView& /*s*/) {
  return true;
}

void ContactTimeLaw::Force(const TimeLawLayout& /*layout*/, const DaeView& s,
                           Eigen::Ref<Eigen::VectorXd> f_nl) const {
  if (!closed_) return;
  const double lambda = -stiffness_ * GapOf(geometry_, s.phase, s.x);
  f_nl(geometry_.dof) += geometry_.direction * lambda;
  if (geometry_.other >= 0) f_nl(geometry_.other) -= geometry_.direction * lambda;
}

std::vector<std::pair<int, double>> ContactTimeLaw::StiffnessBound() const {
  std::vector<std::pair<int, double>> bound{{geometry_.dof, stiffness_}};
  if (geometry_.other >= 0) bound.emplace_back(geometry_.other, stiffness_);
  return bound;
}

std::vector<std::pair<std::string, double>> ContactTimeLaw::Signals(const TimeLawLayout& /*layout*/,
                                                                    const DaeView& s) const {
  // λ = k·max(0, −g) from the state alone, so schemes that track no mode (central differences)
  // report it too; in IDA it differs from the applied force only within the root tolerance.
  const double g = GapOf(geometry_, s.phase, s.x);
  return {{"gap", g}, {"force", stiffness_ * std::max(0.0, -g)}};
}

bool ContactTimeLaw::ExplicitForce(double phase, const Eigen::VectorXd& x,
                                   const Eigen::VectorXd& /*v*/,
                                   Eigen::Ref<Eigen::VectorXd> f_nl) const {
  const double lambda = stiffness_ * std::max(0.0, -Gap(phase, x));
  f_nl(geometry_.dof) += geometry_.direction * lambda;
  if (geometry_.other >= 0) f_nl(geometry_.other) -= geometry_.direction * lambda;
  return true;
}

}  // namespace nfrc
