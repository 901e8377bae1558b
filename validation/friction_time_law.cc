#include "validation/friction_time_law.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace nfrc {
namespace {

// A slip entered with |v_rel| below this many admissibility tolerances of the velocity scale
// counts as starting from rest (the root location leaves v_rel ~ 1e-14 of the scale, and the
// stick phase keeps it), so the relative acceleration decides.
constexpr double kNearZeroFactor = 1e3;

double Sign(FrictionTimeLaw::Mode mode) {
  return mode == FrictionTimeLaw::Mode::kSlipPositive ? 1.0 : -1.0;
}

// Excitation frequency estimated from the phase φ = ωt (the mean ω of a chirp) in rad per time
// unit, for the velocity and acceleration scales of the admissibility tests; 1 at t = 0.
double FrequencyScale(const DaeView& s) {
  if (s.t > 0.0 && s.phase > 0.0) return s.phase / s.t;
  return 1.0;
}

// The relative sliding velocity v_dof − v_other (m/s).
double RelativeVelocity(int dof, int other, const DaeView& s) {
  return s.v(dof) - (other >= 0 ? s.v(other) : 0.0);
}

// The force r and its derivative dr/dv_rel of a regularised law in the current mode.
std::pair<double, double> RegularisedForce(const FrictionParameters& p, FrictionTimeLaw::Mode mode,
                                           double v) {
  const double limit = p.limit;
  switch (p.equality) {
    case FrictionEquality::kTanh: {
      const double t = std::tanh(p.alpha * v);
      return {-limit * t, -limit * p.alpha * (1.0 - t * t)};
    }
    case FrictionEquality::kArctan: {
      const double z = p.alpha * v;
      return {-limit * 2.0 / std::numbers::pi * std::atan(z),
              -limit * 2.0 / std::numbers::pi * p.alpha / (1.0 + z * z)};
    }
    case FrictionEquality::kPiecewiseLinear:
      if (mode == FrictionTimeLaw::Mode::kStick) return {-limit * v / p.delta, -limit / p.delta};
      return {-limit * Sign(mode), 0.0};
    default:
      assert(false && "exact laws have an own unknown");
      return {0.0, 0.0};
  }
}

}  // namespace

FrictionTimeLaw::FrictionTimeLaw(int dof, int other, FrictionParameters parameters, bool massless,
                                 double admissibility_tolerance)
    : dof_(dof),
      other_(other),
      parameters_(parameters),
      massless_(massless),
      tolerance_(admissibility_tolerance) {
  if (parameters_.equality == FrictionEquality::kSign) {
    throw std::invalid_argument("law: \"sign\" has no time-domain form");
  }
  if (!(parameters_.limit >= 0.0)) throw std::invalid_argument("mu*normal_load: must be >= 0");
  if (dof_ < 0) throw std::invalid_argument("dof: must be >= 0");
  if (dof_ == other_) throw std::invalid_argument("other: must differ from dof");
  if ((parameters_.equality == FrictionEquality::kTanh ||
       parameters_.equality == FrictionEquality::kArctan) &&
      !(parameters_.alpha > 0.0)) {
    throw std::invalid_argument("alpha: must be positive");
  }
  if (parameters_.equality == FrictionEquality::kPiecewiseLinear && !(parameters_.delta > 0.0)) {
    throw std::invalid_argument("delta: must be positive");
  }
  if (!(tolerance_ >= 0.0)) throw std::invalid_argument("admissibility_tolerance: must be >= 0");
  // Smooth laws have no stick phase; the mode is then only a label.
  if (parameters_.equality == FrictionEquality::kTanh ||
      parameters_.equality == FrictionEquality::kArctan) {
    mode_ = Mode::kSlipPositive;
  }
}

int FrictionTimeLaw::NumOwn() const { return IsExact(parameters_.equality) ? 1 : 0; }

bool FrictionTimeLaw::OwnIsDifferential(int k) const {
  return k == 0 && differentiated_ && massless_ && IsExact(parameters_.equality);
}

void FrictionTimeLaw::SnapOwn(const TimeLawLayout& /*layout*/, const DaeView& /*s*/,
                              Eigen::Ref<Eigen::VectorXd> own) const {
  // ṙ = 0 in slip keeps whatever r the slip started with: exactly the sliding force.
  if (OwnIsDifferential(0) && mode_ != Mode::kStick) own(0) = -Sign(mode_) * parameters_.limit;
}

void FrictionTimeLaw::Residual(const TimeLawLayout& layout, const DaeView& s,
                               Eigen::Ref<Eigen::VectorXd> residual) const {
  const double v_rel = RelativeVelocity(dof_, other_, s);
  double r = 0.0;
  if (IsExact(parameters_.equality)) {
    r = s.own(0);
    double own_row = 0.0;
    switch (mode_) {
      case Mode::kSlipPositive:
        own_row = OwnIsDifferential(0) ? s.own_dot(0) : r + parameters_.limit;
        break;
      case Mode::kSlipNegative:
        own_row = OwnIsDifferential(0) ? s.own_dot(0) : r - parameters_.limit;
        break;
      case Mode::kStick:
        // Index-1 stick: the relative acceleration (massless: the relative ẋ) vanishes.
        own_row = massless_ ? s.xdot(dof_) - (other_ >= 0 ? s.xdot(other_) : 0.0)
                            : s.a(dof_) - (other_ >= 0 ? s.a(other_) : 0.0);
        break;
    }
    residual(layout.Own(0)) += own_row;
  } else {
    r = RegularisedForce(parameters_, mode_, v_rel).first;
  }
  residual(layout.Momentum(dof_)) -= r;
  if (other_ >= 0) residual(layout.Momentum(other_)) += r;
}

