#include "validation/contact_friction_time_law.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace nfrc {
namespace {

// As FrictionTimeLaw: a sliding velocity below this many admissibility tolerances of the
// velocity scale counts as rest (root locations leave |v| ~ 1e-14 of the scale, and a stick
// keeps it), so the relative acceleration decides.
constexpr double kNearZeroFactor = 1e3;

using Mode = ContactFrictionTimeLaw::Mode;

double Sign(Mode mode) { return mode == Mode::kSlipPositive ? 1.0 : -1.0; }

// Excitation frequency from the phase φ = ωt (a chirp's mean ω) in rad per time unit; 0 at
// t = 0, where the law cannot know it.
double PhaseRate(const DaeView& s) { return s.t > 0.0 && s.phase > 0.0 ? s.phase / s.t : 0.0; }

// The frequency scale of the admissibility tests (rad per time unit): the phase rate, 1 at t = 0.
double FrequencyScale(const DaeView& s) {
  const double rate = PhaseRate(s);
  return rate > 0.0 ? rate : 1.0;
}

// g0(φ) and its first two derivatives in φ (m, m/rad, m/rad²).
struct GapZero {
  double value = 0.0;
  double slope = 0.0;
  double curvature = 0.0;
};

GapZero GapZeroAt(const ContactGeometry& normal, double phase) {
  GapZero g0;
  g0.value = normal.gap;
  for (const auto& h : normal.gap_harmonics) {
    const double c = std::cos(h.harmonic * phase), s = std::sin(h.harmonic * phase);
    g0.value += h.cos * c + h.sin * s;
    g0.slope += h.harmonic * (h.sin * c - h.cos * s);
    g0.curvature -= h.harmonic * h.harmonic * (h.cos * c + h.sin * s);
  }
  return g0;
}

// x_dof − x_other of any vector expression (no copy of a DaeView's map).
double Relative(const ContactGeometry& normal, const Eigen::Ref<const Eigen::VectorXd>& x) {
  return x(normal.dof) - (normal.other >= 0 ? x(normal.other) : 0.0);
}

// g = g0(φ) − n (x_dof − x_other) (m).
double GapOf(const ContactGeometry& normal, double phase,
             const Eigen::Ref<const Eigen::VectorXd>& x) {
  return GapZeroAt(normal, phase).value - normal.direction * Relative(normal, x);
}

}  // namespace

ContactFrictionTimeLaw::ContactFrictionTimeLaw(ContactGeometry normal, double obstacle_stiffness,
                                               int tangent_dof, int tangent_other, double mu,
                                               double preload, double admissibility_tolerance)
    : normal_(std::move(normal)),
      stiffness_(obstacle_stiffness),
      tangent_dof_(tangent_dof),
      tangent_other_(tangent_other),
      mu_(mu),
      preload_(preload),
      tolerance_(admissibility_tolerance) {
  auto fail = [](const std::string& field, const std::string& problem) {
    throw std::invalid_argument(field + ": " + problem);
  };
  if (!(stiffness_ > 0.0) || !std::isfinite(stiffness_)) {
    fail("obstacle_stiffness",
         "must be finite and > 0 (N/m; a rigid obstacle has no time-domain form for "
         "contact_friction)");
  }
  if (!(mu_ >= 0.0) || !std::isfinite(mu_)) fail("mu", "must be finite and >= 0");
  if (!(preload_ >= 0.0) || !std::isfinite(preload_)) {
    fail("preload", "must be finite and >= 0 (N)");
  }
  if (normal_.dof < 0) fail("dof", "must be >= 0");
  if (normal_.other < -1) fail("other", "must be >= 0, or -1 for none");
  if (normal_.other == normal_.dof) fail("other", "must differ from dof");
  if (normal_.direction != 1.0 && normal_.direction != -1.0) {
    fail("direction", "must be 1 (obstacle on the positive side) or -1");
  }
  if (!std::isfinite(normal_.gap)) fail("gap", "must be finite");
  for (const auto& h : normal_.gap_harmonics) {
    if (!std::isfinite(h.cos) || !std::isfinite(h.sin)) fail("gap.harmonics", "must be finite");
  }
  if (tangent_dof_ < 0) fail("tangent_dof", "must be >= 0");
  if (tangent_dof_ == normal_.dof || tangent_dof_ == normal_.other) {
    fail("tangent_dof", "must differ from dof and other");
  }
  if (tangent_other_ < -1) fail("tangent_other", "must be >= 0, or -1 for ground");
  if (tangent_other_ >= 0 && (tangent_other_ == normal_.dof || tangent_other_ == normal_.other ||
                              tangent_other_ == tangent_dof_)) {
    fail("tangent_other", "must differ from dof, other and tangent_dof");
  }
  if (!(tolerance_ >= 0.0) || !std::isfinite(tolerance_)) {
    fail("admissibility_tolerance", "must be finite and >= 0");
  }
}

