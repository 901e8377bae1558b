#include "tools/law_reader.h"

#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "nonlinearities/coulomb_friction.h"
#include "nonlinearities/dlft_contact.h"
#include "nonlinearities/lcp_contact.h"
#include "nonlinearities/penalty_contact.h"
#include "nonlinearities/polynomial_spring.h"
#include "tools/input_fields.h"

namespace nfrc {
namespace {

// Two unit DOFs named "a" and "b": a model for laws that only resolve DOFs.
LinearModel TwoDofModel() {
  LinearModel model;
  model.mass = Eigen::MatrixXd::Identity(2, 2).sparseView();
  model.stiffness = Eigen::MatrixXd::Identity(2, 2).sparseView();
  model.damping = Eigen::MatrixXd::Zero(2, 2).sparseView();
  model.dof_names = {"a", "b"};
  return model;
}

// The law a case-file object describes, as the system would build it.
std::unique_ptr<Nonlinearity> MakeNonlinearity(const nlohmann::json& spec, const std::string& path,
                                               const LinearModel& model) {
  return MakeHarmonicLaw(ReadLaw(spec, path, model), model);
}

// The InputError message of reading the JSON `text` on TwoDofModel, or "no error".
std::string LawInputError(const std::string& text) {
  try {
    MakeNonlinearity(nlohmann::json::parse(text), "nonlinearities[0]", TwoDofModel());
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

// True if `message` starts by naming `field` of the law ("nonlinearities[0].<field>: ").
bool NamesField(const std::string& message, const std::string& field) {
  return message.rfind("nonlinearities[0]." + field + ": ", 0) == 0;
}

TEST_CASE("coulomb friction: case-file errors name the field") {
  LinearModel model;
  model.mass = Eigen::MatrixXd::Identity(2, 2).sparseView();
  model.stiffness = model.mass;
  model.damping = model.mass;
  auto error = [&](const char* text) {
    try {
      MakeNonlinearity(nlohmann::json::parse(text), "nonlinearities[0]", model);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error(R"({"type": "coulomb_friction", "dof": 1, "mu": -1, "normal_load": 1})") ==
        "nonlinearities[0].mu: must be non-negative");
  CHECK(error(R"({"type": "coulomb_friction", "dof": 1, "mu": 1})") ==
        "nonlinearities[0].normal_load: missing (required)");
  CHECK(error(R"({"type": "coulomb_friction", "dof": 1, "mu": 1, "normal_load": 1,
                  "law": "tanh"})") == "nonlinearities[0].alpha: required by law \"tanh\"");
  CHECK(error(R"({"type": "coulomb_friction", "dof": 1, "mu": 1, "normal_load": 1,
                  "law": "stribeck"})")
            .find("nonlinearities[0].law: unknown friction law") == 0);
  CHECK(error(R"({"type": "coulomb_friction", "dof": 1, "mu": 1, "normal_load": 1,
                  "delta": 1})") == "nonlinearities[0].delta: does not apply to law \"min_max\"");
}

// ---------------------------------------------------------------------------------------
// Case-file errors.
TEST_CASE("DLFT contact: case-file errors name the field") {
  // Valid forms, so each error below is due to the one field changed.
  const LinearModel model = TwoDofModel();
  auto law = MakeNonlinearity(nlohmann::json::parse(R"({"type": "dlft_contact", "dof": "b",
      "gap": 0.1, "obstacle_stiffness": 50, "epsilon": 20})"),
                              "nonlinearities[0]", model);
  CHECK(law->type() == "dlft_contact");
  CHECK(law->Dofs() == std::vector<int>{1});
  CHECK(law->ObstacleCompliance() == std::vector<double>{1.0 / 50});
  const auto& dlft = dynamic_cast<const DlftContact&>(*law);
  CHECK(dlft.epsilon() == 20.0);
  CHECK(dlft.obstacle_stiffness() == 50.0);
  law = MakeNonlinearity(nlohmann::json::parse(R"({"type": "dlft_contact", "dof": 0, "other": 1,
      "direction": -1, "gap": {"constant": 0.1, "harmonics": [{"harmonic": 3, "sin": 0.01}]}})"),
                         "nonlinearities[0]", model);
  CHECK(law->Dofs() == std::vector<int>{0, 1});
  CHECK(law->ObstacleCompliance().empty());                        // rigid
  CHECK(dynamic_cast<const DlftContact&>(*law).epsilon() == 0.0);  // default, unresolved