void FrictionTimeLaw::Jacobian(const TimeLawLayout& layout, const DaeView& s, double cj,
                               std::vector<Eigen::Triplet<double>>* entries) const {
  if (IsExact(parameters_.equality)) {
    const int own = layout.Own(0);
    entries->emplace_back(layout.Momentum(dof_), own, -1.0);
    if (other_ >= 0) entries->emplace_back(layout.Momentum(other_), own, 1.0);
    if (mode_ == Mode::kStick) {
      const int column_dof = massless_ ? layout.X(dof_) : layout.V(dof_);
      entries->emplace_back(own, column_dof, cj);
      if (other_ >= 0) {
        entries->emplace_back(own, massless_ ? layout.X(other_) : layout.V(other_), -cj);
      }
    } else {
      entries->emplace_back(own, own, OwnIsDifferential(0) ? cj : 1.0);
    }
    return;
  }
  const double dr = RegularisedForce(parameters_, mode_, RelativeVelocity(dof_, other_, s)).second;
  if (dr == 0.0) return;
  entries->emplace_back(layout.Momentum(dof_), layout.V(dof_), -dr);
  if (other_ >= 0) {
    entries->emplace_back(layout.Momentum(dof_), layout.V(other_), dr);
    entries->emplace_back(layout.Momentum(other_), layout.V(dof_), dr);
    entries->emplace_back(layout.Momentum(other_), layout.V(other_), -dr);
  }
}

int FrictionTimeLaw::NumRoots() const {
  return IsExact(parameters_.equality) || parameters_.equality == FrictionEquality::kPiecewiseLinear
             ? 2
             : 0;
}

void FrictionTimeLaw::Roots(const TimeLawLayout& /*layout*/, const DaeView& s, double* g) const {
  const double v_rel = RelativeVelocity(dof_, other_, s);
  if (parameters_.equality == FrictionEquality::kPiecewiseLinear) {
    // Only the band edges reachable from the current mode are active.
    const double delta = parameters_.delta;
    g[0] = mode_ == Mode::kSlipNegative ? 1.0 : v_rel - delta;
    g[1] = mode_ == Mode::kSlipPositive ? 1.0 : v_rel + delta;
    return;
  }
  if (!IsExact(parameters_.equality)) return;
  if (mode_ == Mode::kStick) {
    // The same bound as Admissible, so a stick accepted within the tolerance still releases.
    // Massless too: a stick entered at r = ∓μN exactly (a massless slider stops with the
    // sliding force) would otherwise start its root at zero, and IDA loses a root that is zero
    // at a restart, so a force moving outward would never release. (The slip's r = ∓μN is
    // snapped and its constraint on x projected on release, so the slack does not remain.)
    const double bound = parameters_.limit * (1.0 + tolerance_);
    g[0] = bound - s.own(0);
    g[1] = bound + s.own(0);
  } else {
    g[0] = v_rel;
    g[1] = 1.0;
  }
}

void FrictionTimeLaw::InitMode(const TimeLawLayout& /*layout*/, const DaeView& s) {
  const double v_rel = RelativeVelocity(dof_, other_, s);
  switch (parameters_.equality) {
    case FrictionEquality::kPiecewiseLinear:
      mode_ = v_rel > parameters_.delta
                  ? Mode::kSlipPositive
                  : (v_rel < -parameters_.delta ? Mode::kSlipNegative : Mode::kStick);
      return;
    case FrictionEquality::kMinMax:
    case FrictionEquality::kHueber: {
      const double scale = std::max(s.v.cwiseAbs().maxCoeff(), s.xdot.cwiseAbs().maxCoeff()) +
                           FrequencyScale(s) * s.x.cwiseAbs().maxCoeff();
      if (parameters_.limit == 0.0 || std::abs(v_rel) > kNearZeroFactor * tolerance_ * scale) {
        mode_ = v_rel >= 0.0 ? Mode::kSlipPositive : Mode::kSlipNegative;
      } else {
        mode_ = Mode::kStick;
      }
      return;
    }
    default:
      return;
  }
}

