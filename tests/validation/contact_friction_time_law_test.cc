// Contact with friction in the time domain: Jacobians against finite differences, the mode logic
// against the law's definition, and IDA runs on a two-DOF mass (normal x_n, tangential x_t)
// against exact Coulomb friction under the static normal load, in permanent stick, and through
// separations.
#include "validation/contact_friction_time_law.h"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "validation/friction_time_law.h"
#include "validation/ida_integrator.h"
#include "validation/time_law_check.h"
#include "validation/transient_model.h"

namespace nfrc {
namespace {

using Mode = ContactFrictionTimeLaw::Mode;

// Central differences with h = 1e-7 of residuals affine in y and ẏ within a mode (the gap
// harmonics depend on the phase only): round-off ε|F|/h ≈ 1e-8 of entries up to k = 300;
// 1e-6 relative leaves a margin and still catches any wrong entry (all are O(1) to O(k)).
constexpr double kJacobianTolerance = 1e-6;

constexpr double kTime = 2.0, kPhase = 3.0;  // the hand-built states' t and φ

ContactGeometry Normal(int dof, int other, double direction, double gap) {
  ContactGeometry g;
  g.dof = dof;
  g.other = other;
  g.direction = direction;
  g.gap = gap;
  return g;
}

// A hand-built DAE state [x | v | r] with ẏ = [ẋ | a | ṙ] over `n` DOFs, the law's own
// unknown r last.
struct LawState {
  TimeLawLayout layout;
  Eigen::VectorXd y, yp;
  LawState(const Eigen::VectorXd& x, const Eigen::VectorXd& v, const Eigen::VectorXd& a, double r) {
    const int n = static_cast<int>(x.size());
    layout.num_dofs = n;
    layout.own_offset = 2 * n;
    y.resize(2 * n + 1);
    yp.resize(2 * n + 1);
    y << x, v, r;
    yp << (v.array() + 0.25).matrix(), a, 0.9;
  }
  DaeView View(const TimeLaw& law) const { return MakeDaeView(law, layout, kTime, kPhase, y, yp); }
  Eigen::VectorXd Residual(const TimeLaw& law) const {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(y.size());
    law.Residual(layout, View(law), f);
    return f;
  }
  std::vector<double> Roots(const TimeLaw& law) const {
    std::vector<double> g(static_cast<size_t>(law.NumRoots()));
    law.Roots(layout, View(law), g.data());
    return g;
  }
};

// Five DOFs: normal.dof 0, tangent_dof 1, normal.other 2, tangent_other 3 (when used) and an
// unrelated DOF 4. The state puts the gap at `gap` (through x_0) with the sliding velocity
// v_1 − v_3 (v_1 against ground) = `v_rel`.
LawState FiveDofState(const ContactFrictionTimeLaw& law, int tangent_other, double gap,
                      double v_rel, double r) {
  const double v_other = tangent_other >= 0 ? 0.4 : 0.0;
  Eigen::VectorXd x(5), v(5), a(5);
  x << 0.3, -0.7, 0.2, 1.1, 0.5;
  v << 0.6, v_other + v_rel, -0.3, 0.4, 0.8;
  a << -1.3, 0.7, 0.4, 2.2, -0.6;
  const double n = law.normal().direction;
  x(0) += (law.Gap(kPhase, x) - gap) / n;  // ∂g/∂x_0 = −n
  return LawState(x, v, a, r);
}

TEST_CASE("Contact-friction time law: residual, force and Jacobian in every mode") {
  constexpr double kStiffness = 300.0, kMu = 0.4, kPreload = 2.5;
  for (double direction : {1.0, -1.0}) {
    for (int normal_other : {-1, 2}) {
      for (int tangent_other : {-1, 3}) {
        CAPTURE(direction);
        CAPTURE(normal_other);
        CAPTURE(tangent_other);
        ContactGeometry normal = Normal(0, normal_other, direction, 0.05);
        normal.gap_harmonics.push_back({2, 0.01, -0.02});
        ContactFrictionTimeLaw law(normal, kStiffness, 1, tangent_other, kMu, kPreload);
        CHECK(law.type() == "contact_friction");
        REQUIRE(law.NumOwn() == 1);
        CHECK_FALSE(law.OwnIsDifferential(0));
        CHECK(law.NumRoots() == 4);
        CHECK(law.PhaseName() == "stick");
        struct Case {
          double gap, v_rel;
          Mode mode;
        };
        for (const Case& c :
             {Case{0.02, 0.5, Mode::kOpen}, Case{-0.01, 0.5, Mode::kSlipPositive},
              Case{-0.01, -0.5, Mode::kSlipNegative}, Case{-0.01, 0.0, Mode::kStick}}) {
          CAPTURE(static_cast<int>(c.mode));
          const double r = 0.7;
          const LawState s = FiveDofState(law, tangent_other, c.gap, c.v_rel, r);
          law.InitMode(s.layout, s.View(law));
          REQUIRE(law.mode() == c.mode);
          CHECK(law.ModeIndex() == static_cast<int>(c.mode));
          CHECK(law.InPhase() == (c.mode == Mode::kStick));
          CHECK(law.Gap(kPhase, s.y.head(5)) == doctest::Approx(c.gap));
          for (double cj : {0.0, 3.7}) {
            const TimeLawCheck check =
                CheckTimeLawJacobian(law, s.layout, kTime, kPhase, s.y, s.yp, cj);
            CAPTURE(cj);
            CAPTURE(check.worst);
            CHECK(check.Passed(kJacobianTolerance));
          }
          // Momentum rows: −n N0 (+n N0) always; closed: +n λ (−n λ) with λ = −k g, and −r on
          // tangent_dof (+r on tangent_other). Own row: r open, r ± μλ slip±, relative a stick.
          const bool closed = c.mode != Mode::kOpen;
          const double lambda = closed ? -kStiffness * c.gap : 0.0;
          const double applied_r = closed ? r : 0.0;
          const Eigen::VectorXd f = s.Residual(law);
          const TimeLawLayout& l = s.layout;
          CHECK(f(l.Momentum(0)) == doctest::Approx(direction * (lambda - kPreload)));
          CHECK(f(l.Momentum(1)) == doctest::Approx(-applied_r));
          CHECK(f(l.Momentum(2)) ==
                doctest::Approx(normal_other >= 0 ? -direction * (lambda - kPreload) : 0.0));
          CHECK(f(l.Momentum(3)) == doctest::Approx(tangent_other >= 0 ? applied_r : 0.0));
          CHECK(f(l.Momentum(4)) == 0.0);
          CHECK(f.head(5).isZero(0.0));
          const double a_rel = s.yp(5 + 1) - (tangent_other >= 0 ? s.yp(5 + 3) : 0.0);
          const double own_row = c.mode == Mode::kOpen           ? r
                                 : c.mode == Mode::kSlipPositive ? r + kMu * lambda
                                 : c.mode == Mode::kSlipNegative ? r - kMu * lambda
                                                                 : a_rel;
          CHECK(f(l.Own(0)) == doctest::Approx(own_row));
          // Force() is the momentum rows' f_nl.
          Eigen::VectorXd f_nl = Eigen::VectorXd::Zero(5);
          law.Force(s.layout, s.View(law), f_nl);
          CHECK((f_nl - f.segment(5, 5)).norm() < 1e-12);
          Eigen::VectorXd unused = Eigen::VectorXd::Zero(5);
          CHECK_FALSE(law.ExplicitForce(kPhase, s.y.head(5), s.y.segment(5, 5), unused));
          const auto signals = law.Signals(s.layout, s.View(law));
          REQUIRE(signals.size() == 4);
          CHECK(signals[0].first == "gap");
          CHECK(signals[0].second == doctest::Approx(c.gap));
          CHECK(signals[1].first == "normal_force");
          CHECK(signals[1].second == doctest::Approx(kStiffness * std::max(0.0, -c.gap)));
          CHECK(signals[2].first == "friction_force");
          CHECK(signals[2].second == applied_r);
          CHECK(signals[3].first == "velocity");
          CHECK(signals[3].second == doctest::Approx(c.v_rel));
        }
        const auto bound = law.StiffnessBound();
        REQUIRE(bound.size() == (normal_other >= 0 ? 2u : 1u));
        CHECK(bound[0] == std::pair<int, double>(0, kStiffness));
        if (normal_other >= 0) CHECK(bound[1] == std::pair<int, double>(2, kStiffness));
      }
    }
  }
}

TEST_CASE("Contact-friction time law: bad parameters are refused naming the field") {
  auto message = [](auto make) {
    try {
      make();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  auto field = [&](auto make) {
    const std::string text = message(make);
    return text.substr(0, text.find(':'));
  };
  const ContactGeometry good = Normal(0, -1, 1.0, 0.0);
  const double nan = std::nan("");
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(field([&] { ContactFrictionTimeLaw(good, 0.0, 1, -1, 0.3, 1.0); }) == "obstacle_stiffness");
  CHECK(message([&] { ContactFrictionTimeLaw(good, 0.0, 1, -1, 0.3, 1.0); }).find("rigid") !=
        std::string::npos);
  CHECK(field([&] { ContactFrictionTimeLaw(good, -5.0, 1, -1, 0.3, 1.0); }) ==
        "obstacle_stiffness");
  CHECK(field([&] { ContactFrictionTimeLaw(good, inf, 1, -1, 0.3, 1.0); }) == "obstacle_stiffness");
  CHECK(field([&] { ContactFrictionTimeLaw(good, nan, 1, -1, 0.3, 1.0); }) == "obstacle_stiffness");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, -1, -0.1, 1.0); }) == "mu");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, -1, nan, 1.0); }) == "mu");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, -1, inf, 1.0); }) == "mu");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, -1, 0.3, -1.0); }) == "preload");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, -1, 0.3, inf); }) == "preload");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, -1, -1, 0.3, 1.0); }) == "tangent_dof");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 0, -1, 0.3, 1.0); }) == "tangent_dof");
  CHECK(field([&] { ContactFrictionTimeLaw(Normal(0, 2, 1.0, 0.0), 1.0, 2, -1, 0.3, 1.0); }) ==
        "tangent_dof");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, 1, 0.3, 1.0); }) == "tangent_other");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, 0, 0.3, 1.0); }) == "tangent_other");
  CHECK(field([&] { ContactFrictionTimeLaw(Normal(0, 2, 1.0, 0.0), 1.0, 1, 2, 0.3, 1.0); }) ==
        "tangent_other");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, -2, 0.3, 1.0); }) == "tangent_other");
  CHECK(field([&] { ContactFrictionTimeLaw(Normal(0, 0, 1.0, 0.0), 1.0, 1, -1, 0.3, 1.0); }) ==
        "other");
  CHECK(field([&] { ContactFrictionTimeLaw(Normal(-1, -1, 1.0, 0.0), 1.0, 1, -1, 0.3, 1.0); }) ==
        "dof");
  CHECK(field([&] { ContactFrictionTimeLaw(Normal(0, -1, 0.5, 0.0), 1.0, 1, -1, 0.3, 1.0); }) ==
        "direction");
  CHECK(field([&] { ContactFrictionTimeLaw(Normal(0, -1, 1.0, nan), 1.0, 1, -1, 0.3, 1.0); }) ==
        "gap");
  CHECK(field([&] { ContactFrictionTimeLaw(good, 1.0, 1, -1, 0.3, 1.0, -1e-9); }) ==
        "admissibility_tolerance");
  // The limits of the ranges are fine: μ = 0, N0 = 0, −1 for "none".
  CHECK(message([&] { ContactFrictionTimeLaw(good, 1.0, 1, -1, 0.0, 0.0); }) == "no exception");
  CHECK(message([&] { ContactFrictionTimeLaw(Normal(0, 2, -1.0, 0.1), 1.0, 1, 3, 0.3, 1.0); }) ==
        "no exception");
  // Massless DOFs are refused (the stick row is an acceleration).
  ContactFrictionTimeLaw law(good, 1.0, 1, -1, 0.3, 1.0);
  CHECK(message([&] { law.set_massless(false); }) == "no exception");
  CHECK(field([&] { law.set_massless(true); }) == "dof");
}

