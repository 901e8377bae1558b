// Coulomb friction in the time domain: Jacobians against finite differences, the mode logic
// against the law's definition, and IDA runs against closed forms and an event-driven
// semi-analytic solution written here.
#include "validation/friction_time_law.h"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "support/den_hartog.h"
#include "validation/ida_integrator.h"
#include "validation/time_law_check.h"
#include "validation/transient_model.h"

namespace nfrc {
namespace {

constexpr double kPi = std::numbers::pi;
using Complex = std::complex<double>;
using Mode = FrictionTimeLaw::Mode;

// Central differences with h = 1e-7 on residuals of size ≤ 10: truncation h²·|F'''| ≈ 1e-14,
// round-off ε|F|/h ≈ 1e-8; 1e-6 relative leaves margin and still catches any wrong entry.
constexpr double kJacobianTolerance = 1e-6;

FrictionParameters Exact(double limit) {
  FrictionParameters p;
  p.equality = FrictionEquality::kMinMax;
  p.limit = limit;
  return p;
}

// A three-DOF layout with the law's own unknowns after [x | v].
struct LawState {
  TimeLawLayout layout;
  Eigen::VectorXd y, yp;
  LawState(const TimeLaw& law, const Eigen::Vector3d& v, double r) {
    layout.num_dofs = 3;
    layout.own_offset = 6;
    y.resize(6 + law.NumOwn());
    yp.resize(6 + law.NumOwn());
    y << 0.3, -0.7, 1.1, v, Eigen::VectorXd::Constant(law.NumOwn(), r);
    yp << (v.array() + 0.25).matrix(), -1.3, 0.4, 2.2, Eigen::VectorXd::Constant(law.NumOwn(), 0.9);
  }
  DaeView View(const TimeLaw& law) const { return MakeDaeView(law, layout, 2.0, 3.0, y, yp); }
  Eigen::VectorXd Residual(const TimeLaw& law) const {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(y.size());
    law.Residual(layout, View(law), f);
    return f;
  }
};

void CheckJacobian(const TimeLaw& law, const LawState& state) {
  for (double cj : {0.0, 3.7}) {
    const TimeLawCheck check =
        CheckTimeLawJacobian(law, state.layout, 2.0, 3.0, state.y, state.yp, cj);
    CAPTURE(cj);
    CAPTURE(check.worst);
    CHECK(check.Passed(kJacobianTolerance));
  }
}

TEST_CASE("Friction time law: exact law Jacobian and residual in every mode") {
  constexpr double kLimit = 0.8;
  for (int other : {-1, 2}) {
    for (bool massless : {false, true}) {
      CAPTURE(other);
      CAPTURE(massless);
      FrictionTimeLaw law(0, other, Exact(kLimit), massless);
      REQUIRE(law.NumOwn() == 1);
      const double v_other = other >= 0 ? 0.4 : 0.0;
      struct Case {
        double v_rel;
        Mode mode;
      };
      for (const Case& c : {Case{0.5, Mode::kSlipPositive}, Case{-0.5, Mode::kSlipNegative},
                            Case{0.0, Mode::kStick}}) {
        const double r = 0.3;
        const LawState s(law, Eigen::Vector3d(v_other + c.v_rel, -0.2, v_other), r);
        law.InitMode(s.layout, s.View(law));
        CAPTURE(static_cast<int>(c.mode));
        REQUIRE(law.ModeIndex() == static_cast<int>(c.mode));
        CHECK(law.InPhase() == (c.mode == Mode::kStick));
        CheckJacobian(law, s);
        // r acts on `dof` and −r on `other`: momentum rows −r, +r.
        const Eigen::VectorXd f = s.Residual(law);
        CHECK(f(s.layout.Momentum(0)) == doctest::Approx(-r));
        CHECK(f(s.layout.Momentum(1)) == 0.0);
        CHECK(f(s.layout.Momentum(2)) == doctest::Approx(other >= 0 ? r : 0.0));
        double own_row = c.mode == Mode::kSlipPositive   ? r + kLimit
                         : c.mode == Mode::kSlipNegative ? r - kLimit
                         : massless                      ? s.yp(0) - (other >= 0 ? s.yp(2) : 0.0)
                                                         : s.yp(3) - (other >= 0 ? s.yp(5) : 0.0);
        CHECK(f(s.layout.Own(0)) == doctest::Approx(own_row));
        Eigen::Vector3d f_nl = Eigen::Vector3d::Zero();
        law.Force(s.layout, s.View(law), f_nl);
        CHECK(f_nl(0) == doctest::Approx(-r));
        CHECK(f_nl(2) == doctest::Approx(other >= 0 ? r : 0.0));
        Eigen::Vector3d unused = Eigen::Vector3d::Zero();
        CHECK_FALSE(law.ExplicitForce(0.0, s.y.head(3), s.y.segment(3, 3), unused));
      }
    }
  }
}

TEST_CASE("Friction time law: differentiated massless law holds r by ṙ = 0 in slip") {
  constexpr double kLimit = 0.8;
  for (int other : {-1, 2}) {
    CAPTURE(other);
    FrictionTimeLaw law(0, other, Exact(kLimit), true);
    CHECK_FALSE(law.OwnIsDifferential(0));  // index 1 unless the integrator differentiates
    law.set_differentiated(true);
    REQUIRE(law.OwnIsDifferential(0));
    const double v_other = other >= 0 ? 0.4 : 0.0;
    for (double v_rel : {0.5, -0.5, 0.0}) {
      CAPTURE(v_rel);
      LawState s(law, Eigen::Vector3d(v_other + v_rel, -0.2, v_other), 0.3);
      law.InitMode(s.layout, s.View(law));
      CheckJacobian(law, s);
      const Eigen::VectorXd f = s.Residual(law);
      // Slip: ṙ (own_dot = 0.9 in LawState); stick: ẋ_rel as before.
      const double own_row = v_rel != 0.0 ? 0.9 : s.yp(0) - (other >= 0 ? s.yp(2) : 0.0);
      CHECK(f(s.layout.Own(0)) == doctest::Approx(own_row));
      CHECK(f(s.layout.Momentum(0)) == doctest::Approx(-0.3));
      // SnapOwn sets the sliding force exactly; it leaves a sticking one alone.
      Eigen::VectorXd own = Eigen::VectorXd::Constant(1, 0.3);
      law.SnapOwn(s.layout, s.View(law), own);
      CHECK(own(0) == (v_rel > 0 ? -kLimit : (v_rel < 0 ? kLimit : 0.3)));
    }
  }
}

TEST_CASE("Friction time law: regularised laws match their force and finite differences") {
  constexpr double kLimit = 0.8, kAlpha = 3.0, kDelta = 0.2;
  struct Law {
    FrictionEquality equality;
    double (*s)(double);
  };
  const Law laws[] = {
      {FrictionEquality::kTanh, [](double v) { return std::tanh(kAlpha * v); }},
      {FrictionEquality::kArctan, [](double v) { return 2 / kPi * std::atan(kAlpha * v); }},
      {FrictionEquality::kPiecewiseLinear,
       [](double v) { return std::clamp(v / kDelta, -1.0, 1.0); }}};
  for (const Law& l : laws) {
    FrictionParameters p;
    p.equality = l.equality;
    p.limit = kLimit;
    p.alpha = kAlpha;
    p.delta = kDelta;
    for (int other : {-1, 2}) {
      // Away from the piecewise-linear kinks at ±δ.
      for (double v_rel : {-0.55, -0.07, 0.13, 0.9}) {
        CAPTURE(ToString(l.equality));
        CAPTURE(other);
        CAPTURE(v_rel);
        FrictionTimeLaw law(0, other, p, false);
        REQUIRE(law.NumOwn() == 0);
        const double v_other = other >= 0 ? -0.3 : 0.0;
        const LawState s(law, Eigen::Vector3d(v_other + v_rel, 0.6, v_other), 0.0);
        law.InitMode(s.layout, s.View(law));
        CheckJacobian(law, s);
        const double r = -kLimit * l.s(v_rel);
        const Eigen::VectorXd f = s.Residual(law);
        CHECK(f(s.layout.Momentum(0)) == doctest::Approx(-r));
        CHECK(f(s.layout.Momentum(2)) == doctest::Approx(other >= 0 ? r : 0.0));
        Eigen::Vector3d explicit_force = Eigen::Vector3d::Zero();
        REQUIRE(law.ExplicitForce(0.0, s.y.head(3), s.y.segment(3, 3), explicit_force));
        CHECK(explicit_force(0) == doctest::Approx(-r));
        const auto signals = law.Signals(s.layout, s.View(law));
        REQUIRE(signals.size() == 2);
        CHECK(signals[0].first == "force");
        CHECK(signals[0].second == doctest::Approx(r));
        CHECK(signals[1].second == doctest::Approx(v_rel));
        if (l.equality == FrictionEquality::kPiecewiseLinear) {
          CHECK(law.InPhase() == (std::abs(v_rel) < kDelta));
        } else {
          CHECK_FALSE(law.InPhase());
        }
      }
    }
  }
  FrictionParameters sign;
  sign.equality = FrictionEquality::kSign;
  sign.limit = kLimit;
  CHECK_THROWS_AS(FrictionTimeLaw(0, -1, sign, false), std::invalid_argument);
  CHECK_THROWS_AS(FrictionTimeLaw(0, -1, Exact(-1.0), false), std::invalid_argument);
}

TEST_CASE("Friction time law: mode switches follow Coulomb's law") {
  constexpr double kLimit = 2.0;
  FrictionTimeLaw law(0, -1, Exact(kLimit), false);
  auto state = [&](double v, double a, double r) {
    LawState s(law, Eigen::Vector3d(v, 0.0, 0.0), r);
    s.yp.segment(3, 3) << a, 0.0, 0.0;
    return s;
  };
  const LawState rest = state(0.0, 0.0, 0.0);
  law.InitMode(rest.layout, rest.View(law));
  CHECK(law.ModeIndex() == static_cast<int>(Mode::kStick));
  double g[2];
  // Sticking force within μN: both stick roots positive; r past +μN: root 0 negative.
  const LawState holding = state(0.0, 0.0, 0.5 * kLimit);
  law.Roots(holding.layout, holding.View(law), g);
  CHECK(g[0] > 0.0);
  CHECK(g[1] > 0.0);
  CHECK(law.Admissible(holding.layout, holding.View(law)));
  const LawState pulled = state(0.0, 0.0, 1.01 * kLimit);
  law.Roots(pulled.layout, pulled.View(law), g);
  CHECK(g[0] < 0.0);
  // r = −μN sign(v_rel) when sliding, so a sticking force beyond +μN means slip−.
  CHECK_FALSE(law.Admissible(pulled.layout, pulled.View(law)));
  CHECK(law.ModeIndex() == static_cast<int>(Mode::kSlipNegative));
  // Slip− from rest with the acceleration of slip−: admissible; with the opposite: stick.
  const LawState going = state(0.0, -0.3, kLimit);
  CHECK(law.Admissible(going.layout, going.View(law)));
  const LawState wrong = state(0.0, 0.3, kLimit);
  CHECK_FALSE(law.Admissible(wrong.layout, wrong.View(law)));
  CHECK(law.ModeIndex() == static_cast<int>(Mode::kStick));
  // From stick, root 1 (r reached −μN) starts slip+; in slip the root is v_rel.
  law.OnRoot(rest.layout, rest.View(law), 1);
  CHECK(law.ModeIndex() == static_cast<int>(Mode::kSlipPositive));
  const LawState sliding = state(0.4, -0.1, -kLimit);
  law.Roots(sliding.layout, sliding.View(law), g);
  CHECK(g[0] == doctest::Approx(0.4));
  CHECK(law.Admissible(sliding.layout, sliding.View(law)));
  law.OnRoot(sliding.layout, sliding.View(law), 0);
  CHECK(law.ModeIndex() == static_cast<int>(Mode::kStick));
  law.OnRoot(rest.layout, rest.View(law), 0);
  CHECK(law.ModeIndex() == static_cast<int>(Mode::kSlipNegative));
}

// The one-DOF oscillator ẍ + cẋ + kx = f cos ωt + r (unit mass) with Coulomb friction r on the
// mass: r = −μN sign ẋ while sliding, |r| ≤ μN stuck.
struct OneDof {
  double c, k, f, limit, omega;
  double Period() const { return 2 * kPi / omega; }
};

// The closed-form motion of one slip phase in direction σ = ±1 from (t0, x0, v0): the forced
// response to f cos ωt − σμN plus the damped free vibration (c² < 4k).
struct SlipPhase {
  double t0 = 0, sigma = 1;
  Complex particular;  // x_p(t) = Re(P e^{iωt}) − σμN/k
  double omega = 0, offset = 0, decay = 0, omega_d = 0, a = 0, b = 0;