  CHECK(LawInputError(R"({"type": "dlft_contact", "dof": 0, "other": 1, "gap": 0.1,
                    "obstacle_stiffness": 50})")
            .find("nonlinearities[0].obstacle_stiffness: not allowed with other") == 0);
  CHECK(NamesField(
      LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "obstacle_stiffness": 0})"),
      "obstacle_stiffness"));
  CHECK(NamesField(
      LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "obstacle_stiffness": -1})"),
      "obstacle_stiffness"));
  CHECK(NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "epsilon": 0})"),
                   "epsilon"));
  CHECK(
      NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "epsilon": -3})"),
                 "epsilon"));
  CHECK(NamesField(
      LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "epsilon": "big"})"),
      "epsilon"));
  CHECK(
      NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "direction": 0})"),
                 "direction"));
  CHECK(
      NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "direction": 2})"),
                 "direction"));
  CHECK(NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0,
                          "gap": {"harmonics": [{"harmonic": 0, "cos": 0.1}]}})"),
                   "gap.harmonics[0].harmonic"));
  CHECK(NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0,
                          "gap": {"harmonics": [{"cos": 0.1}]}})"),
                   "gap.harmonics[0].harmonic"));
  CHECK(NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": {"harmonics": 1}})"),
                   "gap.harmonics"));
  CHECK(NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": [0.1]})"), "gap"));
  CHECK(LawInputError(R"({"type": "dlft_contact", "dof": 0})") ==
        "nonlinearities[0].gap: missing (required)");
  CHECK(LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "stiffness": 100})") ==
        "nonlinearities[0].stiffness: unknown key");
  CHECK(LawInputError(R"({"type": "dlft_contact", "dof": 0, "gap": 0.1, "eps": 100})") ==
        "nonlinearities[0].eps: unknown key");
  CHECK(NamesField(LawInputError(R"({"type": "dlft_contact", "dof": 0, "other": 0, "gap": 0.1})"),
                   "other"));
  CHECK(NamesField(LawInputError(R"({"type": "dlft_contact", "dof": "z", "gap": 0.1})"), "dof"));
  // Constructor checks for programmatic use.
  ContactGeometry pair;
  pair.dof = 0;
  pair.other = 1;
  CHECK_THROWS_AS(DlftContact(pair, 10.0, 0.0), std::invalid_argument);
  ContactGeometry grounded;
  grounded.dof = 0;
  CHECK_THROWS_AS(DlftContact(grounded, -1.0, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(DlftContact(grounded, 0.0, -1.0), std::invalid_argument);
  DlftContact refinable(grounded, 0.0, 5.0);
  CHECK_THROWS_AS(refinable.set_epsilon(0.0), std::invalid_argument);
  refinable.set_epsilon(40.0);
  CHECK(refinable.epsilon() == 40.0);
}

TEST_CASE("LCP contact: case-file errors name the field") {
  CHECK(LawInputError(R"({"type": "lcp_contact", "dof": "a", "gap": 1e-3})") == "no error");
  CHECK(LawInputError(R"({"type": "lcp_contact", "dof": "a", "gap": 1e-3,
                          "obstacle_stiffness": 4e9, "epsilon": 1e9})") == "no error");
  CHECK(NamesField(LawInputError(R"({"type": "lcp_contact", "gap": 1e-3})"), "dof"));
  CHECK(NamesField(LawInputError(R"({"type": "lcp_contact", "dof": "a"})"), "gap"));
  CHECK(NamesField(LawInputError(R"({"type": "lcp_contact", "dof": "a", "gap": 1e-3,
                                     "epsilon": -1})"),
                   "epsilon"));
  CHECK(NamesField(LawInputError(R"({"type": "lcp_contact", "dof": "a", "gap": 1e-3,
                                     "obstacle_stiffness": 0})"),
                   "obstacle_stiffness"));
  CHECK(NamesField(LawInputError(R"({"type": "lcp_contact", "dof": "a", "other": "b",
                                     "gap": 1e-3, "obstacle_stiffness": 1e9})"),
                   "obstacle_stiffness"));
  CHECK(NamesField(LawInputError(R"({"type": "lcp_contact", "dof": "a", "gap": 1e-3,
                                     "stiffness": 1e9})"),
                   "stiffness"));
}