TEST_CASE("Contact-friction time law: mode switches follow the contact and Coulomb rules") {
  // Obstacle on the positive side of DOF 0 at zero gap (g = −x_0), tangential DOF 1 at x_1 = 0.5,
  // both against ground: λ = k x_0 when closed, the limit μk x_0; the tangential velocity scale
  // is ≈ ω x_1 = 0.75 m/s, so "v near zero" means |v| ≲ 1e3 × tol × 0.75 ≈ 1e-6 m/s.
  constexpr double kStiffness = 100.0, kMu = 0.5, kPreload = 1.0, kTolerance = 1e-9;
  ContactFrictionTimeLaw law(Normal(0, -1, 1.0, 0.0), kStiffness, 1, -1, kMu, kPreload, kTolerance);
  auto state = [](double x_n, double v_t, double a_t, double r, double v_n = 0.0,
                  double a_n = 0.0) {
    return LawState(Eigen::Vector2d(x_n, 0.5), Eigen::Vector2d(v_n, v_t), Eigen::Vector2d(a_n, a_t),
                    r);
  };
  auto init = [&](const LawState& s) {
    law.InitMode(s.layout, s.View(law));
    return law.mode();
  };
  auto admissible = [&](const LawState& s) { return law.Admissible(s.layout, s.View(law)); };
  auto on_root = [&](const LawState& s, int root) {
    law.OnRoot(s.layout, s.View(law), root);
    return law.mode();
  };

  // Open: the gap is the only live root; friction roots are constants.
  const LawState away = state(-0.01, 0.3, 0.0, 0.0);
  REQUIRE(init(away) == Mode::kOpen);
  std::vector<double> g = away.Roots(law);
  CHECK(g == std::vector<double>{0.01, 1.0, 1.0, 1.0});
  CHECK(admissible(away));
  CHECK_FALSE(law.InPhase());

  // Closed at x_0 = 0.02: λ = 2, limit μλ = 1. The slip root is v.
  const LawState sliding = state(0.02, 0.3, 0.0, -1.0);
  REQUIRE(init(sliding) == Mode::kSlipPositive);
  g = sliding.Roots(law);
  CHECK(g[0] == doctest::Approx(-0.02));
  CHECK(g[1] == doctest::Approx(0.3));
  CHECK(g[2] == 1.0);
  CHECK(g[3] == 1.0);
  CHECK(admissible(sliding));
  CHECK(init(state(0.02, -0.3, 0.0, 1.0)) == Mode::kSlipNegative);

  // Stick: the release roots are μλ(1 + tol) ∓ r (roots 2 and 3; v's root 1 is inactive).
  const LawState holding = state(0.02, 0.0, 0.0, 0.4);
  REQUIRE(init(holding) == Mode::kStick);
  CHECK(law.InPhase());
  g = holding.Roots(law);
  CHECK(g[0] == doctest::Approx(-0.02));
  CHECK(g[1] == 1.0);
  CHECK(g[2] == doctest::Approx(1.0 * (1 + kTolerance) - 0.4));
  CHECK(g[3] == doctest::Approx(1.0 * (1 + kTolerance) + 0.4));
  CHECK(admissible(holding));
  // Within the tolerance band the stick holds; beyond it friction saturates against the excess.
  CHECK(admissible(state(0.02, 0.0, 0.0, -1.0 * (1 + 0.5 * kTolerance))));
  CHECK(law.mode() == Mode::kStick);
  CHECK_FALSE(admissible(state(0.02, 0.0, 0.0, 1.01)));
  CHECK(law.mode() == Mode::kSlipNegative);
  // Slip− from rest: admissible if it accelerates that way, else stick.
  CHECK(admissible(state(0.02, 0.0, -0.3, 1.0)));
  CHECK_FALSE(admissible(state(0.02, 0.0, 0.3, 1.0)));
  CHECK(law.mode() == Mode::kStick);
  // Stick root 2 (r reached +μλ) starts slip−, root 3 (−μλ) slip+.
  CHECK(on_root(holding, 2) == Mode::kSlipNegative);
  REQUIRE(init(holding) == Mode::kStick);
  CHECK(on_root(holding, 3) == Mode::kSlipPositive);
  // Slip root 1 (v crossed zero) → stick; a slip plainly the wrong way reverses.
  CHECK(on_root(state(0.02, -1e-3, 0.0, -1.0), 1) == Mode::kStick);
  REQUIRE(init(sliding) == Mode::kSlipPositive);
  CHECK_FALSE(admissible(state(0.02, -0.3, 0.0, -1.0)));
  CHECK(law.mode() == Mode::kSlipNegative);

  // Opening: the gap root opens from any closed mode, sticking included, and the friction
  // roots of the same event are then ignored.
  const LawState lifted = state(-1e-6, 0.0, 0.0, 0.4);
  REQUIRE(init(holding) == Mode::kStick);
  g = lifted.Roots(law);
  CHECK(g[0] > 0.0);  // the gap root has crossed: it is reported
  CHECK(g[2] < 0.0);  // and so has the release bound (it falls to zero with λ)
  CHECK(on_root(lifted, 0) == Mode::kOpen);
  CHECK(on_root(lifted, 2) == Mode::kOpen);
  CHECK(admissible(lifted));
  // A friction root alone at a positive gap opens too.
  REQUIRE(init(holding) == Mode::kStick);
  CHECK(on_root(lifted, 3) == Mode::kOpen);
  // A friction root while open changes nothing.
  CHECK(on_root(state(-0.01, 0.0, 0.0, 0.0), 1) == Mode::kOpen);

  // Closing: slip in the direction of v, stick from rest.
  REQUIRE(init(away) == Mode::kOpen);
  CHECK(on_root(state(1e-9, 0.3, 0.0, 0.0), 0) == Mode::kSlipPositive);
  REQUIRE(init(away) == Mode::kOpen);
  CHECK(on_root(state(1e-9, -0.3, 0.0, 0.0), 0) == Mode::kSlipNegative);
  // However small v is, and against the acceleration: the slip root must start on v's side
  // (the growing limit could turn a slip against v around before v crosses zero).
  const LawState creeping = state(1e-9, 1e-12, -0.3, 0.0);
  REQUIRE(init(away) == Mode::kOpen);
  CHECK(on_root(creeping, 0) == Mode::kSlipPositive);
  CHECK(admissible(creeping));
  // Elsewhere such a slip, v within the near-zero band, decelerating, is a stick.
  CHECK_FALSE(admissible(creeping));
  CHECK(law.mode() == Mode::kStick);
  REQUIRE(init(away) == Mode::kOpen);
  CHECK(on_root(state(1e-9, 0.0, 0.0, 0.0), 0) == Mode::kStick);
  // A closing root reported again (gap still negative) keeps the closed mode.
  CHECK(on_root(state(2e-9, 0.3, 0.0, 0.0), 0) == Mode::kStick);
  // A mode contradicting the gap is not admissible.
  REQUIRE(init(away) == Mode::kOpen);
  CHECK_FALSE(admissible(state(0.01, -0.3, 0.0, 0.0)));
  CHECK(law.mode() == Mode::kSlipNegative);
  CHECK_FALSE(admissible(away));
  CHECK(law.mode() == Mode::kOpen);

  // Zero limit, exactly on the obstacle (g = 0, λ = 0): a stick holds only with r = 0, and the
  // gap's motion decides between open and closed (IDA would ignore a gap root that starts at
  // zero, so the mode must be right there).
  const LawState touching = state(0.0, 0.0, 0.0, 0.0, 0.0, 0.5);  // pressed in: g̈ < 0
  REQUIRE(init(state(0.02, 0.0, 0.0, 0.0)) == Mode::kStick);
  CHECK(admissible(touching));
  CHECK(law.mode() == Mode::kStick);
  CHECK_FALSE(admissible(state(0.0, 0.0, 0.0, 1e-12, 0.0, 0.5)));
  CHECK(law.mode() == Mode::kSlipNegative);
  CHECK(admissible(state(0.0, 0.0, -0.3, 0.0, 0.0, 0.5)));
  // Closed at g = 0 but pulled off (g̈ > 0) or moving off (ġ > 0): open.
  CHECK_FALSE(admissible(state(0.0, 0.0, -0.3, 0.0, 0.0, -0.5)));
  CHECK(law.mode() == Mode::kOpen);
  CHECK(admissible(state(0.0, 0.0, -0.3, 0.0, 0.0, -0.5)));
  // Open at g = 0 and pressed in from rest (a start from rest on the obstacle): closes.
  CHECK_FALSE(admissible(touching));
  CHECK(law.mode() == Mode::kStick);
  CHECK_FALSE(admissible(state(0.0, 0.0, 0.0, 0.0, -0.2, 0.5)));  // ġ = −v_n·n > 0
  CHECK(law.mode() == Mode::kOpen);
  CHECK_FALSE(admissible(state(0.0, 0.3, 0.0, 0.0, 0.2, -0.5)));  // ġ < 0 wins over g̈
  CHECK(law.mode() == Mode::kSlipPositive);
  // InitMode on g = 0: ġ, then g̈ from the view's accelerations (zero at a start, where
  // Admissible decides once they are consistent).
  CHECK(init(state(0.0, 0.0, 0.0, 0.0, 0.2)) == Mode::kStick);
  CHECK(init(state(0.0, 0.0, 0.0, 0.0, -0.2)) == Mode::kOpen);
  CHECK(init(state(0.0, 0.0, 0.0, 0.0, 0.0, 0.5)) == Mode::kStick);
  CHECK(init(state(0.0, 0.0, 0.0, 0.0)) == Mode::kOpen);
  // A gap root reported exactly at g = 0 toggles.
  CHECK(on_root(touching, 0) == Mode::kStick);
  CHECK(on_root(touching, 0) == Mode::kOpen);

  // μ = 0: no stick, the slip direction follows v.
  ContactFrictionTimeLaw free(Normal(0, -1, 1.0, 0.0), kStiffness, 1, -1, 0.0, kPreload);
  const LawState rest = state(0.02, 0.0, 0.0, 0.0);
  free.InitMode(rest.layout, rest.View(free));
  CHECK(free.mode() == Mode::kSlipPositive);
  CHECK(free.Admissible(rest.layout, rest.View(free)));
  free.OnRoot(rest.layout, rest.View(free), 1);
  CHECK(free.mode() == Mode::kSlipNegative);
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Runs stop when the state changes by less than this per period; the slowest contraction per
// period here (the tangential free decay e^{−c_t T/2}, 0.81 at the highest ω = 1.5) leaves the
// orbit within 1e-9/(1 − 0.81) ≈ 5e-9 of it.
constexpr double kSteadyTolerance = 1e-9;

TransientOptions Options(int samples) {
  TransientOptions options;
  options.steady_tolerance = kSteadyTolerance;
  options.samples_per_period = samples;
  options.max_periods = 1000;  // a few hundred at most here; a failure should not run on
  return options;
}

InitialState Rest(int n) { return {Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)}; }