void ContactFrictionTimeLaw::set_massless(bool massless) {
  if (massless) {
    throw std::invalid_argument(
        "dof: contact_friction needs mass on dof, other, tangent_dof and tangent_other (its "
        "stick row is the relative tangential acceleration)");
  }
}

double ContactFrictionTimeLaw::Gap(double phase, const Eigen::VectorXd& x) const {
  return GapOf(normal_, phase, x);
}

double ContactFrictionTimeLaw::SlidingVelocity(const DaeView& s) const {
  return s.v(tangent_dof_) - (tangent_other_ >= 0 ? s.v(tangent_other_) : 0.0);
}

double ContactFrictionTimeLaw::Limit(const DaeView& s) const {
  return mu_ * stiffness_ * std::max(0.0, -GapOf(normal_, s.phase, s.x));
}

int ContactFrictionTimeLaw::GapTrend(const DaeView& s) const {
  // ġ = g0'(φ) φ̇ − n (v_dof − v_other), g̈ ≈ g0''(φ) φ̇² − n (a_dof − a_other) (φ̈ left out: zero
  // for a harmonic excitation, and only a start or a root exactly on g = 0 asks).
  const GapZero g0 = GapZeroAt(normal_, s.phase);
  const double rate = PhaseRate(s);
  const double g_dot = g0.slope * rate - normal_.direction * Relative(normal_, s.v);
  if (g_dot != 0.0) return g_dot > 0.0 ? 1 : -1;
  const double g_ddot = g0.curvature * rate * rate - normal_.direction * Relative(normal_, s.a);
  return g_ddot > 0.0 ? 1 : (g_ddot < 0.0 ? -1 : 0);
}

double ContactFrictionTimeLaw::VelocityScale(const DaeView& s) const {
  double v = 0.0, x = 0.0;
  for (int dof : {tangent_dof_, tangent_other_}) {
    if (dof < 0) continue;
    v = std::max({v, std::abs(s.v(dof)), std::abs(s.xdot(dof))});
    x = std::max(x, std::abs(s.x(dof)));
  }
  return v + FrequencyScale(s) * x;
}

void ContactFrictionTimeLaw::Close(const DaeView& s) {
  // The flight left v as it is: any nonzero v is a side that the slip root starts on. Only an
  // exactly resting tangential pair sticks (with zero limit, admissible only for r = 0).
  const double v = SlidingVelocity(s);
  if (mu_ == 0.0 || v != 0.0) {
    mode_ = v >= 0.0 ? Mode::kSlipPositive : Mode::kSlipNegative;
    closing_ = true;
  } else {
    mode_ = Mode::kStick;
  }
}

void ContactFrictionTimeLaw::Residual(const TimeLawLayout& layout, const DaeView& s,
                                      Eigen::Ref<Eigen::VectorXd> residual) const {
  const double n = normal_.direction;
  const int dof = normal_.dof, other = normal_.other;
  // The preload: +n N0 on the structure at `dof`, so −n N0 in its momentum row.
  residual(layout.Momentum(dof)) -= n * preload_;
  if (other >= 0) residual(layout.Momentum(other)) += n * preload_;
  const double r = s.own(0);
  if (!Closed()) {
    residual(layout.Own(0)) += r;
    return;
  }
  // λ = −k g without the max, so the residual is smooth within the mode.
  const double lambda = -stiffness_ * GapOf(normal_, s.phase, s.x);
  residual(layout.Momentum(dof)) += n * lambda;
  if (other >= 0) residual(layout.Momentum(other)) -= n * lambda;
  residual(layout.Momentum(tangent_dof_)) -= r;
  if (tangent_other_ >= 0) residual(layout.Momentum(tangent_other_)) += r;
  double own_row = 0.0;
  switch (mode_) {
    case Mode::kSlipPositive:
      own_row = r + mu_ * lambda;
      break;
    case Mode::kSlipNegative:
      own_row = r - mu_ * lambda;
      break;
    case Mode::kStick:
      // Index-1 stick: the relative tangential acceleration vanishes.
      own_row = s.a(tangent_dof_) - (tangent_other_ >= 0 ? s.a(tangent_other_) : 0.0);
      break;
    case Mode::kOpen:
      break;
  }
  residual(layout.Own(0)) += own_row;
}

