#include "tools/validate.h"

#include <doctest/doctest.h>

#include "tools/case_file.h"
#include "tools/validation_reader.h"

#include <filesystem>
#include <fstream>

#include "tools/input_fields.h"

namespace nfrc {
namespace {

std::string OutDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("nfrc_validate_test_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

// IDA runs at rtol 1e-10 and stops at a 1e-7 relative period-to-period change; H = 7 leaves a
// truncation error of the Duffing response (0.1x³ with |x| ≲ 2.5) of about the 9th harmonic's
// size, ~1e-7 relative. 1e-5 leaves two orders of margin and still catches any real mismatch.
constexpr double kDuffingAgreement = 1e-5;

TEST_CASE("validate: Duffing transients match the HBM branch and the middle solution is unstable") {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing.json");
  ValidationSettings settings;
  // 0.8: one solution; 1.2: inside the folds at 1.116 and 1.270, three solutions.
  settings.omegas = {0.8, 1.2};
  const std::string dir = OutDir("duffing");
  const nlohmann::json doc = RunValidation(the_case, settings, dir, nullptr, nullptr);
  REQUIRE(doc["points"].size() == 2);
  CHECK(ValidationComplete(doc));

  const nlohmann::json& single = doc["points"][0];
  REQUIRE(single["hbm_solutions"].size() == 1);
  REQUIRE(single["transients"].size() == 1);
  const nlohmann::json& t = single["transient"];
  CHECK(t["periodic"] == true);
  CHECK(t["stayed"] == true);
  CHECK(t["differences"]["h1"][0].get<double>() < kDuffingAgreement);
  CHECK(t["differences"]["energy"].get<double>() < kDuffingAgreement);
  CHECK(t["differences"]["rms"][0].get<double>() < kDuffingAgreement);
  CHECK(std::filesystem::exists(dir + "/" + t["signals"].get<std::string>()));

  const nlohmann::json& fold = doc["points"][1];
  REQUIRE(fold["hbm_solutions"].size() == 3);
  REQUIRE(fold["transients"].size() == 3);
  int stayed = 0;
  for (const nlohmann::json& run : fold["transients"]) {
    REQUIRE(run["periodic"] == true);
    CHECK(run["matches"] != "middle");  // a transient never settles on the saddle
    if (run["stayed"] == true) {
      ++stayed;
      CHECK(run["differences"]["h1"][0].get<double>() < kDuffingAgreement);
    }
  }
  CHECK(stayed == 2);  // the lower and upper solutions are stable
}

TEST_CASE("validate: settings name the bad field") {
  auto message = [](const std::string& text) {
    try {
      ReadValidationSettings(nlohmann::json::parse(text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message(R"({"omega": [0.3, -1]})").find("validation.omega") != std::string::npos);
  CHECK(message(R"({"start": "cold"})").find("validation.start") != std::string::npos);
  CHECK(message(R"({"transient": {"relative_tolerance": -1}})")
            .find("validation.transient.relative_tolerance") != std::string::npos);
  CHECK(message(R"({"transient": {"linear_solver": "lu"}})")
            .find("validation.transient.linear_solver") != std::string::npos);
  CHECK(message(R"({"chirp": {"omega_start": 1, "omega_end": 1}})")
            .find("validation.chirp.omega_end") != std::string::npos);
  CHECK(message(R"({"chirp": {"omega_start": 1, "omega_end": 2, "directions": ["left"]}})")
            .find("validation.chirp.directions") != std::string::npos);
  CHECK(message(R"({"omgea": [1]})").find("omgea") != std::string::npos);
}

}  // namespace
}  // namespace nfrc