// The energy balance of the linear part over the recorded period closes to the quadratures'
// accuracy (rtol 1e-10 over terms ~100× the net, plus ~1e-10 per restart; the friction tests
// measure ≤ 5e-9).
constexpr double kBalanceTolerance = 1e-7;

double BalanceDefect(const PeriodRecord& r) {
  return std::abs(r.work_input - r.work_damping - r.work_laws - r.energy_change) /
         std::abs(r.work_input);
}

const Eigen::VectorXd& Signal(const PeriodRecord& r, size_t law, const std::string& name) {
  for (const auto& [key, values] : r.law_signals.at(law)) {
    if (key == name) return values;
  }
  FAIL("no signal " << name);
  static const Eigen::VectorXd kNone;
  return kNone;
}

// The two-DOF mass: x_n (DOF 0) against the obstacle on its positive side at zero gap, x_t
// (DOF 1) sliding on it; M = I, springs k_n, k_t and dampers to ground: c_t on x_t, and on x_n
// 5 % of critical for the closed contact's k + k_n (light, yet its ringing after each impact
// dies within a period).
struct TwoDof {
  double k_n = 1.0, k_t = 1.0, c_t = 0.1;
  double stiffness = 1e4, mu = 0.05, preload = 10.0;
  double f_t = 1.0;  // tangential forcing f_t cos ωt on x_t (N)
  double f_n = 0.0;  // normal forcing f_n sin ωt on x_n (N; positive presses in)
  double normal_static() const { return preload * stiffness / (stiffness + k_n); }