void ContactFrictionTimeLaw::Jacobian(const TimeLawLayout& layout, const DaeView& /*s*/, double cj,
                                      std::vector<Eigen::Triplet<double>>* entries) const {
  const int own = layout.Own(0);
  if (!Closed()) {
    entries->emplace_back(own, own, 1.0);
    return;
  }
  const int dof = normal_.dof, other = normal_.other;
  const double n = normal_.direction;
  // ∂(n λ)/∂x_dof = n·k·n = k (n² = 1).
  entries->emplace_back(layout.Momentum(dof), layout.X(dof), stiffness_);
  if (other >= 0) {
    entries->emplace_back(layout.Momentum(dof), layout.X(other), -stiffness_);
    entries->emplace_back(layout.Momentum(other), layout.X(dof), -stiffness_);
    entries->emplace_back(layout.Momentum(other), layout.X(other), stiffness_);
  }
  entries->emplace_back(layout.Momentum(tangent_dof_), own, -1.0);
  if (tangent_other_ >= 0) entries->emplace_back(layout.Momentum(tangent_other_), own, 1.0);
  if (mode_ == Mode::kStick) {
    entries->emplace_back(own, layout.V(tangent_dof_), cj);
    if (tangent_other_ >= 0) entries->emplace_back(own, layout.V(tangent_other_), -cj);
    return;
  }
  // r ± μλ with ∂λ/∂x_dof = k n, ∂λ/∂x_other = −k n.
  const double slope = Sign(mode_) * mu_ * stiffness_ * n;
  entries->emplace_back(own, own, 1.0);
  entries->emplace_back(own, layout.X(dof), slope);
  if (other >= 0) entries->emplace_back(own, layout.X(other), -slope);
}

void ContactFrictionTimeLaw::Roots(const TimeLawLayout& /*layout*/, const DaeView& s,
                                   double* g) const {
  const double gap = GapOf(normal_, s.phase, s.x);
  g[0] = gap;
  g[1] = IsSlip() ? SlidingVelocity(s) : 1.0;
  if (mode_ == Mode::kStick) {
    // The same bound as Admissible, with λ = −k g unclipped (smooth): as the gap opens the
    // bound falls to zero, so a nonzero r releases just before the gap root fires.
    const double bound = -mu_ * stiffness_ * gap * (1.0 + tolerance_);
    g[2] = bound - s.own(0);
    g[3] = bound + s.own(0);
  } else {
    g[2] = 1.0;
    g[3] = 1.0;
  }
}

void ContactFrictionTimeLaw::InitMode(const TimeLawLayout& /*layout*/, const DaeView& s) {
  const double gap = GapOf(normal_, s.phase, s.x);
  // Exactly on the obstacle (a start from rest at zero gap): the DOFs' motion decides, else
  // IDA, which ignores a root function that is zero at its start, would never see the gap
  // close. Admissible refines it once the accelerations are known.
  if (gap < 0.0 || (gap == 0.0 && GapTrend(s) < 0)) {
    Close(s);
  } else {
    mode_ = Mode::kOpen;
  }
}

void ContactFrictionTimeLaw::OnRoot(const TimeLawLayout& /*layout*/, const DaeView& s, int root) {
  // The integrator stops just past a crossing, so the gap has its new sign: follow it (a
  // toggle for a genuine crossing, harmless for one reported twice).
  const double gap = GapOf(normal_, s.phase, s.x);
  if (root == 0) {
    if (gap < 0.0 || (gap == 0.0 && !Closed())) {
      if (!Closed()) Close(s);
    } else {
      mode_ = Mode::kOpen;
    }
    return;
  }
  // A friction root. Open: one of a mode left at this very event (the gap root comes first), or
  // a constant; ignored. Closed with a positive gap: the opening wins.
  if (!Closed()) return;
  if (gap > 0.0) {
    mode_ = Mode::kOpen;
    return;
  }
  if (mode_ == Mode::kStick && root >= 2) {
    // r = −μλ sign(v) in slip: r reaching +μλ starts slip−, −μλ starts slip+.
    mode_ = root == 2 ? Mode::kSlipNegative : Mode::kSlipPositive;
  } else if (IsSlip() && root == 1) {
    // v crossed zero. Without friction there is no stick: the slip direction follows v.
    if (mu_ == 0.0) {
      mode_ = mode_ == Mode::kSlipPositive ? Mode::kSlipNegative : Mode::kSlipPositive;
    } else {
      mode_ = Mode::kStick;
    }
  }
}

