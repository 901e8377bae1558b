#include "tools/case_manifest.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "support/duffing_peak.h"
#include "tools/case_file.h"
#include "tools/sweep.h"

namespace nfrc {
namespace {

const std::string kCases = std::string(NFRC_SOURCE_DIR) + "/cases";

// A manifest file written to the temporary folder (its base named by absolute path).
std::string WriteManifest(const std::string& name, const nlohmann::json& manifest) {
  const auto path = std::filesystem::temp_directory_path() / ("nfrc_manifest_" + name + ".json");
  std::ofstream(path) << manifest.dump(2);
  return path.string();
}

nlohmann::json DuffingManifest() {
  return {{"manifest", "Duffing at three damping levels"},
          {"base", kCases + "/duffing_h1.json"},
          {"variants",
           {{{"name", "c0.05"}},
            {{"name", "c0.1"}, {"set", {{"model.C[0][0]", 0.1}}}},
            {{"name", "c0.2"}, {"set", {{"model.C[0][0]", 0.2}, {"title", "heavily damped"}}}}}}};
}

TEST_CASE("manifest: ApplyFieldChange sets, adds and removes fields, and names bad paths") {
  nlohmann::json source = {{"model", {{"M", {{1.0, 0.0}, {0.0, 2.0}}}}},
                           {"harmonics", {{"max", 3}}}};
  ApplyFieldChange(&source, {"model.M[1][1]", 0.5}, "set");
  CHECK(source["model"]["M"][1][1] == 0.5);
  ApplyFieldChange(&source, {"harmonics.samples", 64}, "set");  // a new last name
  CHECK(source["harmonics"]["samples"] == 64);
  ApplyFieldChange(&source, {"harmonics.samples", nullptr}, "set");  // null removes
  CHECK_FALSE(source["harmonics"].contains("samples"));
  CHECK(FieldAt(source, "model.M[0][0]") == 1.0);
  CHECK(FieldAt(source, "model.M[2][0]").is_null());
  for (const char* bad : {"model.M[2][0]", "model.X.y", "model..M", "model.M[1", "model.M[1].a",
                          "harmonics.max.x", "model.M[0][0][0]", ""}) {
    CAPTURE(bad);
    CHECK_THROWS_WITH_AS(ApplyFieldChange(&source, {bad, 1.0}, "where"),
                         doctest::Contains((std::string("where: \"") + bad + "\"").c_str()),
                         InputError);
  }
  CHECK_THROWS_WITH_AS(ApplyFieldChange(&source, {"model.M[0]", nullptr}, "where"),
                       doctest::Contains("cannot remove an element"), InputError);
  CHECK(NumberJson(159.0).is_number_integer());
  CHECK(NumberJson(0.125).is_number_float());
}

TEST_CASE("manifest: a member read as FILE#NAME is the base case with its changes") {
  const std::string path = WriteManifest("duffing", DuffingManifest());
  const CaseFile base = ReadCaseFile(kCases + "/duffing_h1.json");
  const CaseFile light = ReadCaseFile(path + "#c0.05");
  const CaseFile damped = ReadCaseFile(path + "#c0.1");
  CHECK(light.the_case.model.model.damping.coeff(0, 0) == 0.05);
  CHECK(damped.the_case.model.model.damping.coeff(0, 0) == 0.1);
  CHECK(damped.the_case.laws.size() == base.the_case.laws.size());
  CHECK(damped.the_case.path == path + "#c0.1");
  // Everything else is the base's: only the changed field and the title differ.
  nlohmann::json expected = base.source;
  expected["model"]["C"][0][0] = 0.1;
  expected["title"] = damped.source["title"];
  CHECK(damped.source == expected);
  CHECK(damped.source["title"].get<std::string>().find("[c0.1: model.C[0][0] = 0.1]") !=
        std::string::npos);
  CHECK(ReadCaseFile(path + "#2").source["title"] == "heavily damped");  // by index
  CHECK_THROWS_WITH_AS(ReadCaseFile(path), doctest::Contains("a manifest of 3 cases"), InputError);
  CHECK_THROWS_WITH_AS(ReadCaseFile(path + "#c9"),
                       doctest::Contains("no member \"c9\" (the members are c0.05, c0.1, c0.2)"),
                       InputError);
  CHECK_THROWS_WITH_AS(ReadCaseFile(kCases + "/duffing_h1.json#c0.1"),
                       doctest::Contains("not a manifest"), InputError);
}

TEST_CASE("manifest: a grid of parameters, with names") {
  nlohmann::json grid = {{"manifest", "grid"},
                         {"base", kCases + "/duffing_h1.json"},
                         {"parameters",
                          {{{"path", "model.C[0][0]"}, {"values", {0.05, 0.1}}},
                           {{"path", "harmonics.max"}, {"values", {1, 3, 5}}}}},
                         {"names", {"a1", "a3", "a5", "b1", "b3", "b5"}}};
  const CaseManifest manifest = ReadManifest(WriteManifest("grid", grid));
  REQUIRE(manifest.variants.size() == 6);
  CHECK(manifest.variants[4].name == "b3");  // the last parameter varies fastest
  CHECK(manifest.variants[4].changes[0].value == 0.1);
  CHECK(manifest.variants[4].changes[1].value == 3);
  const CaseFile b3 = ReadCaseFile(manifest.path + "#b3");
  CHECK(b3.the_case.harmonics.max_harmonic() == 3);
  grid["names"] = {"a1"};
  CHECK_THROWS_WITH_AS(ReadManifest(WriteManifest("grid_names", grid)),
                       doctest::Contains("manifest.names: expected one name per grid point (6)"),
                       InputError);
}

TEST_CASE("manifest: bad manifests name the file and the field") {
  struct Bad {
    nlohmann::json manifest;
    std::string message;
  };
  const nlohmann::json good = DuffingManifest();
  std::vector<Bad> bad;
  bad.push_back({good, "manifest.variants: the name \"c0.1\" is given twice"});
  bad.back().manifest["variants"][2]["name"] = "c0.1";
  bad.push_back({good, "manifest.variants[1].sett: unknown key"});
  bad.back().manifest["variants"][1]["sett"] = nlohmann::json::object();
  bad.push_back({good, "set: model.C[5][0]"});
  bad.back().manifest["variants"][1]["set"] = {{"model.C[5][0]", 1.0}};
  bad.push_back({good, "exactly one of \"variants\" and \"parameters\""});
  bad.back().manifest.erase("variants");
  bad.push_back({good, "manifest.base: " +
                           (std::filesystem::temp_directory_path() / "no_such_case.json").string() +
                           ": cannot open case file"});
  bad.back().manifest["base"] = "no_such_case.json";
  bad.push_back({good, "is a manifest, not a case file"});
  bad.back().manifest["base"] = WriteManifest("as_base", good);
  for (size_t k = 0; k < bad.size(); ++k) {
    CAPTURE(k);
    const std::string path = WriteManifest("bad" + std::to_string(k), bad[k].manifest);
    CHECK_THROWS_WITH_AS(ReadManifest(path), doctest::Contains(bad[k].message.c_str()), InputError);
    CHECK_THROWS_WITH_AS(ReadManifest(path), doctest::Contains(path.c_str()), InputError);
  }
  CHECK_THROWS_WITH_AS(ReadManifest(kCases + "/duffing_h1.json"),
                       doctest::Contains("this is a case file, not a manifest"), InputError);
}

TEST_CASE("manifest: nfrc sweep of a manifest traces every variant, and resumes") {
  const std::string path = WriteManifest("sweep", DuffingManifest());
  const CaseManifest manifest = ReadManifest(path);
  const CaseFile base = ReadCaseFile(manifest.base_path);
  const auto dir = (std::filesystem::temp_directory_path() / "nfrc_manifest_sweep").string();
  std::filesystem::remove_all(dir);
  const SweepPlan plan(manifest);
  SweepOptions options;
  options.jobs = 2;
  const std::vector<SweepRun> runs = RunSweep(base, plan, dir, options).runs;
  REQUIRE(runs.size() == 3);
  // As sweep_test.cc: the branch's largest point lies below the true peak by at most the
  // curve's drop over half a step (1e-3 relative), never above it.
  const double damping[] = {0.05, 0.1, 0.2};
  for (size_t k = 0; k < 3; ++k) {
    CAPTURE(k);
    REQUIRE(runs[k].status == "complete");
    CHECK(runs[k].name == manifest.variants[k].name);
    const double exact = testing::DuffingPeakAmplitude(0.18, damping[k], 0.1);
    const double peak = runs[k].peaks.at("max_abs_0");
    MESSAGE(runs[k].name << ": peak " << peak << ", closed form " << exact);
    CHECK(peak < exact * (1.0 + 1e-12));
    CHECK(peak > exact * (1.0 - 1e-3));
  }
  std::ifstream in(dir + "/sweep.json");
  const nlohmann::json record = nlohmann::json::parse(in);
  CHECK(record["manifest"] == path);
  CHECK(record["variants"][1] ==
        nlohmann::json{{"name", "c0.1"}, {"set", {{"model.C[0][0]", 0.1}}}});
  CHECK(record["runs"][1]["name"] == "c0.1");
  CHECK(record["runs"][1]["values"] == nlohmann::json{{"model.C[0][0]", 0.1}});
  CHECK_FALSE(record.contains("parameters"));
  const std::vector<SweepRun> again = RunSweep(base, plan, dir, options).runs;
  for (const SweepRun& run : again) CHECK(run.resumed);
  // Another sweep in the same directory is refused.
  CHECK_THROWS_WITH_AS(RunSweep(base, SweepGrid{{"model.C[0][0]", {0.1}}}, dir, options),
                       doctest::Contains("holds another sweep"), InputError);
}

// What ApplyFieldChange says of `changes` applied in order to a copy of `source`: "" where
// every change applies, else its message (the independent reference of CheckFieldChanges).
std::string ApplyMessage(const nlohmann::json& source, const std::vector<FieldChange>& changes) {
  nlohmann::json copy = source;
  try {
    for (const FieldChange& change : changes) {
      ApplyFieldChange(&copy, change, "variant: set: " + change.path);
    }
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

std::string CheckMessage(const nlohmann::json& source, const std::vector<FieldChange>& changes) {
  try {
    CheckFieldChanges(source, changes, "variant: set");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST_CASE("manifest: CheckFieldChanges says what applying the changes in order would") {
  const nlohmann::json source = {{"model", {{"M", {{1.0, 0.0}, {0.0, 2.0}}}, {"damping", 0.1}}},
                                 {"harmonics", {{"max", 3}}},
                                 {"list", {1, 2, 3}}};
  const nlohmann::json object = {{"a", {{"b", 1}}}};
  const std::vector<std::vector<FieldChange>> sequences = {
      {{"model.M[1][1]", 0.5}},
      {{"model.M[2][0]", 0.5}},
      {{"harmonics.samples", 64}},
      {{"harmonics.samples.x", 64}},
      {{"harmonics.new", object}, {"harmonics.new.a.b", 2}},
      {{"harmonics.new", object}, {"harmonics.new.a.c", 2}},
      {{"harmonics.new", object}, {"harmonics.new.z.c", 2}},
      {{"harmonics.new", object}, {"harmonics", 5}, {"harmonics.new.a", 2}},
      {{"harmonics.new", object}, {"harmonics.new", nullptr}, {"harmonics.new.a", 2}},
      {{"harmonics.max", nullptr}, {"harmonics.max", 4}},
      {{"model.damping", object}, {"model.damping.a.b", 3}},
      {{"model.damping", 0.2}, {"model.damping.x", 3}},
      {{"list[1]", nullptr}},
      {{"list[1]", object}, {"list[1].a.b", 7}},
      {{"list[3]", 1}},
      {{"list", nlohmann::json::array({1})}, {"list[0]", 2}, {"list[1]", 2}},
      {{"model..M", 1}},
      {{"model.M[0][0][0]", 1}},
      {{"", 1}},
  };
  for (const std::vector<FieldChange>& changes : sequences) {
    std::string paths;
    for (const FieldChange& change : changes)
      paths += change.path + " = " + change.value.dump() + "; ";
    CAPTURE(paths);
    CHECK(CheckMessage(source, changes) == ApplyMessage(source, changes));
  }
}

TEST_CASE("manifest: a grid of 10 000 members is read without building them") {
  // A base of 200 kB: building every member copied it 10 000 times (2 GB); reading the
  // manifest checks each member's paths without a copy and builds only the member asked for
  // (tests/tools/hardening.py compares the time with the base's own).
  nlohmann::json base;
  {
    std::ifstream in(kCases + "/duffing_h1.json");
    base = nlohmann::json::parse(in);
  }
  base["title"] = std::string(200000, 'x');  // bulk that every copy of the base carries
  const auto dir = std::filesystem::temp_directory_path() / "nfrc_manifest_grid";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "base.json") << base.dump();
  std::vector<double> forces(100), dampings(100);
  for (int i = 0; i < 100; ++i) {
    forces[i] = 0.01 * (i + 1);
    dampings[i] = 0.05 + 0.001 * i;
  }
  const nlohmann::json manifest = {{"manifest", "10 000 members"},
                                   {"base", (dir / "base.json").string()},
                                   {"parameters",
                                    {{{"path", "model.forcing[0].cos"}, {"values", forces}},
                                     {{"path", "model.C[0][0]"}, {"values", dampings}}}}};
  const std::string path = WriteManifest("grid_10000", manifest);
  const CaseManifest read = ReadManifest(path);
  REQUIRE(read.variants.size() == 10000);
  const CaseFile member = ReadCaseFile(path + "#9999");
  CHECK(member.source["model"]["forcing"][0]["cos"] == 1.0);
  CHECK(member.source["model"]["C"][0][0] == doctest::Approx(0.149));
  // A bad path in the grid is still named, from the first member on.
  nlohmann::json bad = manifest;
  bad["parameters"][1]["path"] = "model.C[3][0]";
  CHECK_THROWS_WITH_AS(ReadManifest(WriteManifest("grid_bad", bad)),
                       doctest::Contains("variant \"0\": set: model.C[3][0]"), InputError);
}

}  // namespace
}  // namespace nfrc
