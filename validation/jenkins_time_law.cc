#include "validation/jenkins_time_law.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace nfrc {
namespace {

// A relative velocity below this many admissibility tolerances of the velocity scale counts as
// zero (the root location leaves u̇ ~ 1e-14 of the scale), so the relative acceleration
// decides; as FrictionTimeLaw.
constexpr double kNearZeroFactor = 1e3;

// Excitation frequency estimated from the phase φ = ωt (the mean ω of a chirp) in rad per time
// unit, for the velocity and acceleration scales of the admissibility tests; 1 at t = 0.
double FrequencyScale(const DaeView& s) {
  if (s.t > 0.0 && s.phase > 0.0) return s.phase / s.t;
  return 1.0;
}

double Sign(JenkinsTimeLaw::Mode mode) {
  return mode == JenkinsTimeLaw::Mode::kSlipPositive ? 1.0 : -1.0;
}

JenkinsTimeLaw::Mode Slip(double sigma) {
  return sigma > 0.0 ? JenkinsTimeLaw::Mode::kSlipPositive : JenkinsTimeLaw::Mode::kSlipNegative;
}

// Relative margin of a stick's release bound over an unsnapped |f| it was entered with: above
// f's round-off (a few ulps), and small, since a stick that releases on the side it was
// entered from (the ringing of a stiff spring) carries it into the next slip's force.
constexpr double kRootMargin = 64 * std::numeric_limits<double>::epsilon();

// Where the relative motion goes with respect to a direction σ = ±1 at a consistent state.
enum class Trend { kOutward, kInward, kUndecided };

}  // namespace

JenkinsTimeLaw::JenkinsTimeLaw(int dof, int other, double stiffness, double limit,
                               double admissibility_tolerance)
    : dof_(dof),
      other_(other),
      stiffness_(stiffness),
      limit_(limit),
      tolerance_(admissibility_tolerance) {
  if (!(stiffness_ > 0.0)) throw std::invalid_argument("stiffness: must be positive");
  if (!std::isfinite(stiffness_)) throw std::invalid_argument("stiffness: must be finite");
  if (!(limit_ >= 0.0)) throw std::invalid_argument("mu*normal_load: must be >= 0");
  if (!std::isfinite(limit_)) throw std::invalid_argument("mu*normal_load: must be finite");
  if (dof_ < 0) throw std::invalid_argument("dof: must be >= 0");
  if (dof_ == other_) throw std::invalid_argument("other: must differ from dof");
  if (!(tolerance_ >= 0.0)) throw std::invalid_argument("admissibility_tolerance: must be >= 0");
  release_bound_ = Bound();
}

double JenkinsTimeLaw::RelativeVelocity(const DaeView& s) const {
  // A massless DOF's v is algebraic; ẋ is its velocity (equal to v at a consistent state).
  const auto& velocity = massless_ ? s.xdot : s.v;
  return velocity(dof_) - (other_ >= 0 ? velocity(other_) : 0.0);
}

void JenkinsTimeLaw::SnapOwn(const TimeLawLayout& /*layout*/, const DaeView& /*s*/,
                             Eigen::Ref<Eigen::VectorXd> own) const {
  // ḟ = 0 in slip keeps whatever f the slip started with: exactly the sliding force.
  if (mode_ != Mode::kStick) own(0) = Sign(mode_) * limit_;
}

void JenkinsTimeLaw::Residual(const TimeLawLayout& layout, const DaeView& s,
                              Eigen::Ref<Eigen::VectorXd> residual) const {
  const double f = s.own(0);
  residual(layout.Momentum(dof_)) += f;
  if (other_ >= 0) residual(layout.Momentum(other_)) -= f;
  double own_row = s.own_dot(0);
  if (mode_ == Mode::kStick) {
    // The slider holds: the spring force follows u, ḟ = k_t u̇ (ẋ: valid for massless DOFs too).
    own_row -= stiffness_ * (s.xdot(dof_) - (other_ >= 0 ? s.xdot(other_) : 0.0));
  }
  residual(layout.Own(0)) += own_row;
}

void JenkinsTimeLaw::Jacobian(const TimeLawLayout& layout, const DaeView& /*s*/, double cj,
                              std::vector<Eigen::Triplet<double>>* entries) const {
  const int own = layout.Own(0);
  entries->emplace_back(layout.Momentum(dof_), own, 1.0);
  if (other_ >= 0) entries->emplace_back(layout.Momentum(other_), own, -1.0);
  entries->emplace_back(own, own, cj);
  if (mode_ != Mode::kStick) return;
  entries->emplace_back(own, layout.X(dof_), -stiffness_ * cj);
  if (other_ >= 0) entries->emplace_back(own, layout.X(other_), stiffness_ * cj);
}

void JenkinsTimeLaw::Roots(const TimeLawLayout& /*layout*/, const DaeView& s, double* g) const {
  if (mode_ == Mode::kStick) {
    // The bound Admissible accepted, so that a stick accepted within the tolerance still
    // releases, and one entered with |f| just beyond it starts with positive roots.
    g[0] = release_bound_ - s.own(0);
    g[1] = release_bound_ + s.own(0);
  } else {
    g[0] = RelativeVelocity(s);
    g[1] = 1.0;
  }
}

double JenkinsTimeLaw::OwnStateScale(int k, double value) const {
  constexpr double kFreeMargin = 1e-3;
  if (k != 0 || !(limit_ > 0.0)) return 0.0;
  return std::abs(value) < (1.0 - kFreeMargin) * limit_ ? limit_ : 0.0;
}

