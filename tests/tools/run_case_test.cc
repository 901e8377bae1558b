#include "tools/run_case.h"

#include <doctest/doctest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tools/case_file.h"
#include "tools/validation_reader.h"

namespace nfrc {
namespace {

std::string OutDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("nfrc_run_test_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST_CASE("nfrc run writes branch.json with points, folds and summary, and measures are right") {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing_h1.json");
  const std::string dir = OutDir("h1");
  const Branch branch = RunCase(the_case, dir, nullptr);
  const nlohmann::json doc = ReadJson(dir + "/branch.json");
  CHECK(doc["program"] == "nfrc");
  CHECK(doc["harmonics"]["max"] == 1);
  CHECK(doc["points"].size() == branch.points.size());
  CHECK(doc["folds"].size() == 2);
  CHECK(doc["summary"]["termination"] == ToString(TerminationReason::kReachedLambdaBound));
  // The step history as the summary holds it, entry by entry.
  const auto& history = doc["summary"]["history"];
  REQUIRE(history.size() == branch.summary.history.size());
  for (size_t i = 0; i < history.size(); ++i) {
    const StepRecord& record = branch.summary.history[i];
    CHECK(history[i]["accepted"] == record.accepted);
    CHECK(history[i]["fixed_lambda"] == record.fixed_lambda);
    CHECK(history[i]["newton_iterations"] == record.newton_iterations);
  }
  // With one harmonic, max |x(t)| equals the first-harmonic amplitude √(a² + b²); the fine
  // resampling (≥ 512 samples) finds the peak to 1 − cos(π/512) ≈ 2e-5 relative.
  for (const auto& point : doc["points"]) {
    const double h1 = point["h1"][0];
    const double max_abs = point["max_abs"][0];
    CHECK(max_abs <= h1 * (1 + 1e-12));
    CHECK(max_abs >= h1 * (1 - 2e-5));
    // A pure first harmonic swings symmetrically: max x = −min x = max |x| on the same grid.
    CHECK(point["max"][0].get<double>() == doctest::Approx(max_abs).epsilon(2e-5));
    CHECK(point["min"][0].get<double>() == doctest::Approx(-max_abs).epsilon(2e-5));
  }
  const auto& last = branch.points.back();
  CHECK(doc["points"].back()["h1"][0].get<double>() ==
        doctest::Approx(std::hypot(last.y(0), last.y(1))).epsilon(1e-12));
  // CSV: header plus one line per point.
  std::ifstream csv(dir + "/branch.csv");
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  CHECK(lines == static_cast<int>(branch.points.size()) + 1);
}

// A progress stream that raises `stop` once it has been told of point `point`: a SIGINT
// arriving while the run computes the next one.
class StopAtPoint : public std::stringbuf {
 public:
  StopAtPoint(std::atomic<bool>* stop, int point)
      : stop_(stop), text_("point " + std::to_string(point) + " ") {}

 protected:
  int sync() override {
    if (str().find(text_) != std::string::npos) stop_->store(true);
    return 0;
  }

 private:
  std::atomic<bool>* stop_;
  std::string text_;
};

TEST_CASE("a run stopped part-way keeps its points on disk and says why") {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing.json");
  const std::string dir = OutDir("stopped");
  std::atomic<bool> stop{false};
  StopAtPoint watch(&stop, 3);
  std::ostream progress(&watch);
  progress << std::unitbuf;  // every line reaches sync() at once
  const Branch branch = RunCase(the_case, dir, &progress, &stop);
  CHECK(branch.summary.reason == TerminationReason::kStoppedByObserver);
  const nlohmann::json doc = ReadJson(dir + "/branch.json");
  // Points 0..3 were found when the flag rose; the engine stops within the next step.
  CHECK(doc["points"].size() >= 4);
  CHECK(doc["points"].size() <= 5);
  CHECK(doc["summary"]["termination"] == ToString(TerminationReason::kStoppedByObserver));
  CHECK(doc["summary"]["message"].get<std::string>().find("interrupted") != std::string::npos);
}

TEST_CASE("a run whose stop came before its first point says so and writes no point") {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing.json");
  const std::string dir = OutDir("stopped_at_start");
  const std::atomic<bool> stop{true};
  const Branch branch = RunCase(the_case, dir, nullptr, &stop);
  CHECK(branch.summary.reason == TerminationReason::kStoppedByObserver);
  CHECK(branch.summary.message.find("interrupted before the first point") != std::string::npos);
  const nlohmann::json doc = ReadJson(dir + "/branch.json");
  CHECK(doc["points"].empty());
}

}  // namespace
}  // namespace nfrc