TEST_CASE("penalty contact: case-file errors name the field") {
  const LinearModel model = TwoDofModel();
  // Valid forms first, so the errors below are due to the one field changed.
  auto law = MakeNonlinearity(
      nlohmann::json::parse(
          R"({"type": "penalty_contact", "dof": "b", "gap": 1, "stiffness": 100})"),
      "nonlinearities[0]", model);
  CHECK(law->type() == "penalty_contact");
  CHECK(law->Dofs() == std::vector<int>{1});
  CHECK(law->ObstacleCompliance().empty());
  law = MakeNonlinearity(nlohmann::json::parse(R"({"type": "penalty_contact", "dof": 0, "other": 1,
      "direction": -1, "gap": {"constant": 0.5, "harmonics": [{"harmonic": 2, "cos": 0.1}]},
      "stiffness": 100})"),
                         "nonlinearities[0]", model);
  CHECK(law->Dofs() == std::vector<int>{0, 1});

  CHECK(LawInputError(R"({"type": "penalty_contact", "dof": 0, "gap": 1})") ==
        "nonlinearities[0].stiffness: missing (required)");
  CHECK(NamesField(
      LawInputError(R"({"type": "penalty_contact", "dof": 0, "gap": 1, "stiffness": 0})"),
      "stiffness"));
  CHECK(NamesField(
      LawInputError(R"({"type": "penalty_contact", "dof": 0, "gap": 1, "stiffness": -5})"),
      "stiffness"));
  CHECK(NamesField(
      LawInputError(R"({"type": "penalty_contact", "dof": 0, "gap": 1, "stiffness": "hard"})"),
      "stiffness"));
  CHECK(LawInputError(R"({"type": "penalty_contact", "dof": 0, "stiffness": 100})") ==
        "nonlinearities[0].gap: missing (required)");
  CHECK(NamesField(
      LawInputError(R"({"type": "penalty_contact", "dof": 0, "gap": "1", "stiffness": 100})"),
      "gap"));
  CHECK(
      NamesField(LawInputError(R"({"type": "penalty_contact", "dof": 0, "gap": 1, "stiffness": 100,
                          "direction": 0.5})"),
                 "direction"));
  CHECK(NamesField(
      LawInputError(R"({"type": "penalty_contact", "dof": 2, "gap": 1, "stiffness": 100})"),
      "dof"));
  CHECK(NamesField(
      LawInputError(R"({"type": "penalty_contact", "dof": "c", "gap": 1, "stiffness": 100})"),
      "dof"));
  CHECK(NamesField(LawInputError(R"({"type": "penalty_contact", "gap": 1, "stiffness": 100})"),
                   "dof"));
  CHECK(NamesField(LawInputError(R"({"type": "penalty_contact", "dof": 0, "other": "a", "gap": 1,
                          "stiffness": 100})"),
                   "other"));
  CHECK(LawInputError(R"({"type": "penalty_contact", "dof": 0, "gap": 1, "stifness": 100,
                    "stiffness": 100})") == "nonlinearities[0].stifness: unknown key");
  CHECK(NamesField(LawInputError(R"({"type": "penalty_contact", "dof": 0, "stiffness": 100,
                          "gap": {"constant": 1, "harmonics": [{"harmonic": 0, "cos": 1}]}})"),
                   "gap.harmonics[0].harmonic"));
  CHECK(NamesField(LawInputError(R"({"type": "penalty_contact", "dof": 0, "stiffness": 100,
                          "gap": {"constant": 1, "harmonics": [{"harmonic": 1, "cosine": 1}]}})"),
                   "gap.harmonics[0].cosine"));
  CHECK(NamesField(LawInputError(R"({"type": "penalty_contact", "dof": 0, "stiffness": 100,
                          "gap": {"constant": 1, "offset": 2}})"),
                   "gap.offset"));
  // obstacle_stiffness belongs to DLFT: the penalty law is itself the flexible obstacle.
  CHECK(LawInputError(R"({"type": "penalty_contact", "dof": 0, "gap": 1, "stiffness": 100,
                    "obstacle_stiffness": 100})") ==
        "nonlinearities[0].obstacle_stiffness: unknown key");
  CHECK(NamesField(
      LawInputError(R"({"type": "penalty_contacts", "dof": 0, "gap": 1, "stiffness": 100})"),
      "type"));
}

TEST_CASE("registry builds springs from case-file objects and names bad fields") {
  const LinearModel model = TwoDofModel();
  auto law = MakeNonlinearity(
      nlohmann::json::parse(R"({"type": "cubic_spring", "dof": "b", "coefficient": 2})"),
      "nonlinearities[0]", model);
  CHECK(law->type() == "cubic_spring");
  CHECK(law->Dofs() == std::vector<int>{1});

  auto message = [&](const char* text) {
    try {
      MakeNonlinearity(nlohmann::json::parse(text), "nonlinearities[0]", model);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  CHECK(message(R"({"type": "quartic", "dof": 0})").find("nonlinearities[0].type: unknown") == 0);
  CHECK(message(R"({"type": "cubic_spring", "dof": 0})") ==
        "nonlinearities[0].coefficient: missing (required)");
  CHECK(message(R"({"type": "cubic_spring", "dof": 5, "coefficient": 1})")
            .find("nonlinearities[0].dof: DOF 5 out of range") == 0);
  CHECK(message(R"({"type": "cubic_spring", "dof": 0, "coefficient": 1, "coef": 2})") ==
        "nonlinearities[0].coef: unknown key");
  CHECK(message(R"({"type": "cubic_spring", "dof": 0, "coefficient": "big"})") ==
        "nonlinearities[0].coefficient: expected a number, got \"big\"");
  CHECK(message(R"({"type": "polynomial_spring", "dof": 0, "terms": [{"power": 1,
        "coefficient": 1}]})")
            .find("nonlinearities[0].terms[0].power: must be at least 2") == 0);
  CHECK(message(R"({"type": "cubic_spring", "dof": 0, "other": "a", "coefficient": 1})") ==
        "nonlinearities[0].other: must differ from dof");
}

}  // namespace
}  // namespace nfrc