void JenkinsTimeLaw::InitMode(const TimeLawLayout& /*layout*/, const DaeView& s) {
  const double f = s.own(0);
  release_bound_ = Bound();
  if (limit_ == 0.0) {
    // No stick without friction: the slider follows u.
    mode_ = RelativeVelocity(s) >= 0.0 ? Mode::kSlipPositive : Mode::kSlipNegative;
  } else if (std::abs(f) < limit_) {
    mode_ = Mode::kStick;
  } else {
    mode_ = Slip(f);
  }
}

void JenkinsTimeLaw::OnRoot(const TimeLawLayout& /*layout*/, const DaeView& s, int root) {
  if (mode_ == Mode::kStick) {
    // f reaching +μN releases into slip+, −μN into slip−; a root that fired with f still
    // inside the bound (only by round-off) changes nothing.
    const double sigma = root == 0 ? 1.0 : -1.0;
    if (sigma * s.own(0) < release_bound_) return;
    mode_ = Slip(sigma);
  } else if (root == 0) {
    // Without friction there is no stick: the slip direction just follows u̇.
    if (limit_ == 0.0) {
      mode_ = mode_ == Mode::kSlipPositive ? Mode::kSlipNegative : Mode::kSlipPositive;
    } else {
      mode_ = Mode::kStick;
    }
  }
}

bool JenkinsTimeLaw::Admissible(const TimeLawLayout& /*layout*/, const DaeView& s) {
  if (limit_ == 0.0) return true;
  const double f = s.own(0);
  if (mode_ == Mode::kStick && std::abs(f) <= Bound()) {
    AcceptStick(f);
    return true;
  }

  // Slip in direction σ, or a stick whose |f| exceeds the bound with the sign σ: both are
  // decided by where the relative motion goes. With mass, the two modes have the same x, v, f
  // and a (only ḟ differs), so the decision does not depend on the mode it is asked in.
  const double sigma = mode_ == Mode::kStick ? (f > 0.0 ? 1.0 : -1.0) : Sign(mode_);
  const double omega = FrequencyScale(s);
  const double a_max = s.a.cwiseAbs().maxCoeff();
  const double v_scale = std::max(s.v.cwiseAbs().maxCoeff(), s.xdot.cwiseAbs().maxCoeff()) +
                         omega * s.x.cwiseAbs().maxCoeff() + a_max / omega;
  const double near_zero = kNearZeroFactor * tolerance_ * v_scale;
  const double u_dot = sigma * RelativeVelocity(s);
  Trend trend = Trend::kUndecided;
  if (u_dot > near_zero) {
    trend = Trend::kOutward;
  } else if (u_dot < -near_zero) {
    trend = Trend::kInward;
  } else if (!massless_) {
    // From rest the relative acceleration says whether the spring would load past μN.
    const double a_rel = s.a(dof_) - (other_ >= 0 ? s.a(other_) : 0.0);
    const double a_scale = a_max + omega * v_scale;
    trend = sigma * a_rel >= -tolerance_ * a_scale ? Trend::kOutward : Trend::kInward;
  }
  // A massless interface's velocity is algebraic: near zero there is no acceleration to ask,
  // and the current mode stays (kUndecided).

  if (mode_ == Mode::kStick) {
    // |f| beyond μN(1 + tolerance) in stick: the sliding force of a slip that an integrator
    // did not snap (IdaDae snaps at every restart), carrying the release root's overshoot ḟ·δt
    // (up to ~1e-7 μN for a stiff spring late in a run). Admissible while the spring unloads;
    // loading, the slider slides.
    if (trend != Trend::kOutward) {
      AcceptStick(f);
      return true;
    }
    mode_ = Slip(sigma);
    return false;
  }
  // Slip: the relative motion reversed, so the spring unloads from ±μN: stick (never the
  // opposite slip, which would need f = ∓μN).
  if (trend != Trend::kInward) return true;
  mode_ = Mode::kStick;
  return false;
}

void JenkinsTimeLaw::AcceptStick(double f) {
  // A stick entered at f = ±μN exactly (a snapped slip) releases at ±μN(1 + tolerance). An
  // unsnapped sliding force sits at or just beyond that bound (IDA reports a root where g has
  // crossed): the bound then moves just beyond |f|, since a root starting at zero fires again
  // as f leaves it by round-off, and IDA stops on a root "found at and very near t".
  release_bound_ = std::max(Bound(), std::abs(f) * (1.0 + kRootMargin));
}

void JenkinsTimeLaw::Force(const TimeLawLayout& /*layout*/, const DaeView& s,
                           Eigen::Ref<Eigen::VectorXd> f_nl) const {
  const double f = s.own(0);
  f_nl(dof_) += f;
  if (other_ >= 0) f_nl(other_) -= f;
}

std::vector<std::pair<int, double>> JenkinsTimeLaw::StiffnessBound() const {
  std::vector<std::pair<int, double>> bound = {{dof_, stiffness_}};
  if (other_ >= 0) bound.emplace_back(other_, stiffness_);
  return bound;
}

std::vector<std::pair<std::string, double>> JenkinsTimeLaw::Signals(const TimeLawLayout& /*layout*/,
                                                                    const DaeView& s) const {
  const double f = s.own(0);
  const double u = s.x(dof_) - (other_ >= 0 ? s.x(other_) : 0.0);
  return {{"force", f}, {"displacement", u}, {"slider", u - f / stiffness_}};
}

bool JenkinsTimeLaw::ExplicitForce(double /*phase*/, const Eigen::VectorXd& /*x*/,
                                   const Eigen::VectorXd& /*v*/,
                                   Eigen::Ref<Eigen::VectorXd> /*f_nl*/) const {
  return false;
}

}  // namespace nfrc