  TransientModel Model() const {
    TransientModel model;
    model.model.mass = Eigen::Matrix2d::Identity().sparseView();
    const double c_n = 2 * 0.05 * std::sqrt(stiffness + k_n);
    model.model.damping = Eigen::Vector2d(c_n, c_t).asDiagonal().toDenseMatrix().sparseView();
    model.model.stiffness = Eigen::Vector2d(k_n, k_t).asDiagonal().toDenseMatrix().sparseView();
    ForcingTerm tangential;
    tangential.dof = 1;
    tangential.cos = f_t;
    model.forcing = {tangential};
    if (f_n != 0.0) {
      ForcingTerm normal;
      normal.dof = 0;
      normal.sin = f_n;
      model.forcing.push_back(normal);
    }
    auto law = std::make_unique<ContactFrictionTimeLaw>(Normal(0, -1, 1.0, 0.0), stiffness, 1, -1,
                                                        mu, preload);
    law->set_massless(false);
    model.laws.push_back(std::move(law));
    model.law_paths = {"nonlinearities[0]"};
    model.massless.assign(2, false);
    return model;
  }
};

// The reference of (a): ẍ + c_t ẋ + k_t x = f_t cos ωt + r with exact Coulomb friction of limit
// `limit` (FrictionTimeLaw, min_max), steady state from rest.
PeriodRecord CoulombReference(const TwoDof& o, double omega, double limit, int samples) {
  TransientModel model;
  model.model.mass = Eigen::MatrixXd::Ones(1, 1).sparseView();
  model.model.damping = Eigen::MatrixXd::Constant(1, 1, o.c_t).sparseView();
  model.model.stiffness = Eigen::MatrixXd::Constant(1, 1, o.k_t).sparseView();
  ForcingTerm term;
  term.dof = 0;
  term.cos = o.f_t;
  model.forcing = {term};
  FrictionParameters exact;
  exact.equality = FrictionEquality::kMinMax;
  exact.limit = limit;
  model.laws.push_back(std::make_unique<FrictionTimeLaw>(0, -1, exact, false));
  model.law_paths = {"nonlinearities[0]"};
  model.massless = {false};
  const TransientResult result =
      IdaIntegrator(model, Options(samples)).RunToSteadyState(omega, Rest(1));
  CAPTURE(result.message);
  REQUIRE(result.periodic());
  return result.last_period;
}

