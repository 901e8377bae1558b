#include "tools/sweep.h"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/errors.h"
#include "support/duffing_peak.h"

namespace nfrc {
namespace {

constexpr double kC = 0.05, kK3 = 0.1;
// The largest max |x| of a branch is taken on its points, so it lies below the curve's true
// maximum by the curve's drop over half a step (measured 1.7e-4 to 2.6e-4 relative here); it
// can never lie above it (beyond rounding). 1e-3 is the bar below.
constexpr double kPeakTolerance = 1e-3;
constexpr double kRounding = 1e-12;

std::string OutDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("nfrc_sweep_test_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

CaseFile CaseFileNamed(const std::string& name) {
  return ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
}

// The closed-form peak of duffing_h1.json (c = kC) at forcing P, k₃ and stiffness k.
double ClosedFormPeak(double force, double k3 = kK3, double k = 1.0) {
  return testing::DuffingPeakAmplitude(force, kC, k3, k);
}

TEST_CASE("sweep: one branch per forcing level, peaks against the closed form, threads = serial") {
  const CaseFile file = CaseFileNamed("duffing_h1.json");
  const CaseParameter forcing("model.forcing[0].cos", file.the_case);
  const std::vector<double> values = {0.05, 0.1, 0.18};
  SweepOptions options;
  options.jobs = 2;
  const std::string dir = OutDir("duffing");
  const std::vector<SweepRun> runs = RunSweep(file, forcing, values, dir, options).runs;
  options.jobs = 1;
  const std::vector<SweepRun> serial =
      RunSweep(file, forcing, values, OutDir("serial"), options).runs;
  REQUIRE(runs.size() == 3);
  for (size_t k = 0; k < runs.size(); ++k) {
    CAPTURE(k);
    CHECK(runs[k].status == "complete");
    CHECK(std::filesystem::exists(dir + "/" + runs[k].dir + "/branch.json"));
    const double exact = ClosedFormPeak(values[k]);
    const double peak = runs[k].peaks.at("max_abs_0");
    MESSAGE("P = " << values[k] << ": peak " << peak << ", closed form " << exact);
    CHECK(peak < exact * (1.0 + kRounding));
    CHECK(peak > exact * (1.0 - kPeakTolerance));
    CHECK(runs[k].folds == serial[k].folds);
    CHECK(runs[k].peaks == serial[k].peaks);
  }
  CHECK(runs[0].folds == 0);  // below the cusp (P ≈ 0.054): no fold
  CHECK(runs[2].folds == 2);
  std::ifstream in(dir + "/sweep.json");
  const nlohmann::json record = nlohmann::json::parse(in);
  CHECK(record["parameter"] == "model.forcing[0].cos");
  CHECK(record["values"].get<std::vector<double>>() == values);
  CHECK(record["parameters"] ==
        nlohmann::json::array({{{"path", "model.forcing[0].cos"}, {"values", values}}}));
  CHECK(record["runs"].size() == 3);
  CHECK(record["runs"][2]["values"] == nlohmann::json{{"model.forcing[0].cos", 0.18}});
}

nlohmann::json ReadRecord(const std::string& dir) {
  std::ifstream in(dir + "/sweep.json");
  return nlohmann::json::parse(in);
}

TEST_CASE(
    "sweep: a grid of forcing and k3, every point against the closed form, threads = serial") {
  const CaseFile file = CaseFileNamed("duffing_h1.json");
  const SweepGrid grid = {
      {CaseParameter("model.forcing[0].cos", file.the_case), {0.05, 0.1, 0.18}},
      {CaseParameter("nonlinearities[0].coefficient", file.the_case), {0.1, 0.2}}};
  SweepOptions options;
  options.jobs = 2;
  const std::string dir = OutDir("grid");
  const std::vector<SweepRun> runs = RunSweep(file, grid, dir, options).runs;
  options.jobs = 1;
  const std::vector<SweepRun> serial = RunSweep(file, grid, OutDir("grid_serial"), options).runs;
  REQUIRE(runs.size() == 6);
  for (size_t k = 0; k < runs.size(); ++k) {
    CAPTURE(k);
    // Row-major: the last parameter (k3) varies fastest.
    const double force = grid[0].values[k / 2], k3 = grid[1].values[k % 2];
    CHECK(runs[k].values == std::vector<double>{force, k3});
    CHECK(runs[k].dir == std::to_string(k));
    CHECK(runs[k].status == "complete");
    CHECK(std::filesystem::exists(dir + "/" + runs[k].dir + "/branch.json"));
    const double exact = ClosedFormPeak(force, k3);
    const double peak = runs[k].peaks.at("max_abs_0");
    MESSAGE("P = " << force << ", k3 = " << k3 << ": peak " << peak << ", closed form " << exact
                   << " (" << (exact - peak) / exact << " below)");
    CHECK(peak < exact * (1.0 + kRounding));
    CHECK(peak > exact * (1.0 - kPeakTolerance));
    CHECK(runs[k].folds == serial[k].folds);
    CHECK(runs[k].peaks == serial[k].peaks);
  }
  CHECK(runs[0].folds == 0);  // P = 0.05, k3 = 0.1: below the cusp (P ≈ 0.054)
  CHECK(runs[5].folds == 2);
  const nlohmann::json record = ReadRecord(dir);
  CHECK_FALSE(record.contains("parameter"));  // one-parameter readers must not misread a grid
  CHECK(record["parameters"].size() == 2);
  CHECK(record["parameters"][1]["path"] == "nonlinearities[0].coefficient");
  CHECK(record["parameters"][1]["values"].get<std::vector<double>>() == grid[1].values);
  CHECK(record["runs"][3]["values"] ==
        nlohmann::json{{"model.forcing[0].cos", 0.1}, {"nonlinearities[0].coefficient", 0.2}});
  std::ifstream in(dir + "/3/branch.json");
  CHECK(nlohmann::json::parse(in)["case"]["nonlinearities"][0]["coefficient"] == 0.2);

  // Again: every run is kept. The same axes in another order are another sweep.
  const std::vector<SweepRun> again = RunSweep(file, grid, dir, options).runs;
  for (const SweepRun& run : again) CHECK(run.resumed);
  CHECK_THROWS_WITH_AS(RunSweep(file, {grid[1], grid[0]}, dir, options), doctest::Contains("--out"),
                       InputError);
}

TEST_CASE("sweep: a failing run is a status, and an interrupted sweep resumes") {
  const CaseFile file = CaseFileNamed("friction/one_dof_coulomb.json");
  const CaseParameter mu("nonlinearities[0].mu", file.the_case);
  // μ = −1 is refused by the case's validation: that run fails, the others go on.
  const std::vector<double> values = {0.5, -1.0, 0.4};
  const std::string dir = OutDir("resume");
  std::vector<SweepRun> runs = RunSweep(file, mu, values, dir, {}).runs;
  CHECK(runs[0].status == "complete");
  CHECK(runs[1].status == "failed");
  CHECK(runs[1].message.find("nonlinearities[0].mu") != std::string::npos);
  CHECK(runs[2].status == "complete");
  // Again in the same directory: the complete runs are kept, the failed one is traced again.
  runs = RunSweep(file, mu, values, dir, {}).runs;
  CHECK(runs[0].resumed);
  CHECK_FALSE(runs[1].resumed);
  CHECK(runs[2].resumed);
  // Another sweep in that directory is refused, naming --out; so are values that are not
  // finite, naming --values.
  CHECK_THROWS_WITH_AS(RunSweep(file, mu, {0.3}, dir, {}), doctest::Contains("--out"), InputError);
  CHECK_THROWS_WITH_AS(RunSweep(file, mu, {std::nan("")}, OutDir("nan"), {}),
                       doctest::Contains("--values"), InputError);
}

TEST_CASE("sweep: a grid point the case refuses fails its runs only, and they are traced again") {
  const CaseFile file = CaseFileNamed("friction/one_dof_coulomb.json");
  // μ = −1 is refused by the case's validation: runs 2 and 3 (μ varies slowest) fail.
  const SweepGrid grid = {
      {CaseParameter("nonlinearities[0].mu", file.the_case), {0.5, -1.0}},
      {CaseParameter("nonlinearities[0].normal_load", file.the_case), {1.0, 0.8}}};
  const std::string dir = OutDir("grid_resume");
  std::vector<SweepRun> runs = RunSweep(file, grid, dir, {}).runs;
  REQUIRE(runs.size() == 4);
  CHECK(runs[0].status == "complete");
  CHECK(runs[1].status == "complete");
  for (size_t k : {size_t{2}, size_t{3}}) {
    CHECK(runs[k].status == "failed");
    CHECK(runs[k].message.find("nonlinearities[0].mu") != std::string::npos);
  }
  runs = RunSweep(file, grid, dir, {}).runs;
  CHECK(runs[0].resumed);
  CHECK(runs[1].resumed);
  CHECK_FALSE(runs[2].resumed);
  CHECK(runs[3].status == "failed");
}

TEST_CASE("sweep: grid order, shape checks and records from before grids") {
  const CaseFile file = CaseFileNamed("duffing_h1.json");
  const CaseParameter force_cos("model.forcing[0].cos", file.the_case);
  const CaseParameter force_sin("model.forcing[0].sin", file.the_case);
  const CaseParameter k3("nonlinearities[0].coefficient", file.the_case);
  const SweepGrid grid = {{force_cos, {1.0, 2.0}}, {k3, {10.0, 20.0, 30.0}}};
  CHECK(GridSize(grid) == 6);
  CHECK(GridPoint(grid, 0) == std::vector<double>{1.0, 10.0});
  CHECK(GridPoint(grid, 2) == std::vector<double>{1.0, 30.0});
  CHECK(GridPoint(grid, 4) == std::vector<double>{2.0, 20.0});
  CHECK_THROWS_WITH_AS(CheckGrid({{force_cos, {1.0}}, {force_cos, {2.0}}}),
                       doctest::Contains("--parameter"), InputError);
  CHECK_THROWS_WITH_AS(CheckGrid({{force_cos, {1.0}}, {k3, {}}}), doctest::Contains("--values"),
                       InputError);
  // 50³ = 125000 runs: over kMaxSweepRuns, refused before anything is written.
  const std::vector<double> fifty(50, 1.0);
  const std::string big = OutDir("big");
  CHECK_THROWS_WITH_AS(
      RunSweep(file, {{force_cos, fifty}, {force_sin, fifty}, {k3, fifty}}, big, {}),
      doctest::Contains("125000 runs"), InputError);
  CHECK_FALSE(std::filesystem::exists(big));

  // A one-parameter sweep.json written before grids (no "parameters") is the same sweep.
  const std::string dir = OutDir("old_record");
  RunSweep(file, force_cos, {0.05}, dir, {});
  nlohmann::json record = ReadRecord(dir);
  record.erase("parameters");
  std::ofstream(dir + "/sweep.json") << record.dump();
  CHECK(RunSweep(file, force_cos, {0.05}, dir, {}).runs[0].resumed);
}

TEST_CASE("sweep: a field of the case file outside the laws and forcing (the stiffness K[0][0])") {
  const CaseFile file = CaseFileNamed("duffing_h1.json");
  const std::vector<double> stiffness = {0.8, 1.5};
  const std::string dir = OutDir("stiffness");
  const std::vector<SweepRun> runs =
      RunSweep(file, SweepGrid{{"model.K[0][0]", stiffness}}, dir, {}).runs;
  REQUIRE(runs.size() == 2);
  for (size_t k = 0; k < runs.size(); ++k) {
    CAPTURE(k);
    REQUIRE(runs[k].status == "complete");
    const double exact = ClosedFormPeak(0.18, kK3, stiffness[k]);
    const double peak = runs[k].peaks.at("max_abs_0");
    MESSAGE("k = " << stiffness[k] << ": peak " << peak << ", closed form " << exact);
    CHECK(peak < exact * (1.0 + kRounding));
    CHECK(peak > exact * (1.0 - kPeakTolerance));
    // The branch's record holds the case as run, with the swept value at its path.
    std::ifstream in(dir + "/" + runs[k].dir + "/branch.json");
    const nlohmann::json branch = nlohmann::json::parse(in);
    CHECK(branch["case"]["model"]["K"][0][0] == stiffness[k]);
  }
  CHECK_THROWS_WITH_AS(RunSweep(file, SweepGrid{{"model.K[3][0]", {1.0}}}, OutDir("bad"), {}),
                       doctest::Contains("--parameter: \"model.K[3][0]\""), InputError);
  CHECK_THROWS_WITH_AS(RunSweep(file, SweepGrid{{"title", {1.0}}}, OutDir("bad"), {}),
                       doctest::Contains("names no number"), InputError);
}

void WriteRecord(const std::string& dir, const nlohmann::json& record) {
  std::ofstream(dir + "/sweep.json") << record.dump();
}

bool Mentions(const std::vector<std::string>& notes, const std::string& text) {
  for (const std::string& note : notes) {
    if (note.find(text) != std::string::npos) return true;
  }
  return false;
}

// A copy of duffing_h1.json in `dir` with k₃ = `k3`, read as a case file.
CaseFile EditedDuffing(const std::string& dir, double k3) {
  std::ifstream in(std::string(NFRC_SOURCE_DIR) + "/cases/duffing_h1.json");
  nlohmann::json source = nlohmann::json::parse(in);
  source["nonlinearities"][0]["coefficient"] = k3;
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/duffing_edited.json";
  std::ofstream(path) << source.dump();
  return ReadCaseFile(path);
}

TEST_CASE("sweep: a resume keeps only the runs of the same case, in their own folders") {
  const CaseFile file = CaseFileNamed("duffing_h1.json");
  const CaseParameter force("model.forcing[0].cos", file.the_case);
  const std::vector<double> values = {0.05, 0.1};
  const std::string dir = OutDir("own_runs");
  SweepResult first = RunSweep(file, force, values, dir, {});
  REQUIRE(first.runs[0].status == "complete");
  REQUIRE(first.runs[1].status == "complete");

  // The same command on an edited case (k3 0.1 -> 5) is refused: those runs are not its own.
  const CaseFile edited = EditedDuffing(OutDir("edited_case"), 5.0);
  CHECK(CaseFingerprint(edited) != CaseFingerprint(file));
  CHECK_THROWS_WITH_AS(RunSweep(edited, force, values, dir, {}),
                       doctest::Contains("of another case"), InputError);

  // Run 0's folder deleted: traced again, and said so; run 1 kept.
  std::filesystem::remove_all(dir + "/0");
  SweepResult second = RunSweep(file, force, values, dir, {});
  CHECK_FALSE(second.runs[0].resumed);
  CHECK(second.runs[0].status == "complete");
  CHECK(second.runs[1].resumed);
  CHECK(Mentions(second.notes,
                 "run 0: its record in sweep.json not used (its folder has no run.json): traced "
                 "again"));
  CHECK(std::filesystem::is_regular_file(dir + "/0/branch.json"));

  // A record naming another folder is not trusted: the run is the one in its own folder.
  nlohmann::json record = ReadRecord(dir);
  record["runs"][1]["dir"] = "../../../../etc";
  WriteRecord(dir, record);
  SweepResult third = RunSweep(file, force, values, dir, {});
  CHECK(third.runs[0].resumed);
  CHECK(third.runs[1].dir == "1");
  CHECK(Mentions(third.notes, "names the folder \"../../../../etc\", not 1"));
  CHECK(ReadRecord(dir)["runs"][1]["dir"] == "1");

  // A run.json of another case in a run's folder (the folder replaced by hand): traced again.
  {
    std::ifstream in(dir + "/1/run.json");
    nlohmann::json run = nlohmann::json::parse(in);
    run["case_fingerprint"] = "0000000000000000";
    in.close();
    std::ofstream(dir + "/1/run.json") << run.dump();
  }
  SweepResult fourth = RunSweep(file, force, values, dir, {});
  CHECK_FALSE(fourth.runs[1].resumed);
  CHECK(Mentions(fourth.notes,
                 "run 1: its record in sweep.json not used (its run.json is of "
                 "another case): traced again"));

  // A sweep.json behind its runs (rewritten on a schedule; a killed sweep writes no last one):
  // a run whose complete run.json is there is kept all the same.
  record = ReadRecord(dir);
  record["runs"][1]["status"] = "pending";
  WriteRecord(dir, record);
  SweepResult fifth = RunSweep(file, force, values, dir, {});
  CHECK(fifth.runs[1].resumed);
  CHECK(fifth.runs[1].status == "complete");
}

TEST_CASE("sweep: the fingerprint covers the files a case names (Matrix Market matrices)") {
  const std::string dir = OutDir("fingerprint_files");
  std::filesystem::create_directories(dir);
  for (const char* name : {"two_rods.json", "K.mtx", "M.mtx"}) {
    std::filesystem::copy_file(std::string(NFRC_SOURCE_DIR) + "/cases/two_rods/" + name,
                               dir + "/" + name);
  }
  const std::string fingerprint = CaseFingerprint(ReadCaseFile(dir + "/two_rods.json"));
  CHECK(CaseFingerprint(ReadCaseFile(dir + "/two_rods.json")) == fingerprint);
  // The same JSON, one stiffness entry of K.mtx changed (in its last digit).
  std::ifstream in(dir + "/K.mtx");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const size_t entry = text.find("50399999999.999992");
  REQUIRE(entry != std::string::npos);
  text.replace(entry, 18, "50399999999.999999");
  std::ofstream(dir + "/K.mtx") << text;
  CHECK(CaseFingerprint(ReadCaseFile(dir + "/two_rods.json")) != fingerprint);
}

TEST_CASE("sweep: a sweep.json of the wrong types is bad input naming the file and the field") {
  const CaseFile file = CaseFileNamed("duffing_h1.json");
  const CaseParameter force("model.forcing[0].cos", file.the_case);
  const std::string dir = OutDir("wrong_types");
  RunSweep(file, force, {0.05}, dir, {});
  const nlohmann::json good = ReadRecord(dir);
  struct Bad {
    const char* field;
    nlohmann::json value;
    const char* message;
  };
  const Bad bad[] = {{"runs", 5, "runs: expected a list"},
                     {"index", "zero", "runs[0].index: expected an integer"},
                     {"index", 7, "runs[0].index: run 7 is not one of this sweep's 1 runs"},
                     {"status", true, "runs[0].status"},
                     {"peaks", nlohmann::json::array({1}), "runs[0].peaks"}};
  for (const Bad& b : bad) {
    CAPTURE(b.message);
    nlohmann::json record = good;
    if (std::string(b.field) == "runs") {
      record["runs"] = b.value;
    } else {
      record["runs"][0][b.field] = b.value;
    }
    WriteRecord(dir, record);
    CHECK_THROWS_WITH_AS(RunSweep(file, force, {0.05}, dir, {}), doctest::Contains(b.message),
                         InputError);
    CHECK_THROWS_WITH_AS(RunSweep(file, force, {0.05}, dir, {}),
                         doctest::Contains((dir + "/sweep.json").c_str()), InputError);
  }
  std::filesystem::remove(dir + "/sweep.json");
  std::filesystem::create_directory(dir + "/sweep.json");
  CHECK_THROWS_WITH_AS(RunSweep(file, force, {0.05}, dir, {}),
                       doctest::Contains("sweep.json: is a directory"), InputError);
}

TEST_CASE("sweep: sweep.json is rewritten on a schedule, not after every run") {
  // 3000 runs that each fail at once (mu = -1 is refused): with sweep.json rewritten after
  // every run that is 3000 writes of a record growing to ~1 MB, O(runs²) bytes; on the
  // schedule (writing at most a tenth of the time) a few dozen.
  const CaseFile file = CaseFileNamed("friction/one_dof_coulomb.json");
  const CaseParameter mu("nonlinearities[0].mu", file.the_case);
  const std::vector<double> values(3000, -1.0);
  const std::string dir = OutDir("schedule");
  const SweepResult result = RunSweep(file, mu, values, dir, {});
  MESSAGE("sweep.json written " << result.record_writes << " times for " << values.size()
                                << " runs");
  CHECK(result.record_writes <= static_cast<int>(values.size()) / 10);
  const nlohmann::json record = ReadRecord(dir);
  REQUIRE(record["runs"].size() == values.size());
  CHECK(record["runs"].back()["status"] == "failed");
}

}  // namespace
}  // namespace nfrc
