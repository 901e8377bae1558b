#include "validation/transient_model.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "core/errors.h"
#include "validation/friction_time_law.h"
#include "validation/period_measures.h"

namespace nfrc {
namespace {

LinearModel TwoDof(double m2) {
  LinearModel model;
  Eigen::MatrixXd m(2, 2), k(2, 2);
  m << 1, 0, 0, m2;
  k << 2, -1, -1, 1;
  model.mass = m.sparseView();
  model.damping = (0.01 * k).sparseView();
  model.stiffness = k.sparseView();
  return model;
}

TransientModel Make(const LinearModel& model, const std::vector<LawSpec>& laws) {
  return MakeTransientModel(ModelDefinition{model, {}}, laws);
}

ContactGeometry Gap(int dof, double gap) {
  ContactGeometry geometry;
  geometry.dof = dof;
  geometry.gap = gap;
  return geometry;
}

CoulombFrictionSpec Friction(int dof, double mu, double normal_load) {
  CoulombFrictionSpec spec;
  spec.dof = dof;
  spec.mu = mu;
  spec.normal_load = normal_load;
  return spec;
}

TEST_CASE("Transient model: every harmonic law maps to its time-domain form") {
  const LinearModel model = TwoDof(1.0);
  const std::vector<LawSpec> laws = {Friction(1, 0.9, 10),
                                     CubicSpringSpec{0, -1, 0.5},
                                     PolynomialSpringSpec{0, 1, {{2, 1.0}}},
                                     PenaltyContactSpec{Gap(0, 0.1), 100},
                                     DlftContactSpec{{Gap(1, 0.1), 100, 0}},
                                     DlftContactSpec{{Gap(0, 0.2), 0, 0}},
                                     LcpContactSpec{{Gap(1, 0.3), 0, 0}, 0}};
  const TransientModel t = Make(model, laws);
  REQUIRE(t.laws.size() == 5);
  CHECK(t.laws[0]->type() == "coulomb_friction");
  CHECK(t.laws[1]->type() == "cubic_spring");
  CHECK(t.laws[2]->type() == "polynomial_spring");
  CHECK(t.laws[3]->type() == "penalty_contact");
  CHECK(t.laws[4]->type() == "dlft_contact");  // flexible obstacle: a penalty spring
  CHECK(t.law_paths[4] == "nonlinearities[4]");
  REQUIRE(t.rigid_contacts.size() == 2);  // rigid obstacles go to the explicit scheme
  CHECK(t.rigid_contacts[0].gap == 0.2);
  CHECK(t.rigid_contacts[1].dof == 1);
  CHECK(t.massless == std::vector<bool>{false, false});
}

TEST_CASE("Transient model: massless DOFs and refused inputs name the field") {
  const LinearModel massless = TwoDof(0.0);
  const std::vector<LawSpec> spring = {CubicSpringSpec{1, -1, 1}};
  CHECK(Make(massless, spring).massless == std::vector<bool>{false, true});
  const std::vector<LawSpec> friction = {Friction(1, 0.9, 6.5)};
  // Exact friction on a massless DOF: accepted. A damped one keeps the index-1 form; an
  // undamped one gets its momentum row differentiated by the integrator (index 2 in slip).
  const TransientModel damped = Make(massless, friction);
  CHECK(damped.massless == std::vector<bool>{false, true});
  REQUIRE(damped.laws.size() == 1);
  CHECK_FALSE(dynamic_cast<const FrictionTimeLaw&>(*damped.laws[0]).differentiated());
  LinearModel undamped = TwoDof(0.0);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(2, 2);
  c(0, 0) = 0.02;
  undamped.damping = c.sparseView();
  const TransientModel reduced = Make(undamped, friction);
  CHECK(reduced.massless == std::vector<bool>{false, true});
  REQUIRE(reduced.laws.size() == 1);
  CHECK(dynamic_cast<const FrictionTimeLaw&>(*reduced.laws[0]).differentiated());
  CHECK(reduced.laws[0]->OwnIsDifferential(0));

  LinearModel coupled = TwoDof(0.0);
  Eigen::MatrixXd m(2, 2);
  m << 1, 0.1, 0.1, 0;
  coupled.mass = m.sparseView();
  CHECK_THROWS_WITH_AS(Make(coupled, {}), doctest::Contains("model.M"), InputError);

  const LinearModel massed = TwoDof(1.0);
  CoulombFrictionSpec sign_law = Friction(1, 0.9, 6.5);
  sign_law.law = FrictionEquality::kSign;
  const std::vector<LawSpec> sign = {sign_law};
  CHECK_THROWS_WITH_AS(Make(massed, sign), doctest::Contains("nonlinearities[0].law"), InputError);
}

// The DFT of N uniform samples of a trigonometric polynomial of degree < N/2 is exact to
// round-off.
constexpr double kRoundOff = 1e-12;

TEST_CASE("Transient model: period measures of a known signal") {
  constexpr int kSamples = 64;
  PeriodRecord record;
  record.period = 2.0;
  record.t = Eigen::VectorXd::LinSpaced(kSamples, 0.0, 2.0 * (kSamples - 1) / kSamples);
  record.x.resize(1, kSamples);
  for (int i = 0; i < kSamples; ++i) {
    const double theta = 2.0 * std::numbers::pi * i / kSamples;
    record.x(0, i) = 3.0 * std::cos(theta) - 4.0 * std::sin(theta) + 0.5 * std::cos(3 * theta);
  }
  record.mean_energy = 7.0;
  record.work_input = 2.0;
  record.work_damping = 1.5;
  record.work_laws = 0.4;
  record.energy_change = 0.0;
  LawPhaseLog log;
  log.type = "coulomb_friction";
  log.phase_name = "stick";
  log.in_phase_at_start = true;
  log.changes = {{0.5, false}, {1.0, true}, {1.5, false}};
  record.phases = {log};
  const PeriodMeasures m = MeasurePeriod(record, {0});
  const Eigen::Vector2d ab = FirstHarmonic(record.x.row(0).transpose());
  CHECK(ab(0) == doctest::Approx(3.0).epsilon(kRoundOff));
  CHECK(ab(1) == doctest::Approx(-4.0).epsilon(kRoundOff));
  CHECK(m.h1[0] == doctest::Approx(5.0).epsilon(kRoundOff));
  CHECK(m.energy == 7.0);
  CHECK(m.energy_balance_defect == doctest::Approx(0.05));
  // Stick over [0, 0.5) and [1.0, 1.5): two phases covering half the period.
  REQUIRE(m.phase_counts.size() == 1);
  CHECK(m.phase_names[0] == "stick");
  CHECK(m.phase_counts[0] == 2);
  CHECK(m.phase_fractions[0] == doctest::Approx(0.5));
}

}  // namespace
}  // namespace nfrc