TEST_CASE("Contact-friction time law: IDA under a large preload is Coulomb friction") {
  // No normal forcing: x_n settles on the static balance (k + k_n) x_n = N0 and stays there, so
  // λ_N = N0 k/(k + k_n) (N0 to k_n/k = 1e-4) and x_t obeys exact Coulomb friction with the
  // constant limit μλ_N: FrictionTimeLaw on the one-DOF tangential model is an independent
  // reference (its own law, its own DAE). The run starts from rest exactly on the obstacle
  // (g = 0): the preload must close the contact there.
  TwoDof o;
  const double limit = o.mu * o.normal_static();
  // Same equations once x_n has settled (e^{−5t}: to round-off within the first periods), both
  // at IDA's accuracy (~1e-9 of the amplitude) and steady to ~5e-9: 1e-6 leaves a margin of 100
  // (as the friction tests' history tolerance).
  constexpr double kCoulombTolerance = 1e-6;
  constexpr int kSamples = 1024;
  for (double w : {0.5, 1.5}) {  // stick-slip (two stops per period) and continuous sliding
    CAPTURE(w);
    const auto start = std::chrono::steady_clock::now();
    TransientModel model = o.Model();
    const TransientResult result =
        IdaIntegrator(model, Options(kSamples)).RunToSteadyState(w, Rest(2));
    CAPTURE(result.message);
    REQUIRE(result.periodic());
    const PeriodRecord& rec = result.last_period;
    const PeriodRecord ref = CoulombReference(o, w, limit, kSamples);
    // The normal force: N0 to k_n/k, and exactly the static balance to IDA's accuracy.
    const Eigen::VectorXd& normal_force = Signal(rec, 0, "normal_force");
    CHECK(normal_force.minCoeff() == doctest::Approx(o.preload).epsilon(2 * o.k_n / o.stiffness));
    CHECK((normal_force.array() - o.normal_static()).abs().maxCoeff() <
          kCoulombTolerance * o.preload);
    // Same samples, same phases: both records start at a multiple of T.
    const double scale = ref.x.row(0).cwiseAbs().maxCoeff();
    const double difference = (rec.x.row(1) - ref.x.row(0)).cwiseAbs().maxCoeff();
    const double amplitude = rec.x.row(1).cwiseAbs().maxCoeff();
    CHECK(difference < kCoulombTolerance * scale);
    CHECK(std::abs(amplitude - scale) < kCoulombTolerance * scale);
    // The friction force is the reference's, and the stick phases are the same.
    const Eigen::VectorXd& friction = Signal(rec, 0, "friction_force");
    const Eigen::VectorXd& reference_force = Signal(ref, 0, "force");
    CHECK((friction - reference_force).cwiseAbs().maxCoeff() < kCoulombTolerance * limit);
    const int sticks = rec.phases.at(0).CountPhases(rec.t0, rec.period);
    CHECK(sticks == ref.phases.at(0).CountPhases(ref.t0, ref.period));
    CHECK(sticks == (w < 1 ? 2 : 0));
    // Dissipation: the friction's (the preload and the obstacle spring are conservative).
    CHECK(std::abs(rec.work_laws - ref.work_laws) < kCoulombTolerance * ref.work_laws);
    CHECK(BalanceDefect(rec) < kBalanceTolerance);
    MESSAGE("ω = " << w << ": max|x_t| " << amplitude << " (Coulomb " << scale
                   << "), max|x_t − x_Coulomb| " << difference / scale << " relative, λ_N "
                   << normal_force.mean() << " (N0 " << o.preload << "), stick phases " << sticks
                   << ", dissipation " << rec.work_laws << " (Coulomb " << ref.work_laws
                   << "), balance defect " << BalanceDefect(rec) << ", " << result.periods
                   << " periods, " << result.events << " events, " << Seconds(start) << " s");
  }
}