  SlipPhase() = default;
  SlipPhase(const OneDof& o, double t0_, double x0, double v0, double sigma_)
      : t0(t0_), sigma(sigma_), omega(o.omega) {
    particular = o.f / Complex(o.k - o.omega * o.omega, o.c * o.omega);
    offset = -sigma * o.limit / o.k;
    decay = o.c / 2;
    omega_d = std::sqrt(o.k - decay * decay);
    a = x0 - ForcedX(t0);
    b = (v0 - ForcedV(t0) + decay * a) / omega_d;
  }
  double ForcedX(double t) const {
    return (particular * std::polar(1.0, omega * t)).real() + offset;
  }
  double ForcedV(double t) const {
    return (Complex(0, omega) * particular * std::polar(1.0, omega * t)).real();
  }
  double X(double t) const {
    const double s = t - t0;
    return ForcedX(t) +
           std::exp(-decay * s) * (a * std::cos(omega_d * s) + b * std::sin(omega_d * s));
  }
  double V(double t) const {
    const double s = t - t0;
    return ForcedV(t) + std::exp(-decay * s) * ((-decay * a + omega_d * b) * std::cos(omega_d * s) +
                                                (-decay * b - omega_d * a) * std::sin(omega_d * s));
  }
};

// One phase of the motion: slip (σ = ±1, closed form) or stick (σ = 0 at x_stick).
struct Segment {
  double t_begin = 0, t_end = 0;
  int sigma = 0;
  double x_stick = 0;
  SlipPhase slip;
  double X(double t) const { return sigma == 0 ? x_stick : slip.X(t); }
};

// First t in (t_begin, t_end] where `event` turns positive, located by bisection to round-off
// after a scan on a grid of `step`; t_end + 1 if none. A grid of T/4096 cannot step over a
// velocity sign change unless two events are closer than that (checked: none in these runs).
template <typename Event>
double FirstEvent(Event event, double t_begin, double t_end, double step) {
  for (double ta = t_begin; ta < t_end;) {
    const double tb = std::min(ta + step, t_end);
    if (event(tb) > 0) {
      double lo = ta, hi = tb;
      for (int i = 0; i < 200 && hi - lo > 4e-16 * std::abs(hi); ++i) {
        const double mid = 0.5 * (lo + hi);
        (event(mid) > 0 ? hi : lo) = mid;
      }
      return hi;
    }
    ta = tb;
  }
  return t_end + 1;
}

// Event-driven steady state of OneDof: closed forms in slip, x constant in stick until
// |f cos ωt − kx| exceeds μN, slip → stick where ẋ = 0 and the force is admissible, slip
// reversal otherwise. Integrated from rest until the state at t = nT repeats.
struct StickSlipReference {
  struct State {
    double t = 0, x = 0, v = 0;
    int sigma = 0;
  };

