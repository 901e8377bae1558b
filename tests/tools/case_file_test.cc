#include "tools/case_file.h"

#include <doctest/doctest.h>

#include "support/case_error.h"
#include "tools/input_fields.h"

namespace nfrc {
namespace {

// The Duffing case of the issue with one field replaced (or removed if `value` is null).
nlohmann::json Duffing() {
  return nlohmann::json::parse(R"({
    "model": {"type": "matrices", "M": [[1]], "C": [[0.05]], "K": [[1]],
              "forcing": [{"dof": 0, "cos": 0.18}]},
    "nonlinearities": [{"type": "cubic_spring", "dof": 0, "coefficient": 0.1}],
    "harmonics": {"max": 7, "samples": 64},
    "continuation": {"omega_start": 0.5, "omega_end": 1.6, "step": 0.01},
    "output": {"dofs": [0]}})");
}

std::string Error(const nlohmann::json& source) { return testing::CaseError(source); }

std::string ErrorWith(const std::string& pointer, const nlohmann::json& value) {
  nlohmann::json source = Duffing();
  const nlohmann::json::json_pointer where(pointer);
  if (value.is_null()) {
    source[where.parent_pointer()].erase(where.back());
  } else {
    source[where] = value;
  }
  return Error(source);
}

TEST_CASE("the issue's Duffing case parses") {
  const Case parsed = ParseCase(Duffing(), ".");
  CHECK(parsed.harmonics.max_harmonic() == 7);
  CHECK(parsed.harmonics.num_samples() == 64);
  CHECK(parsed.laws.size() == 1);
  CHECK(parsed.continuation.lambda_end == 1.6);
  CHECK(parsed.continuation.initial_step == 0.01);
}

TEST_CASE("bad case files give one message naming the field") {
  CHECK(ErrorWith("/harmonics/max", 0) == "harmonics.max: must be at least 1, got 0");
  CHECK(ErrorWith("/harmonics/samples", 10) ==
        "harmonics.samples: must be at least 2*max+1 = 15, got 10");
  CHECK(ErrorWith("/harmonics/max", "seven") ==
        "harmonics.max: expected an integer, got \"seven\"");
  CHECK(ErrorWith("/continuation/omega_end", -1.0) == "continuation.omega_end: must be positive");
  CHECK(ErrorWith("/continuation/omega_end", 0.0) == "continuation.omega_end: must be positive");
  CHECK(ErrorWith("/continuation/omega_start", nullptr) ==
        "continuation.omega_start: missing (required)");
  CHECK(ErrorWith("/continuation/stepsize", 0.1) == "continuation.stepsize: unknown key");
  CHECK(ErrorWith("/model/M", nlohmann::json::parse("[[-1]]"))
            .find("model.M: negative mass on the diagonal") == 0);
  CHECK(ErrorWith("/output/dofs", nlohmann::json::parse("[3]")) ==
        "output.dofs[0]: DOF 3 out of range 0..0");
  CHECK(ErrorWith("/output", nullptr) == "case.output: missing (required)");
  CHECK(ErrorWith("/extra", 1) == "case.extra: unknown key");
  CHECK(ErrorWith("/model/forcing/0/harmonic", 9) ==
        "model.forcing: harmonic 9 is not in the harmonic set");
  CHECK(ErrorWith("/nonlinearities/0/type", "cubic").find("nonlinearities[0].type: unknown") == 0);
}

TEST_CASE("the stability object is optional, read strictly and validated") {
  CHECK(ParseCase(Duffing(), ".").stability.enabled);  // on by default
  nlohmann::json source = Duffing();
  source["stability"] = {{"enabled", false},
                         {"unstable_tolerance", 1e-4},
                         {"bifurcation_tolerance", 1e-8},
                         {"max_bifurcation_iterations", 12},
                         {"jump_tolerance", 1e-3}};
  const StabilityOptions read = ParseCase(source, ".").stability;
  CHECK_FALSE(read.enabled);
  CHECK(read.unstable_tolerance == 1e-4);
  CHECK(read.bifurcation_tolerance == 1e-8);
  CHECK(read.max_bifurcation_iterations == 12);
  CHECK(read.jump_tolerance == 1e-3);

  CHECK(ErrorWith("/stability/enabled", "no") ==
        "stability.enabled: expected true or false, got \"no\"");
  CHECK(ErrorWith("/stability/unstable_tolerance", -1.0).find("stability.unstable_tolerance:") ==
        0);
  CHECK(
      ErrorWith("/stability/bifurcation_tolerance", 0.0).find("stability.bifurcation_tolerance:") ==
      0);
  CHECK(ErrorWith("/stability/jump_tolerance", 1.0).find("stability.jump_tolerance:") == 0);
  CHECK(ErrorWith("/stability/max_bifurcation_iterations", 0)
            .find("stability.max_bifurcation_iterations:") == 0);
  CHECK(ErrorWith("/stability/tolerance", 1e-3) == "stability.tolerance: unknown key");
  CHECK(ErrorWith("/stability", 1).find("case.stability: expected an object") == 0);
}

TEST_CASE("unreadable files and invalid JSON name the file") {
  auto load_error = [](const std::string& path) {
    try {
      LoadCase(path);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  CHECK(load_error("/nonexistent/case.json") == "/nonexistent/case.json: cannot open case file");
  const std::string bad = std::string(NFRC_SOURCE_DIR) + "/tests/tools/data/not_json.json";
  CHECK(load_error(bad).find("not_json.json: not valid JSON") != std::string::npos);
}

}  // namespace
}  // namespace nfrc
