#include "tools/validate.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include "tools/case_file.h"
#include "tools/input_fields.h"
#include "tools/validation_reader.h"
#include "tools/validation_writer.h"

namespace nfrc {
namespace {

std::string OutDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("nfrc_validate_test_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

TEST_CASE("validate: the writer records every run of a Duffing validation on disk") {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing.json");
  ValidationSettings settings;
  settings.omegas = {1.2};  // inside the folds: three HBM solutions, three transients
  settings.chirp.enabled = true;
  settings.chirp.omega_start = 1.0;
  settings.chirp.omega_end = 1.4;
  settings.chirp.cycles = 50;  // short: only the files are checked here
  settings.chirp.down = false;
  const std::string dir = OutDir("writer");
  std::ostringstream table;
  const ValidationResult result = RunValidation(the_case, settings, dir, nullptr, &table);
  CHECK(result.complete);

  std::ifstream in(dir + "/validation.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  CHECK(doc["branch"] == "hbm/branch.json");
  CHECK(std::filesystem::exists(dir + "/hbm/branch.json"));
  CHECK(doc["branch_summary"]["folds"] == 2);
  REQUIRE(doc["points"].size() == 1);
  const nlohmann::json& point = doc["points"][0];
  REQUIRE(point["hbm_solutions"].size() == 3);
  REQUIRE(point["transients"].size() == 3);
  for (const nlohmann::json& solution : point["hbm_solutions"]) {
    REQUIRE(solution.contains("monodromy"));
    const nlohmann::json& m = solution["monodromy"];
    CHECK(m["ok"] == true);
    REQUIRE(m["multipliers"].size() == 2);
    CHECK(m["multipliers"][0].size() == 2);  // [re, im]
    CHECK(m["integrations"] == 5);
    CHECK((m["max_modulus"].get<double>() > 1.0) == (solution["branch"] == "middle"));
  }
  CHECK(doc["monodromy_options"]["enabled"] == true);
  for (const nlohmann::json& run : point["transients"]) {
    CHECK(run["periodic"] == true);
    CHECK(std::filesystem::exists(dir + "/" + run["signals"].get<std::string>()));
  }
  CHECK(point["transient"]["stayed"] == true);
  CHECK(point["hbm"]["branch"] == point["transient"]["matches"]);
  REQUIRE(doc.contains("chirp"));
  CHECK(doc["chirp"]["up"]["status"] == "completed");
  CHECK(!doc["chirp"].contains("down"));
  CHECK(std::filesystem::exists(dir + "/chirp_up.csv"));
  // A header and a line per transient.
  const std::string lines = table.str();
  CHECK(lines.find("h1 transient") != std::string::npos);
  CHECK(std::count(lines.begin(), lines.end(), '\n') == 4);
}

// Raises the stop flag once the first ω is written, as an interrupt would.
class StopAfterFirstPoint : public ValidationWriter {
 public:
  StopAfterFirstPoint(std::string dir, const Case& the_case, const ValidationSettings& settings,
                      std::atomic<bool>* stop)
      : ValidationWriter(std::move(dir), the_case, settings, nullptr, nullptr), stop_(stop) {}
  void OnPoint(const ValidationPoint& point) override {
    ValidationWriter::OnPoint(point);
    stop_->store(true);
  }

 private:
  std::atomic<bool>* stop_;
};

TEST_CASE("validate: a run that stops keeps the frequencies done on disk") {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing.json");
  ValidationSettings settings;
  settings.omegas = {0.8, 1.2};
  const std::string dir = OutDir("stopped");
  std::atomic<bool> stop{false};
  StopAfterFirstPoint writer(dir, the_case, settings, &stop);
  ValidationOptions options;
  options.stop = &stop;
  options.observer = &writer;
  const ValidationResult result = ValidateCase(the_case, settings, options);
  CHECK(result.points.size() == 1);
  std::ifstream in(dir + "/validation.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  REQUIRE(doc["points"].size() == 1);
  CHECK(doc["points"][0]["omega"] == 0.8);
  CHECK(doc["points"][0]["transient"]["periodic"] == true);
}

TEST_CASE("validate: bad input writes nothing") {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing.json");
  ValidationSettings settings;
  settings.omegas = {1.2};
  settings.transient.samples_per_period = 8;  // cannot resolve harmonic 7
  const std::string dir = OutDir("bad_input");
  CHECK_THROWS_AS(RunValidation(the_case, settings, dir, nullptr, nullptr), InputError);
  CHECK(!std::filesystem::exists(dir));
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
  CHECK(message(R"({"monodromy": {"enabled": 1}})").find("validation.monodromy.enabled") !=
        std::string::npos);
  CHECK(message(R"({"monodromy": {"relative_step": 1}})")
            .find("validation.monodromy.relative_step") != std::string::npos);
  CHECK(message(R"({"monodromy": {"scale": -1}})").find("validation.monodromy.scale") !=
        std::string::npos);
  CHECK(message(R"({"monodromy": {"steps": 1}})").find("validation.monodromy.steps") !=
        std::string::npos);
  CHECK(!ReadValidationSettings(nlohmann::json::parse(R"({"monodromy": {"enabled": false}})"))
             .monodromy.enabled);
}

}  // namespace
}  // namespace nfrc