TEST_CASE("Contact-friction time law: IDA below the friction limit sticks") {
  // f_t = 0.8 μN0 static: after the closing transient (during which λ_N rings through small
  // values and x_t may slip a little) the tangential DOF sticks for good at some x_s with
  // |f_t cos ωt − k_t x_s| < μλ_N. At resonance (ω = 1) a sliding x_t would be large.
  TwoDof o;
  o.f_t = 0.8 * o.mu * o.preload;
  constexpr double kOmega = 1.0;
  constexpr int kSamples = 256;
  const auto start = std::chrono::steady_clock::now();
  TransientModel model = o.Model();
  const TransientResult result =
      IdaIntegrator(model, Options(kSamples)).RunToSteadyState(kOmega, Rest(2));
  CAPTURE(result.message);
  REQUIRE(result.periodic());
  const PeriodRecord& rec = result.last_period;
  // Stuck over the whole period: one stick phase covering it, no sliding velocity (the index-1
  // stick holds the velocity it started with, ~1e-14 of the scale; 1e-9 f_t/ω leaves a margin),
  // x_t constant, and the friction force the static balance r = −(f_t cos ωt − k_t x_s).
  CHECK(rec.phases.at(0).CountPhases(rec.t0, rec.period) == 1);
  CHECK(rec.phases.at(0).PhaseFraction(rec.t0, rec.period) == doctest::Approx(1.0));
  const Eigen::VectorXd& velocity = Signal(rec, 0, "velocity");
  CHECK(velocity.cwiseAbs().maxCoeff() < 1e-9 * o.f_t / kOmega);
  const double x_s = rec.x(1, 0);
  CHECK((rec.x.row(1).array() - x_s).abs().maxCoeff() < 1e-9 * o.f_t / o.k_t);
  // The transient slip is confined to the first normal oscillations (2π/√k ≈ 0.06 s each, λ_N
  // rebounding to 15 % of N0 at the first): ≲ f_t (0.1 s)²/2 = 5e-3 f_t/k_t.
  CHECK(std::abs(x_s) < 0.01 * o.f_t / o.k_t);
  const Eigen::VectorXd& friction = Signal(rec, 0, "friction_force");
  double balance_error = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double drive = o.f_t * std::cos(kOmega * rec.t(i)) - o.k_t * x_s;
    balance_error = std::max(balance_error, std::abs(friction(i) + drive));
  }
  // IDA's force at rtol 1e-10: 1e-8 of f_t leaves a margin.
  CHECK(balance_error < 1e-8 * o.f_t);
  // A stuck contact absorbs nothing (the preload and the obstacle spring at rest neither).
  CHECK(std::abs(rec.work_laws) < 1e-8 * o.f_t * o.f_t / o.k_t);
  MESSAGE("stick at ω = 1: x_s " << x_s << ", max|v_t| " << velocity.cwiseAbs().maxCoeff()
                                 << ", static balance error " << balance_error << ", "
                                 << result.periods << " periods, " << result.events << " events, "
                                 << Seconds(start) << " s");
}

