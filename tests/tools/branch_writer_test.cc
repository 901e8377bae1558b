#include "tools/branch_writer.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "tools/case_file.h"

namespace nfrc {
namespace {

// Stability results are built by hand here: the writer must record them exactly, whatever
// the analysis that will fill them.

std::string OutDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("nfrc_branch_writer_test_" + name + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  return dir.string();
}

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::vector<std::string> ReadLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  for (std::string cell; std::getline(stream, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.push_back("");  // getline drops the last
  return cells;
}

// Calls writer.OnStart and returns how long it took: an upper bound of its write's duration,
// which sets when the writer's next event is due.
std::chrono::steady_clock::duration TimedStart(BranchWriter& writer) {
  const auto start = std::chrono::steady_clock::now();
  writer.OnStart(2);
  return std::chrono::steady_clock::now() - start;
}

TracePoint Point(int index, double omega) {
  TracePoint point;
  point.index = index;
  point.point.lambda = omega;
  point.measures.response.energy = 0.5;
  point.measures.response.max_abs = {1.0};
  point.measures.response.min = {-1.0};
  point.measures.response.max = {1.0};
  point.measures.response.h1 = {0.9};
  return point;
}

FloquetResult Floquet(std::vector<std::complex<double>> multipliers, int num_unstable) {
  FloquetResult floquet;
  floquet.computed = true;
  floquet.method = "hill";
  floquet.multipliers = std::move(multipliers);
  floquet.max_modulus = std::abs(floquet.multipliers.front());
  floquet.num_unstable = num_unstable;
  return floquet;
}

Bifurcation Crossing() {
  Bifurcation bifurcation;
  bifurcation.type = BifurcationType::kNeimarkSacker;
  bifurcation.omega = 1.25;
  bifurcation.omega_accuracy = 1e-7;
  bifurcation.converged = true;
  bifurcation.iterations = 6;
  bifurcation.after_point = 1;
  bifurcation.measures.energy = 0.75;
  bifurcation.measures.max_abs = {1.5};
  bifurcation.measures.min = {-1.4};
  bifurcation.measures.max = {1.5};
  bifurcation.measures.h1 = {1.3};
  bifurcation.crossing_multipliers = {{0.6, 0.8}, {0.6, -0.8}};
  return bifurcation;
}

TEST_CASE("branch.json and branch.csv record stability, null when not computed") {
  const Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing_h1.json");
  const std::string dir = OutDir("stability");
  BranchWriter writer(dir, the_case, nullptr);
  const auto start_write = TimedStart(writer);
  TracePoint unknown = Point(0, 1.0);  // stability off: floquet.computed is false
  TracePoint stable = Point(1, 1.2);
  stable.floquet = Floquet({{0.5, 0.0}, {0.25, 0.0}}, 0);
  TracePoint unstable = Point(2, 1.3);
  unstable.floquet = Floquet({{1.5, 0.1}, {1.5, -0.1}}, 2);
  writer.OnPoint(unknown);
  writer.OnPoint(stable);
  // A bifurcation ten write durations after the last write is on disk at once, before the
  // next point or the end of the run (OnStart's duration bounds its write's).
  std::this_thread::sleep_for(11 * start_write + std::chrono::milliseconds(1));
  writer.OnBifurcation(Crossing());
  const nlohmann::json streamed = ReadJson(dir + "/branch.json");
  REQUIRE(streamed["bifurcations"].size() == 1);
  writer.OnPoint(unstable);
  writer.Finish(ContinuationSummary{});

  const nlohmann::json doc = ReadJson(dir + "/branch.json");
  REQUIRE(doc["points"].size() == 3);
  CHECK(doc["points"][0]["stable"].is_null());
  CHECK(doc["points"][0]["floquet"].is_null());
  CHECK(doc["points"][1]["stable"] == true);
  CHECK(doc["points"][2]["stable"] == false);
  const nlohmann::json& floquet = doc["points"][2]["floquet"];
  CHECK(floquet["unstable"] == 2);
  CHECK(floquet["method"] == "hill");
  CHECK(floquet["max_modulus"].get<double>() == doctest::Approx(std::abs(std::complex(1.5, 0.1))));
  CHECK(floquet["multipliers"] == nlohmann::json::parse("[[1.5, 0.1], [1.5, -0.1]]"));
  CHECK(doc["folds"].empty());
  CHECK(doc["stability"]["enabled"] == the_case.stability.enabled);

  const nlohmann::json& b = doc["bifurcations"][0];
  CHECK(b["type"] == "neimark_sacker");
  CHECK(b["omega"] == 1.25);
  CHECK(b["omega_accuracy"] == 1e-7);
  CHECK(b["converged"] == true);
  CHECK(b["iterations"] == 6);
  CHECK(b["after_point"] == 1);
  CHECK(b["crossing_multipliers"] == nlohmann::json::parse("[[0.6, 0.8], [0.6, -0.8]]"));
  CHECK(b["energy"] == 0.75);
  CHECK(b["max_abs"] == nlohmann::json::parse("[1.5]"));
  CHECK(b["h1"] == nlohmann::json::parse("[1.3]"));

  const std::vector<std::string> lines = ReadLines(dir + "/branch.csv");
  REQUIRE(lines.size() == 4);
  const std::vector<std::string> header = Split(lines[0]);
  // The older columns keep their places; the stability columns come last.
  CHECK(header[0] == "index");
  CHECK(header[6] == "energy");
  REQUIRE(header.size() == 12);
  CHECK(header[9] == "stable");
  CHECK(header[10] == "max_multiplier");
  CHECK(header[11] == "unstable");
  const std::vector<std::string> none = Split(lines[1]);
  REQUIRE(none.size() == 12);
  CHECK(none[9].empty());
  CHECK(none[10].empty());
  CHECK(none[11].empty());
  CHECK(Split(lines[2])[9] == "1");
  CHECK(Split(lines[2])[11] == "0");
  CHECK(Split(lines[3])[9] == "0");
  CHECK(std::stod(Split(lines[3])[10]) == doctest::Approx(std::abs(std::complex(1.5, 0.1))));
  CHECK(Split(lines[3])[11] == "2");
  std::filesystem::remove_all(dir);
}

TEST_CASE("a burst of folds and bifurcations is written together, then by the next point") {
  const Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing_h1.json");
  const std::string dir = OutDir("burst");
  BranchWriter writer(dir, the_case, nullptr);
  const auto start_write = TimedStart(writer);
  writer.OnPoint(Point(0, 1.0));
  const int before = writer.json_writes();
  // Each write takes at least the time of the events between two writes, so ten write
  // durations of spacing leave at most a few of the 200 writes that writing each would take.
  constexpr int kEvents = 200;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kEvents / 2; ++i) {
    writer.OnBifurcation(Crossing());
    TraceFold fold;
    fold.fold.lambda = 1.1;
    writer.OnFold(fold);
  }
  const auto burst = std::chrono::steady_clock::now() - start;
  CHECK(writer.json_writes() - before < kEvents / 4);
  // The burst's last event may itself have been written; then nothing is left and the next
  // point waits for kJsonInterval like any point.
  const nlohmann::json after_burst = ReadJson(dir + "/branch.json");
  const bool events_left =
      after_burst["bifurcations"].size() < kEvents / 2 || after_burst["folds"].size() < kEvents / 2;
  // The last write was OnStart's or one in the burst, so it took less than their sum: eleven
  // times that later, the next point writes what is left, before kJsonInterval is due.
  const auto wait = 11 * (start_write + burst);
  REQUIRE(wait < BranchWriter::kJsonInterval);
  std::this_thread::sleep_for(wait);
  const int before_point = writer.json_writes();
  writer.OnPoint(Point(1, 1.2));
  const nlohmann::json streamed = ReadJson(dir + "/branch.json");
  CHECK(streamed["bifurcations"].size() == kEvents / 2);
  CHECK(streamed["folds"].size() == kEvents / 2);
  CHECK(writer.json_writes() - before_point == (events_left ? 1 : 0));
  CHECK(streamed["points"].size() == (events_left ? 2u : 1u));
  std::filesystem::remove_all(dir);
}

TEST_CASE("every bifurcation type is written by its name") {
  CHECK(BifurcationToJson(Bifurcation{})["type"] == "fold");
  Bifurcation bifurcation;
  bifurcation.type = BifurcationType::kBranchPoint;
  CHECK(BifurcationToJson(bifurcation)["type"] == "branch_point");
  bifurcation.type = BifurcationType::kPeriodDoubling;
  bifurcation.crossing_multipliers = {{-1.0, 0.0}};
  const nlohmann::json entry = BifurcationToJson(bifurcation);
  CHECK(entry["type"] == "period_doubling");
  CHECK(entry["crossing_multipliers"] == nlohmann::json::parse("[[-1.0, 0.0]]"));
  CHECK(FloquetToJson(FloquetResult{}).is_null());
}

}  // namespace
}  // namespace nfrc
