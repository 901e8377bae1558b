#include "validation/transient_model.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "core/input_fields.h"
#include "nonlinearities/registry.h"
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

std::vector<std::unique_ptr<Nonlinearity>> Laws(const LinearModel& model,
                                                const std::vector<std::string>& specs) {
  std::vector<std::unique_ptr<Nonlinearity>> laws;
  for (size_t i = 0; i < specs.size(); ++i) {
    laws.push_back(MakeNonlinearity(nlohmann::json::parse(specs[i]),
                                    "nonlinearities[" + std::to_string(i) + "]", model));
  }
  return laws;
}

TEST_CASE("Transient model: every harmonic law maps to its time-domain form") {
  const LinearModel model = TwoDof(1.0);
  const auto laws =
      Laws(model, {R"({"type": "coulomb_friction", "dof": 1, "mu": 0.9, "normal_load": 10})",
                   R"({"type": "cubic_spring", "dof": 0, "coefficient": 0.5})",
                   R"({"type": "polynomial_spring", "dof": 0, "other": 1,
          "terms": [{"power": 2, "coefficient": 1}]})",
                   R"({"type": "penalty_contact", "dof": 0, "gap": 0.1, "stiffness": 100})",
                   R"({"type": "dlft_contact", "dof": 1, "gap": 0.1, "obstacle_stiffness": 100})",
                   R"({"type": "dlft_contact", "dof": 0, "gap": 0.2})",
                   R"({"type": "lcp_contact", "dof": 1, "gap": 0.3})"});
  const TransientModel t = MakeTransientModel(model, {}, laws);
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
  const auto spring = Laws(massless, {R"({"type": "cubic_spring", "dof": 1, "coefficient": 1})"});
  CHECK(MakeTransientModel(massless, {}, spring).massless == std::vector<bool>{false, true});
  const auto friction = Laws(massless, {R"({"type": "coulomb_friction", "dof": 1, "mu": 0.9,
                                            "normal_load": 6.5})"});
  // Exact friction on a massless DOF: accepted. A damped one keeps the index-1 form; an
  // undamped one gets its momentum row differentiated by the integrator (index 2 in slip).
  const TransientModel damped = MakeTransientModel(massless, {}, friction);
  CHECK(damped.massless == std::vector<bool>{false, true});
  REQUIRE(damped.laws.size() == 1);
  CHECK_FALSE(dynamic_cast<const FrictionTimeLaw&>(*damped.laws[0]).differentiated());
  LinearModel undamped = TwoDof(0.0);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(2, 2);
  c(0, 0) = 0.02;
  undamped.damping = c.sparseView();
  const TransientModel reduced = MakeTransientModel(undamped, {}, friction);
  CHECK(reduced.massless == std::vector<bool>{false, true});
  REQUIRE(reduced.laws.size() == 1);
  CHECK(dynamic_cast<const FrictionTimeLaw&>(*reduced.laws[0]).differentiated());
  CHECK(reduced.laws[0]->OwnIsDifferential(0));

  LinearModel coupled = TwoDof(0.0);
  Eigen::MatrixXd m(2, 2);
  m << 1, 0.1, 0.1, 0;
  coupled.mass = m.sparseView();
  CHECK_THROWS_WITH_AS(MakeTransientModel(coupled, {}, {}), doctest::Contains("model.M"),
                       InputError);

  const LinearModel massed = TwoDof(1.0);
  const auto sign = Laws(massed, {R"({"type": "coulomb_friction", "dof": 1, "mu": 0.9,
                                      "normal_load": 6.5, "law": "sign"})"});
  CHECK_THROWS_WITH_AS(MakeTransientModel(massed, {}, sign),
                       doctest::Contains("nonlinearities[0].law"), InputError);
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