TEST_CASE("Contact-friction time law: IDA through separations keeps Coulomb's bounds") {
  // f_n = 2 N0 on x_n separates the contact for part of each period (k = 100). Checked on every
  // sample: no force at all while open (r exactly zero: the law applies none), |r| ≤ μλ_N (1 + tol)
  // while closed, and r = −μλ_N sign v while sliding.
  TwoDof o;
  o.stiffness = 100.0;
  o.mu = 0.5;
  o.preload = 1.0;
  o.f_n = 2.0 * o.preload;
  o.f_t = 0.6;
  constexpr double kOmega = 0.8;
  constexpr int kSamples = 1024;
  // IDA's Newton solves r to ~0.33(rtol|r| + atol_r) ≈ 1e-11 of the force scale and the release
  // root overshoots the bound by ~ṙ × the root tolerance (~1e-14 T): 1e-9 of the force scale
  // as absolute slack on top of the admissibility tolerance.
  constexpr double kForceSlack = 1e-9;
  const double force_scale = o.f_t + o.f_n + o.preload;
  const auto start = std::chrono::steady_clock::now();
  TransientModel model = o.Model();
  const TransientResult result =
      IdaIntegrator(model, Options(kSamples)).RunToSteadyState(kOmega, Rest(2));
  CAPTURE(result.message);
  REQUIRE(result.periodic());
  const PeriodRecord& rec = result.last_period;
  const Eigen::VectorXd& gap = Signal(rec, 0, "gap");
  const Eigen::VectorXd& lambda = Signal(rec, 0, "normal_force");
  const Eigen::VectorXd& r = Signal(rec, 0, "friction_force");
  const Eigen::VectorXd& v = Signal(rec, 0, "velocity");
  const double v_scale = v.cwiseAbs().maxCoeff();
  int open = 0, sliding = 0, holding = 0;
  double worst_open = 0.0, worst_slip = 0.0;
  double worst_bound = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < kSamples; ++i) {
    const double limit = o.mu * lambda(i);
    if (gap(i) > 0.0) {
      ++open;
      worst_open = std::max(worst_open, std::abs(r(i)));
      continue;
    }
    worst_bound = std::max(worst_bound, std::abs(r(i)) - limit * (1 + 1e-9));
    if (std::abs(v(i)) > 1e-6 * v_scale) {
      ++sliding;
      worst_slip = std::max(worst_slip, std::abs(r(i) + limit * (v(i) > 0 ? 1 : -1)));
    } else {
      ++holding;
    }
  }
  CHECK(worst_open == 0.0);
  CHECK(worst_bound <= kForceSlack * force_scale);
  CHECK(worst_slip <= kForceSlack * force_scale);
  // Not vacuous: the period has open, sliding and sticking samples.
  CHECK(open > 0);
  CHECK(sliding > 0);
  CHECK(holding > 0);
  CHECK(rec.phases.at(0).CountPhases(rec.t0, rec.period) > 0);
  // Energy: the balance of the linear part closes, and over the periodic orbit the law absorbs
  // only the friction's μλ_N|v| (the preload and the obstacle spring are conservative): ∫−r v dt
  // from the samples. r v is continuous (v = 0 where r jumps at a stop, λ = 0 where the contact
  // opens or closes) with kinks: the trapezoidal rule errs by ~(T/N)² ≈ 4e-5 relative; 1e-3.
  CHECK(BalanceDefect(rec) < kBalanceTolerance);
  const double sampled_work = -(r.array() * v.array()).sum() * rec.period / kSamples;
  CHECK(rec.work_laws > 0.0);
  CHECK(std::abs(sampled_work - rec.work_laws) < 1e-3 * rec.work_laws);
  MESSAGE(
      "separating at ω = " << kOmega << ": open " << open << ", sliding " << sliding << ", stuck "
                           << holding << " of " << kSamples << " samples, stick phases "
                           << rec.phases.at(0).CountPhases(rec.t0, rec.period)
                           << ", max(|r| − μλ_N(1 + tol)) " << worst_bound << ", slip force error "
                           << worst_slip << ", min gap " << gap.minCoeff() << ", max gap "
                           << gap.maxCoeff() << ", friction work " << rec.work_laws << " (samples "
                           << sampled_work << "), balance defect " << BalanceDefect(rec) << ", "
                           << result.periods << " periods, " << result.events << " events, "
                           << Seconds(start) << " s");
}