  OneDof o;
  bool converged = false;
  double t0 = 0;
  std::vector<Segment> segments;  // the period [t0, t0 + T)

  explicit StickSlipReference(const OneDof& oscillator) : o(oscillator) {
    const double period = o.Period();
    State s = Decide({0.0, 0.0, 0.0, 0});
    for (int n = 1; n <= 5000 && !converged; ++n) {
      const State next = Advance(s, n * period, nullptr);
      converged = std::abs(next.x - s.x) + std::abs(next.v - s.v) / o.omega <
                      1e-13 * (std::abs(next.x) + 1) &&
                  next.sigma == s.sigma;
      s = next;
    }
    t0 = s.t;
    Advance(s, t0 + period, &segments);
  }

  // The mode that Coulomb's law gives at rest or keeps when sliding.
  State Decide(State s) const {
    if (s.v != 0) return s;
    const double drive = o.f * std::cos(o.omega * s.t) - o.k * s.x;
    s.sigma = std::abs(drive) <= o.limit ? 0 : (drive > 0 ? 1 : -1);
    return s;
  }

  State Advance(State s, double t_end, std::vector<Segment>* out) const {
    const double step = o.Period() / 4096;
    while (s.t < t_end) {
      Segment seg;
      seg.t_begin = s.t;
      seg.sigma = s.sigma;
      double t_event;
      if (s.sigma == 0) {
        seg.x_stick = s.x;
        t_event = FirstEvent(
            [&](double t) { return std::abs(o.f * std::cos(o.omega * t) - o.k * s.x) - o.limit; },
            s.t, t_end, step);
      } else {
        seg.slip = SlipPhase(o, s.t, s.x, s.v, s.sigma);
        t_event = FirstEvent([&](double t) { return -s.sigma * seg.slip.V(t); }, s.t, t_end, step);
      }
      seg.t_end = std::min(t_event, t_end);
      if (out != nullptr) out->push_back(seg);
      State next{seg.t_end, seg.X(seg.t_end), s.sigma == 0 ? 0.0 : seg.slip.V(seg.t_end), s.sigma};
      if (t_event <= t_end) {
        // A stop or a release: the velocity is zero there and Coulomb's law picks the mode.
        next.v = 0;
        next.sigma = 0;
        next = Decide(next);
        if (s.sigma == 0 && next.sigma == 0) {
          next.sigma = o.f * std::cos(o.omega * next.t) - o.k * next.x > 0 ? 1 : -1;
        }
      }
      s = next;
    }
    return s;
  }