void FrictionTimeLaw::OnRoot(const TimeLawLayout& /*layout*/, const DaeView& /*s*/, int root) {
  if (parameters_.equality == FrictionEquality::kPiecewiseLinear) {
    // A crossing of a band edge toggles between the band and the slip beyond that edge.
    const Mode outside = root == 0 ? Mode::kSlipPositive : Mode::kSlipNegative;
    mode_ = mode_ == Mode::kStick ? outside : Mode::kStick;
    return;
  }
  if (!IsExact(parameters_.equality)) return;
  if (mode_ == Mode::kStick) {
    // r = −μN sign(v_rel) in slip: r reaching +μN starts slip−, −μN starts slip+.
    mode_ = root == 0 ? Mode::kSlipNegative : Mode::kSlipPositive;
  } else if (root == 0) {
    // Without friction there is no stick: the slip direction just follows v_rel.
    if (parameters_.limit == 0.0) {
      mode_ = mode_ == Mode::kSlipPositive ? Mode::kSlipNegative : Mode::kSlipPositive;
    } else {
      mode_ = Mode::kStick;
    }
  }
}

bool FrictionTimeLaw::Admissible(const TimeLawLayout& /*layout*/, const DaeView& s) {
  const double v_rel = RelativeVelocity(dof_, other_, s);
  if (parameters_.equality == FrictionEquality::kPiecewiseLinear) {
    const double delta = parameters_.delta;
    const double slack = tolerance_ * delta;
    Mode wanted = mode_;
    if (mode_ == Mode::kStick && std::abs(v_rel) > delta + slack) {
      wanted = v_rel > 0.0 ? Mode::kSlipPositive : Mode::kSlipNegative;
    } else if (mode_ != Mode::kStick && Sign(mode_) * v_rel < delta - slack) {
      wanted = std::abs(v_rel) <= delta ? Mode::kStick
                                        : (v_rel > 0.0 ? Mode::kSlipPositive : Mode::kSlipNegative);
    }
    const bool admissible = wanted == mode_;
    mode_ = wanted;
    return admissible;
  }
  if (!IsExact(parameters_.equality) || parameters_.limit == 0.0) return true;

  const double limit = parameters_.limit;
  if (mode_ == Mode::kStick) {
    const double r = s.own(0);
    if (std::abs(r) <= limit * (1.0 + tolerance_)) return true;
    // The stick needs more than μN: friction saturates with the sign of the excess.
    mode_ = r > 0.0 ? Mode::kSlipNegative : Mode::kSlipPositive;
    return false;
  }

  const double sigma = Sign(mode_);
  const double omega = FrequencyScale(s);
  const double a_max = s.a.cwiseAbs().maxCoeff();
  const double v_scale = std::max(s.v.cwiseAbs().maxCoeff(), s.xdot.cwiseAbs().maxCoeff()) +
                         omega * s.x.cwiseAbs().maxCoeff() + a_max / omega;
  const double near_zero = kNearZeroFactor * tolerance_ * v_scale;
  if (sigma * v_rel > near_zero) return true;
  if (sigma * v_rel < -near_zero) {
    // Plainly sliding the other way (a massless interface jumps to its sliding velocity).
    mode_ = massless_ ? Mode::kStick : (sigma > 0.0 ? Mode::kSlipNegative : Mode::kSlipPositive);
    return false;
  }
  // The massless interface's velocity is algebraic: near zero there is no acceleration to ask.
  if (massless_) return true;
  const double a_rel = s.a(dof_) - (other_ >= 0 ? s.a(other_) : 0.0);
  const double a_scale = a_max + omega * v_scale;
  if (sigma * a_rel >= -tolerance_ * a_scale) return true;
  mode_ = Mode::kStick;
  return false;
}

void FrictionTimeLaw::Force(const TimeLawLayout& /*layout*/, const DaeView& s,
                            Eigen::Ref<Eigen::VectorXd> f_nl) const {
  const double r =
      IsExact(parameters_.equality)
          ? s.own(0)
          : RegularisedForce(parameters_, mode_, RelativeVelocity(dof_, other_, s)).first;
  f_nl(dof_) -= r;
  if (other_ >= 0) f_nl(other_) += r;
}

std::vector<std::pair<std::string, double>> FrictionTimeLaw::Signals(
    const TimeLawLayout& /*layout*/, const DaeView& s) const {
  const double v_rel = RelativeVelocity(dof_, other_, s);
  const double r =
      IsExact(parameters_.equality) ? s.own(0) : RegularisedForce(parameters_, mode_, v_rel).first;
  return {{"force", r}, {"velocity", v_rel}};
}

bool FrictionTimeLaw::ExplicitForce(double /*phase*/, const Eigen::VectorXd& /*x*/,
                                    const Eigen::VectorXd& v,
                                    Eigen::Ref<Eigen::VectorXd> f_nl) const {
  if (IsExact(parameters_.equality)) return false;
  const double v_rel = v(dof_) - (other_ >= 0 ? v(other_) : 0.0);
  double r = 0.0;
  if (parameters_.equality == FrictionEquality::kPiecewiseLinear) {
    // No modes in an explicit scheme: the clamp itself.
    r = -parameters_.limit * std::clamp(v_rel / parameters_.delta, -1.0, 1.0);
  } else {
    r = RegularisedForce(parameters_, mode_, v_rel).first;
  }
  f_nl(dof_) -= r;
  if (other_ >= 0) f_nl(other_) += r;
  return true;
}

}  // namespace nfrc