TEST_CASE("Contact-friction time law: IDA with a vanishing tangential load scales with it") {
  // The separating run of above with f_t ≪ μN0. Then x_t sticks whenever the contact is closed
  // but for slips of duration O(f_t) next to the closings and openings (where μλ_N < |drive|),
  // and flies freely while open: the response is f_t times that of a linear problem, up to
  // O(f_t) relative corrections (measured 5e-5 at f_t = 1e-6). The tangential motion is then
  // ~1e-6 of the normal one, inside any near-zero band taken on the whole state, and each
  // closing starts the limit from zero: a slip taken there against a small v would be reversed
  // by the growing limit before v crossed zero and run away (its root never firing). f_t = 0
  // exercises the degenerate case: every closing sticks with zero limit and r = 0, and every
  // opening comes with both release roots at once.
  TwoDof o;
  o.stiffness = 100.0;
  o.mu = 0.5;
  o.preload = 1.0;
  o.f_n = 2.0 * o.preload;
  constexpr double kOmega = 0.8;
  constexpr int kSamples = 512;
  // The O(f_t) corrections at 1e-6 and IDA's accuracy: 1e-3 (a runaway is 1e4 times off).
  constexpr double kScalingTolerance = 1e-3;
  struct Run {
    double v_max = 0, r_max = 0;
    int sticks = 0;
  };
  auto run = [&](double f_t) {
    o.f_t = f_t;
    const auto start = std::chrono::steady_clock::now();
    TransientModel model = o.Model();
    const TransientResult result =
        IdaIntegrator(model, Options(kSamples)).RunToSteadyState(kOmega, Rest(2));
    CAPTURE(f_t);
    CAPTURE(result.message);
    REQUIRE(result.periodic());
    const PeriodRecord& rec = result.last_period;
    Run out;
    out.v_max = Signal(rec, 0, "velocity").cwiseAbs().maxCoeff();
    out.r_max = Signal(rec, 0, "friction_force").cwiseAbs().maxCoeff();
    out.sticks = rec.phases.at(0).CountPhases(rec.t0, rec.period);
    MESSAGE("f_t = " << f_t << ": max|v_t| " << out.v_max << ", max|r| " << out.r_max
                     << ", stick phases " << out.sticks << ", " << result.periods << " periods, "
                     << result.events << " events, " << Seconds(start) << " s");
    return out;
  };
  const Run unloaded = run(0.0);
  CHECK(unloaded.v_max == 0.0);
  CHECK(unloaded.r_max == 0.0);
  CHECK(unloaded.sticks > 0);
  const Run small = run(1e-9);
  const Run larger = run(1e-6);
  CHECK(small.v_max > 0.0);
  CHECK(larger.v_max / 1e-6 == doctest::Approx(small.v_max / 1e-9).epsilon(kScalingTolerance));
  CHECK(larger.r_max / 1e-6 == doctest::Approx(small.r_max / 1e-9).epsilon(kScalingTolerance));
  CHECK(larger.sticks == small.sticks);
}

}  // namespace
}  // namespace nfrc