bool ContactFrictionTimeLaw::Admissible(const TimeLawLayout& /*layout*/, const DaeView& s) {
  const bool closing = closing_;
  closing_ = false;
  const double gap = GapOf(normal_, s.phase, s.x);
  if (!Closed()) {
    if (gap < 0.0 || (gap == 0.0 && GapTrend(s) < 0)) {
      Close(s);
      return false;
    }
    return true;
  }
  if (gap > 0.0) {
    mode_ = Mode::kOpen;
    return false;
  }
  // Friction first: on g = 0 the limit is zero, so the settled friction force is zero as when
  // open and both modes see the same accelerations in the gap's trend below (no ping-pong).
  if (mu_ > 0.0) {
    const double limit = Limit(s);
    const double v = SlidingVelocity(s);
    if (mode_ == Mode::kStick) {
      const double r = s.own(0);
      if (std::abs(r) > limit * (1.0 + tolerance_)) {
        // The stick needs more than μλ (a stick with zero limit any r ≠ 0): friction
        // saturates with the sign of the excess.
        mode_ = r > 0.0 ? Mode::kSlipNegative : Mode::kSlipPositive;
        return false;
      }
    } else if (!(closing && Sign(mode_) * v > 0.0)) {
      // A slip taken at a closing in the direction of v stands, however small v: the limit
      // grows from zero there, and a slip against v could be turned around by it before v
      // reaches zero, so that the slip root, starting on the wrong side, would never fire.
      const double sigma = Sign(mode_);
      const double v_scale = VelocityScale(s);
      const double near_zero = kNearZeroFactor * tolerance_ * v_scale;
      if (sigma * v < -near_zero) {
        // Plainly sliding the other way.
        mode_ = sigma > 0.0 ? Mode::kSlipNegative : Mode::kSlipPositive;
        return false;
      }
      if (sigma * v <= near_zero) {
        // From rest the relative acceleration decides: slipping against it means sticking.
        const double a = s.a(tangent_dof_) - (tangent_other_ >= 0 ? s.a(tangent_other_) : 0.0);
        const double a_max = std::max(std::abs(s.a(tangent_dof_)),
                                      tangent_other_ >= 0 ? std::abs(s.a(tangent_other_)) : 0.0);
        if (sigma * a < -tolerance_ * (a_max + FrequencyScale(s) * v_scale)) {
          mode_ = Mode::kStick;
          return false;
        }
      }
    }
  }
  if (gap == 0.0 && GapTrend(s) > 0) {
    mode_ = Mode::kOpen;
    return false;
  }
  return true;
}

void ContactFrictionTimeLaw::Force(const TimeLawLayout& /*layout*/, const DaeView& s,
                                   Eigen::Ref<Eigen::VectorXd> f_nl) const {
  const double n = normal_.direction;
  double normal_force = -preload_;
  if (Closed()) {
    normal_force -= stiffness_ * GapOf(normal_, s.phase, s.x);
    const double r = s.own(0);
    f_nl(tangent_dof_) -= r;
    if (tangent_other_ >= 0) f_nl(tangent_other_) += r;
  }
  f_nl(normal_.dof) += n * normal_force;
  if (normal_.other >= 0) f_nl(normal_.other) -= n * normal_force;
}

std::vector<std::pair<int, double>> ContactFrictionTimeLaw::StiffnessBound() const {
  std::vector<std::pair<int, double>> bound{{normal_.dof, stiffness_}};
  if (normal_.other >= 0) bound.emplace_back(normal_.other, stiffness_);
  return bound;
}

std::vector<std::pair<std::string, double>> ContactFrictionTimeLaw::Signals(
    const TimeLawLayout& /*layout*/, const DaeView& s) const {
  const double gap = GapOf(normal_, s.phase, s.x);
  return {{"gap", gap},
          {"normal_force", stiffness_ * std::max(0.0, -gap)},
          {"friction_force", Closed() ? s.own(0) : 0.0},
          {"velocity", SlidingVelocity(s)}};
}

bool ContactFrictionTimeLaw::ExplicitForce(double /*phase*/, const Eigen::VectorXd& /*x*/,
                                           const Eigen::VectorXd& /*v*/,
                                           Eigen::Ref<Eigen::VectorXd> /*f_nl*/) const {
  return false;
}

}  // namespace nfrc