  double X(double t) const {
    const double period = o.Period();
    const double tau = t0 + std::fmod(std::fmod(t - t0, period) + period, period);
    for (const Segment& seg : segments) {
      if (tau < seg.t_end) return seg.X(tau);
    }
    return segments.back().X(tau);
  }
  // Extremes of x are at the segments' ends (x is monotone in slip, constant in stick).
  double MaxAbs() const {
    double largest = 0;
    for (const Segment& seg : segments) {
      largest = std::max({largest, std::abs(seg.X(seg.t_begin)), std::abs(seg.X(seg.t_end))});
    }
    return largest;
  }
  int StickPhases() const {
    int count = 0;
    for (const Segment& seg : segments) count += seg.sigma == 0;
    if (segments.size() > 1 && segments.front().sigma == 0 && segments.back().sigma == 0) --count;
    return count;
  }
  double StickFraction() const {
    double stuck = 0;
    for (const Segment& seg : segments) stuck += seg.sigma == 0 ? seg.t_end - seg.t_begin : 0;
    return stuck / o.Period();
  }
  // Friction dissipation over the period: μN times the distance slid.
  double FrictionWork() const {
    double distance = 0;
    for (const Segment& seg : segments) {
      if (seg.sigma != 0) distance += std::abs(seg.X(seg.t_end) - seg.X(seg.t_begin));
    }
    return o.limit * distance;
  }
  // (a_1, b_1) of x = a_1 cos ωt + b_1 sin ωt + ..., by 8-point Gauss–Legendre on pieces of at
  // most T/256 of each segment (the closed forms are smooth there: error ≪ 1e-14).
  Eigen::Vector2d FirstHarmonic() const {
    static const double kNodes[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                     0.9602898564975363};
    static const double kWeights[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                       0.1012285362903763};
    Eigen::Vector2d ab = Eigen::Vector2d::Zero();
    const double period = o.Period();
    for (const Segment& seg : segments) {
      const int pieces =
          std::max(1, static_cast<int>(std::ceil((seg.t_end - seg.t_begin) / (period / 256))));
      const double h = (seg.t_end - seg.t_begin) / pieces;
      for (int p = 0; p < pieces; ++p) {
        const double mid = seg.t_begin + (p + 0.5) * h;
        for (int q = 0; q < 4; ++q) {
          for (double sign : {-1.0, 1.0}) {
            const double t = mid + sign * kNodes[q] * h / 2;
            const double w = kWeights[q] * h / 2 * seg.X(t);
            ab += w * Eigen::Vector2d(std::cos(o.omega * t), std::sin(o.omega * t));
          }
        }
      }
    }
    return ab * 2 / period;
  }
};

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// A TransientModel of dense matrices, forcing f_0 cos ωt on DOF 0 (as the cases), and one
// exact friction law on `dof` against ground.
TransientModel FrictionModel(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c,
                             const Eigen::MatrixXd& k, double force, int dof, double limit,
                             bool massless) {
  TransientModel model;
  model.model.mass = m.sparseView();
  model.model.damping = c.sparseView();
  model.model.stiffness = k.sparseView();
  ForcingTerm term;
  term.dof = 0;
  term.cos = force;
  model.forcing = {term};
  auto law = std::make_unique<FrictionTimeLaw>(dof, -1, Exact(limit), massless);
  // As MakeTransientModel: an undamped massless DOF gets its momentum row differentiated.
  law->set_differentiated(massless && c.row(dof).isZero(0.0));
  model.laws.push_back(std::move(law));
  model.law_paths = {"nonlinearities[0]"};
  model.massless.assign(static_cast<size_t>(m.rows()), false);
  model.massless[static_cast<size_t>(dof)] = massless;
  return model;
}

TransientModel OneDofModel(const OneDof& o) {
  return FrictionModel(Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Constant(1, 1, o.c),
                       Eigen::MatrixXd::Constant(1, 1, o.k), o.f, 0, o.limit, false);
}

InitialState Rest(int n) { return {Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)}; }

// (a_1, b_1) of uniform samples over one period starting at ωt0 ≡ 0 (mod 2π): the trapezoidal
// rule, exact for harmonics below N/2; x is C¹ with jumps in ẍ, so its harmonics fall like
// 1/h³ and the aliasing error is ~1e-9 relative for N = 1024.
Eigen::Vector2d SampledFirstHarmonic(const PeriodRecord& record, int dof) {
  const int n = static_cast<int>(record.t.size());
  const double omega = 2 * kPi / record.period;
  Eigen::Vector2d ab = Eigen::Vector2d::Zero();
  for (int i = 0; i < n; ++i) {
    const double phase = omega * record.t(i);
    ab += record.x(dof, i) * Eigen::Vector2d(std::cos(phase), std::sin(phase));
  }
  return ab * 2 / n;
}

// Relative energy balance defect over the recorded period.
double BalanceDefect(const PeriodRecord& r) {
  return std::abs(r.work_input - r.work_damping - r.work_laws - r.energy_change) /
         std::abs(r.work_input);
}

// The one-DOF case (cases/friction/one_dof_coulomb.json).
constexpr double kOneDofC = 0.1, kOneDofK = 1.0, kOneDofF = 1.0, kOneDofLimit = 0.5;

// Runs stop when the state changes by less than this per period; the slowest contraction per
// period (free decay e^{−cT/2} = 0.73 at ω = 1) leaves the orbit within 1e-9/(1 − 0.73) ≈ 4e-9.
constexpr double kSteadyTolerance = 1e-9;

TransientOptions Options(int samples) {
  TransientOptions options;
  options.steady_tolerance = kSteadyTolerance;
  options.samples_per_period = samples;
  return options;
}

// Same-instant comparison with a closed form: IDA at rtol 1e-10 is accurate to ~1e-9
// (design notes), the orbit to ~4e-9; the steady sampled maximum of the reference needs no
// tolerance since both are read at the same instants. 1e-6 relative is the accuracy asked for
// the validation, with a margin of 100 over the expected error.
constexpr double kHistoryTolerance = 1e-6;

// The energy balance closes to the quadratures' accuracy: each is integrated by IDA at rtol
// 1e-10 over a period whose terms are ~100× the balance's net, and a restart at each of the
// ~8 events per period adds ~1e-10 relative (measured defects ≤ 5e-9).
constexpr double kBalanceTolerance = 1e-7;

TEST_CASE("Friction time law: IDA reproduces Den Hartog's continuous sliding") {
  constexpr int kSamples = 8192;
  // max over 8192 samples misses a peak of curvature κ by ≤ κ(T/2N)²/2; at the reversal
  // κ ≤ f − μN + kX ≤ 1.2ω²X for these ω, so ≤ 0.6(π/8192)² ≈ 9e-8 relative.
  constexpr double kSampledPeakTolerance = 1e-6;
  for (double w : {1.0, 1.5, 2.0}) {
    CAPTURE(w);
    const auto start = std::chrono::steady_clock::now();
    const testing::DenHartog exact =
        testing::SolveDenHartog(w, kOneDofC, kOneDofK, kOneDofF, kOneDofLimit);
    REQUIRE(exact.converged);
    REQUIRE(exact.continuous_sliding);
    TransientModel model = OneDofModel({kOneDofC, kOneDofK, kOneDofF, kOneDofLimit, w});
    IdaIntegrator ida(model, Options(kSamples));
    const TransientResult result = ida.RunToSteadyState(w, Rest(1));
    CAPTURE(result.message);
    REQUIRE(result.periodic());
    const PeriodRecord& rec = result.last_period;
    // x(t) = X_h(τ) for τ = t − t_rev ∈ [0, T/2) after the reversal at ωt_rev ≡ φ, −x beyond.
    const testing::HalfPeriod half(w, kOneDofC, kOneDofK, kOneDofF, kOneDofLimit, exact.amplitude,
                                   exact.phi);
    const double period = 2 * kPi / w;
    double history_error = 0, reference_max = 0;
    for (int i = 0; i < kSamples; ++i) {
      double tau = std::fmod(rec.t(i) - exact.phi / w, period);
      if (tau < 0) tau += period;
      const double x = tau < period / 2 ? half.X(tau) : -half.X(tau - period / 2);
      history_error = std::max(history_error, std::abs(rec.x(0, i) - x));
      reference_max = std::max(reference_max, std::abs(x));
    }
    const double ida_max = rec.x.row(0).cwiseAbs().maxCoeff();
    CHECK(history_error < kHistoryTolerance * exact.amplitude);
    CHECK(std::abs(ida_max - reference_max) < kHistoryTolerance * exact.amplitude);
    CHECK(std::abs(ida_max - exact.amplitude) < kSampledPeakTolerance * exact.amplitude);
    CHECK(rec.phases.at(0).CountPhases(rec.t0, rec.period) == 0);
    MESSAGE("ω = " << w << ": X = " << exact.amplitude << ", IDA max|x| error "
                   << (ida_max - exact.amplitude) / exact.amplitude << " (same samples "
                   << (ida_max - reference_max) / exact.amplitude << "), history error "
                   << history_error / exact.amplitude << ", " << result.periods << " periods, "
                   << result.events << " events, " << Seconds(start) << " s");
  }
}

TEST_CASE("Friction time law: IDA stick-slip matches an event-driven closed-form solution") {
  constexpr double kOmega = 0.5;
  constexpr int kSamples = 1024;
  const auto start = std::chrono::steady_clock::now();
  const StickSlipReference ref({kOneDofC, kOneDofK, kOneDofF, kOneDofLimit, kOmega});
  REQUIRE(ref.converged);
  REQUIRE(ref.StickPhases() == 2);  // a stop at each reversal: the case asked for
  TransientModel model = OneDofModel(ref.o);
  IdaIntegrator ida(model, Options(kSamples));
  const TransientResult result = ida.RunToSteadyState(kOmega, Rest(1));
  CAPTURE(result.message);
  REQUIRE(result.periodic());
  const PeriodRecord& rec = result.last_period;
  double history_error = 0, reference_max = 0;
  for (int i = 0; i < kSamples; ++i) {
    history_error = std::max(history_error, std::abs(rec.x(0, i) - ref.X(rec.t(i))));
    reference_max = std::max(reference_max, std::abs(ref.X(rec.t(i))));
  }
  const double scale = ref.MaxAbs();
  const double ida_max = rec.x.row(0).cwiseAbs().maxCoeff();
  const Eigen::Vector2d h1 = SampledFirstHarmonic(rec, 0);
  const Eigen::Vector2d h1_ref = ref.FirstHarmonic();
  const int sticks = rec.phases.at(0).CountPhases(rec.t0, rec.period);
  const double fraction = rec.phases.at(0).PhaseFraction(rec.t0, rec.period);
  CHECK(history_error < kHistoryTolerance * scale);
  // Both maxima are attained in stick phases (x flat), which the samples resolve exactly.
  CHECK(std::abs(ida_max - scale) < kHistoryTolerance * scale);
  CHECK((h1 - h1_ref).norm() < kHistoryTolerance * h1_ref.norm());
  CHECK(sticks == ref.StickPhases());
  // Event times: root location to ~1e-12 T plus the state error / slope ~1e-9 T.
  CHECK(std::abs(fraction - ref.StickFraction()) < kHistoryTolerance);
  // Friction absorbs μN × distance slid; the quadratures share IDA's accuracy.
  CHECK(rec.work_laws > 0);
  CHECK(std::abs(rec.work_laws - ref.FrictionWork()) < kHistoryTolerance * ref.FrictionWork());
  CHECK(BalanceDefect(rec) < kBalanceTolerance);
  MESSAGE("ω = " << kOmega << ": max|x| " << scale << " (IDA error " << (ida_max - scale) / scale
                 << "), history error " << history_error / scale << ", first harmonic "
                 << h1_ref.norm() << " (error " << (h1 - h1_ref).norm() / h1_ref.norm()
                 << "), stick phases " << sticks << ", fraction " << fraction << " (reference "
                 << ref.StickFraction() << "), friction work " << rec.work_laws << " (reference "
                 << ref.FrictionWork() << "), balance defect " << BalanceDefect(rec) << ", "
                 << result.periods << " periods, " << result.events << " events, " << Seconds(start)
                 << " s");
}

// The two-DOF oscillator of cases/friction (Legrand & Pierre 2024, Fig. 6): friction on x2
// against ground, f1 = 20 cos ωt.
TransientModel TwoDofModel(double m2, double d2, double limit, bool massless) {
  Eigen::Matrix2d m, c, k;
  m << 1, 0, 0, m2;
  c << 0.02 + d2, -d2, -d2, d2;
  k << 2, -1, -1, 1;
  return FrictionModel(m, c, k, 20.0, 1, limit, massless);
}

TEST_CASE("Friction time law: two-DOF oscillator at omega = 0.308 sticks four times") {
  const auto start = std::chrono::steady_clock::now();
  TransientModel model = TwoDofModel(1.0, 0.02, 0.9 * 10, false);
  IdaIntegrator ida(model, Options(1024));
  const TransientResult result = ida.RunToSteadyState(0.308, Rest(2));
  CAPTURE(result.message);
  REQUIRE(result.periodic());
  const PeriodRecord& rec = result.last_period;
  const int sticks = rec.phases.at(0).CountPhases(rec.t0, rec.period);
  CHECK(sticks == 4);  // Legrand & Pierre (2024), point E of Fig. 6
  CHECK(rec.work_laws > 0);
  CHECK(BalanceDefect(rec) < kBalanceTolerance);
  // In stick the friction does no work; while sliding it absorbs μN|v|: ∫ from the samples.
  const auto& velocity = rec.law_signals.at(0).at(1);
  REQUIRE(velocity.first == "velocity");
  const double sampled_work =
      0.9 * 10 * velocity.second.cwiseAbs().sum() * rec.period / rec.t.size();
  // The trapezoidal rule on |v| (kinks at the stops) errs by ~(T/N)² ≈ 1e-4 relative.
  constexpr double kSampledWorkTolerance = 1e-3;
  CHECK(std::abs(sampled_work - rec.work_laws) < kSampledWorkTolerance * rec.work_laws);
  MESSAGE("ω = 0.308: " << sticks << " stick phases, stick fraction "
                        << rec.phases[0].PhaseFraction(rec.t0, rec.period) << ", friction work "
                        << rec.work_laws << " (from samples " << sampled_work << "), input "
                        << rec.work_input << ", balance defect " << BalanceDefect(rec) << ", "
                        << result.periods << " periods, " << result.events << " events, "
                        << Seconds(start) << " s");
}

TEST_CASE("Friction time law: massless undamped slider by index reduction") {
  // The damper-mass study's limit m2 = 0, d2 = 0: in slip the row K_1 x − r = 0 with r = ∓μN
  // pins x_1 (index 2); the integrator differentiates it and r becomes differential.
  constexpr double kOmega = 0.4, kLimit = 0.9 * 6.5;
  constexpr int kSamples = 1024;
  auto start = std::chrono::steady_clock::now();
  TransientModel massless = TwoDofModel(0.0, 0.0, kLimit, true);
  REQUIRE(massless.laws[0]->OwnIsDifferential(0));
  IdaIntegrator ida(massless, Options(kSamples));
  const TransientResult result = ida.RunToSteadyState(kOmega, Rest(2));
  CAPTURE(result.message);
  REQUIRE(result.periodic());
  const double massless_seconds = Seconds(start);
  const PeriodRecord& rec = result.last_period;
  const int sticks = rec.phases.at(0).CountPhases(rec.t0, rec.period);
  CHECK(rec.work_laws > 0);
  // The projection onto the undifferentiated row at every restart keeps the balance exact to
  // the quadratures' accuracy (as kBalanceTolerance); 1e-6 leaves room for the drift between
  // restarts, which the differentiated row does not see.
  CHECK(BalanceDefect(rec) < 1e-6);
  const auto& force = rec.law_signals.at(0).at(0);
  REQUIRE(force.first == "force");
  const double largest_force = force.second.cwiseAbs().maxCoeff();
  CHECK(largest_force <= kLimit * (1 + 1e-9));
  // The undifferentiated row K_1 x − r = 0 still holds on the samples: the projections at the
  // restarts remove the drift, and between them it stays at IDA's accuracy (rtol 1e-10 of
  // forces ~10: 1e-9; measured 3e-14).
  const Eigen::VectorXd row = rec.x.row(1) - rec.x.row(0) - force.second.transpose();
  const double drift = row.cwiseAbs().maxCoeff();
  CHECK(drift < 1e-9 * kLimit);
  const double h1 = SampledFirstHarmonic(rec, 0).norm();

  // Independent check: a small slider mass m2 = 1e-3 (index 1, the existing formulation),
  // started on the massless orbit (v_1 = the massless ẋ_1), must come to nearly the same orbit.
  // The slider then has a natural frequency √(k/m2) = 31.6 rad/s ≫ ω: its inertia force m2·ẍ_1
  // is a quasi-static correction of order (ω/31.6)² ≈ 2e-4 plus short transients at each
  // stick-slip switch, which the light slider rings through (it sticks ~20 times per period
  // instead of twice). Measured: the h1 difference falls with m2 (9.5e-4, 5.7e-4, 1.7e-4 at
  // m2 = 1e-3, 3e-4, 1e-4), so the massless orbit is the m2 → 0 limit; 1 % is 10× the value
  // at 1e-3, yet an error of the reduction (a wrong ẋ_1 or r in slip) would move h1 by far more.
  start = std::chrono::steady_clock::now();
  TransientModel massed = TwoDofModel(1e-3, 0.0, kLimit, false);
  TransientOptions options = Options(kSamples);
  options.steady_tolerance = 1e-7;  // the comparison is at 1 %
  IdaIntegrator ida_massed(massed, options);
  const InitialState orbit{rec.x.col(0), rec.v.col(0)};
  const TransientResult check = ida_massed.RunToSteadyState(kOmega, orbit);
  CAPTURE(check.message);
  REQUIRE(check.periodic());
  const double h1_massed = SampledFirstHarmonic(check.last_period, 0).norm();
  CHECK(std::abs(h1_massed - h1) < 0.01 * h1);
  MESSAGE("massless slider, ω = "
          << kOmega << ": h1(x_0) " << h1 << " (m2 = 1e-3: " << h1_massed
          << ", relative difference " << (h1_massed - h1) / h1 << "), stick phases " << sticks
          << ", fraction " << rec.phases[0].PhaseFraction(rec.t0, rec.period) << ", max|r| "
          << largest_force << " (μN " << kLimit << "), row drift " << drift << ", balance defect "
          << BalanceDefect(rec) << ", " << result.periods << " periods, " << result.events
          << " events, " << massless_seconds << " s; m2 = 1e-3: " << check.periods << " periods, "
          << check.last_period.phases[0].CountPhases(check.last_period.t0, check.last_period.period)
          << " stick phases, " << Seconds(start) << " s");
}

TEST_CASE("Friction time law: massless damped slider (index 1) matches a light one") {
  // d2 = 0.02 > 0: the massless row holds C v, so v_1 is algebraic and nothing is
  // differentiated. A stick entered at r = ∓μN exactly must still release when the force
  // moves outward (it did not while its root started at zero: the slider stuck for good).
  constexpr double kOmega = 0.4, kLimit = 0.9 * 6.5, kD2 = 0.02;
  const auto start = std::chrono::steady_clock::now();
  TransientModel massless = TwoDofModel(0.0, kD2, kLimit, true);
  REQUIRE_FALSE(massless.laws[0]->OwnIsDifferential(0));
  const TransientResult result =
      IdaIntegrator(massless, Options(1024)).RunToSteadyState(kOmega, Rest(2));
  CAPTURE(result.message);
  REQUIRE(result.periodic());
  const PeriodRecord& rec = result.last_period;
  CHECK(BalanceDefect(rec) < kBalanceTolerance);
  CHECK(rec.law_signals.at(0).at(0).second.cwiseAbs().maxCoeff() <= kLimit * (1 + 1e-9));
  // With m2 = 1e-4 the slider's own mode (√(k/m2) = 100 rad/s) is critically damped by d2
  // (ζ = d2/(2√(k m2)) = 1), and its inertia shifts the orbit by ~m2·ω²/k ≈ 2e-5 relative
  // (measured 1.5e-5); 1e-3 leaves margin and is far below the stuck slider's error (h1 10.9).
  TransientModel light = TwoDofModel(1e-4, kD2, kLimit, false);
  const TransientResult check =
      IdaIntegrator(light, Options(1024)).RunToSteadyState(kOmega, Rest(2));
  CAPTURE(check.message);
  REQUIRE(check.periodic());
  const double h1 = SampledFirstHarmonic(rec, 0).norm();
  const double h1_light = SampledFirstHarmonic(check.last_period, 0).norm();
  CHECK(std::abs(h1_light - h1) < 1e-3 * h1);
  CHECK(rec.phases.at(0).CountPhases(rec.t0, rec.period) ==
        check.last_period.phases.at(0).CountPhases(check.last_period.t0, check.last_period.period));
  MESSAGE("massless damped slider: h1(x_0) "
          << h1 << " (m2 = 1e-4: " << h1_light << "), stick phases "
          << rec.phases[0].CountPhases(rec.t0, rec.period) << ", balance defect "
          << BalanceDefect(rec) << ", " << result.periods << " periods, " << Seconds(start)
          << " s");
}

TEST_CASE("Friction time law: reference solution reproduces Den Hartog when sliding") {
  // Both are closed forms evaluated to round-off; the event search adds bisection to 4e-16 T.
  constexpr double kReferenceTolerance = 1e-9;
  for (double w : {1.0, 1.5, 2.0}) {
    CAPTURE(w);
    const testing::DenHartog exact =
        testing::SolveDenHartog(w, kOneDofC, kOneDofK, kOneDofF, kOneDofLimit);
    REQUIRE(exact.continuous_sliding);
    const StickSlipReference ref({kOneDofC, kOneDofK, kOneDofF, kOneDofLimit, w});
    REQUIRE(ref.converged);
    CHECK(ref.StickPhases() == 0);
    CHECK(ref.MaxAbs() == doctest::Approx(exact.amplitude).epsilon(kReferenceTolerance));
    CHECK(ref.FrictionWork() ==
          doctest::Approx(4 * kOneDofLimit * exact.amplitude).epsilon(kReferenceTolerance));
  }
}

}  // namespace
}  // namespace nfrc
