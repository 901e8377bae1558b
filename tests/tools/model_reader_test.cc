#include "tools/model_reader.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>

#include "models/damping.h"
#include "models/matrix_market.h"
#include "tools/input_fields.h"

namespace nfrc {
namespace {

std::string TempDir() {
  // One directory per process: ctest runs test cases of this file in parallel.
  const auto dir =
      std::filesystem::temp_directory_path() / ("nfrc_models_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string BuildError(const std::string& text) {
  try {
    BuildModel(nlohmann::json::parse(text), TempDir());
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST_CASE("Matrix Market: coordinate general, coordinate symmetric and array formats") {
  const auto general = ReadMatrixMarket(
      WriteFile("g.mtx",
                "%%MatrixMarket matrix coordinate real general\n% comment\n2 2 3\n1 1 4\n2 1 -1\n"
                "2 2 5.5\n"));
  CHECK(general.coeff(0, 0) == 4.0);
  CHECK(general.coeff(1, 0) == -1.0);
  CHECK(general.coeff(0, 1) == 0.0);
  const auto symmetric = ReadMatrixMarket(WriteFile(
      "s.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 2\n2 1 -1\n"));
  CHECK(symmetric.coeff(0, 1) == -1.0);
  CHECK(symmetric.coeff(1, 0) == -1.0);
  const auto array = ReadMatrixMarket(
      WriteFile("a.mtx", "%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n4\n"));
  CHECK(array.coeff(1, 0) == 2.0);  // column-major
  CHECK(array.coeff(0, 1) == 3.0);
}

TEST_CASE("Matrix Market: errors name the file and line") {
  auto error = [](const std::string& path) {
    try {
      ReadMatrixMarket(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error(TempDir() + "/missing.mtx").find("missing.mtx: cannot open") != std::string::npos);
  const std::string truncated =
      WriteFile("t.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 4\n");
  CHECK(error(truncated).find("t.mtx:3: file ends after 1 of 3 entries") != std::string::npos);
  const std::string complex =
      WriteFile("c.mtx", "%%MatrixMarket matrix coordinate complex general\n1 1 1\n1 1 1 0\n");
  CHECK(error(complex).find("c.mtx:1: field must be real") != std::string::npos);
  const std::string bad_index =
      WriteFile("i.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 1\n3 1 4\n");
  CHECK(error(bad_index).find("i.mtx:3: index out of range") != std::string::npos);
}

TEST_CASE("matrices model: inline, from files, with named DOFs and forcing") {
  WriteFile("k.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 2\n2 1 -1\n"
            "2 2 2\n");
  const ModelDefinition definition = BuildModel(nlohmann::json::parse(R"({
      "type": "matrices", "M": [[1, 0], [0, 2]], "K": "k.mtx",
      "damping": {"rayleigh": {"mass": 0.1, "stiffness": 0.01}},
      "dof_names": ["root", "tip"],
      "forcing": [{"dof": "tip", "cos": 3, "sin": -1, "harmonic": 2}]})"),
                                                TempDir());
  CHECK(definition.model.num_dofs() == 2);
  CHECK(definition.model.stiffness.coeff(0, 1) == -1.0);
  CHECK(definition.model.damping.coeff(1, 1) == doctest::Approx(0.1 * 2 + 0.01 * 2));
  REQUIRE(definition.forcing.size() == 1);
  CHECK(definition.forcing[0].dof == 1);
  CHECK(definition.forcing[0].harmonic == 2);
  CHECK(definition.forcing[0].sin == -1.0);
}

TEST_CASE("modal damping gives ratio ζ in every mode (analytic modes of a 2-DOF chain)") {
  // M = I, K = [[2, -1], [-1, 2]]: modes (1, 1)/√2 at ω = 1 and (1, −1)/√2 at ω = √3.
  const Eigen::MatrixXd k{{2, -1}, {-1, 2}};
  const double zeta = 0.03;
  const Eigen::MatrixXd c = Eigen::MatrixXd(
      ModalDamping(Eigen::MatrixXd::Identity(2, 2).sparseView(), k.sparseView(), zeta));
  const Eigen::Vector2d phi1(1 / std::sqrt(2.0), 1 / std::sqrt(2.0));
  const Eigen::Vector2d phi2(1 / std::sqrt(2.0), -1 / std::sqrt(2.0));
  CHECK(phi1.dot(c * phi1) == doctest::Approx(2 * zeta * 1.0).epsilon(1e-12));
  CHECK(phi2.dot(c * phi2) == doctest::Approx(2 * zeta * std::sqrt(3.0)).epsilon(1e-12));
  CHECK(std::abs(phi1.dot(c * phi2)) < 1e-14);
}

TEST_CASE("bad model objects name the field") {
  CHECK(BuildError(R"({"type": "matrices", "M": [[-1]], "K": [[1]], "forcing": []})")
            .find("model.M: negative mass on the diagonal at DOF 0") == 0);
  CHECK(BuildError(R"({"type": "matrices", "M": [[1, 0], [0, 1]], "K": [[1]], "forcing": []})")
            .find("model.M: size 2x2 differs from K's 1x1") == 0);
  CHECK(BuildError(R"({"type": "matrices", "M": [[1]], "K": [[1]], "forcing": [], "mass": 2})") ==
        "model.mass: unknown key");
  CHECK(BuildError(R"({"type": "matrices", "M": [[1]], "K": [[1, 2]], "forcing": []})")
            .find("model.K: row 0 must be a list of 1 numbers") == 0);
  CHECK(BuildError(R"({"type": "matrices", "M": [[1]], "K": [[1]]})") ==
        "model.forcing: missing (required)");
  CHECK(BuildError(R"({"type": "matrices", "M": [[1]], "K": [[1]],
                       "forcing": [{"dof": "tip", "cos": 1}]})") ==
        "model.forcing[0].dof: no DOF named \"tip\"");
  CHECK(BuildError(R"({"type": "matrices", "M": [[1]], "K": "nope.mtx", "forcing": []})")
            .find("model.K: ") == 0);
  CHECK(BuildError(R"({"type": "beam", "forcing": []})") ==
        "model.type: unknown model type \"beam\"");
  CHECK(BuildError(R"({"type": "matrices", "M": [[1]], "K": [[1]], "forcing": [],
                       "damping": {"modal_ratio": -0.1}})") ==
        "model.damping.modal_ratio: must lie in [0, 10] (1 is critical damping), got -0.1");
  // Refused before any eigenproblem: the message names the field and the size.
  CHECK(BuildError(R"({"type": "rod", "elements": 1001, "length": 1, "area": 1, "young": 1,
                       "density": 1, "damping": {"modal_ratio": 0.01}, "forcing": []})")
            .find("model.damping.modal_ratio: modal damping needs every mode of the model (a "
                  "dense eigenproblem); above 1000 DOFs (this one has 1001)") == 0);
}

// Undamped eigenfrequencies (rad/s) of a model.
Eigen::VectorXd Eigenfrequencies(const LinearModel& model) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(Eigen::MatrixXd(model.stiffness),
                                                                   Eigen::MatrixXd(model.mass));
  return solver.eigenvalues().cwiseSqrt();
}

TEST_CASE("rod case-file object: names, damping, forcing and errors") {
  const auto rod = nlohmann::json::parse(R"({"type": "rod", "elements": 20, "length": 0.13,
      "area": 15.6e-4, "young": 210e9, "density": 7500, "damping": {"modal_ratio": 0.0075},
      "forcing": [{"dof": "end", "cos": 25e3}]})");
  const ModelDefinition definition = BuildModel(rod, ".");
  CHECK(definition.model.num_dofs() == 20);
  CHECK(definition.model.FindDof("end") == 19);
  CHECK(definition.model.FindDof("node1") == 0);
  REQUIRE(definition.forcing.size() == 1);
  CHECK(definition.forcing[0].dof == 19);
  // Linear response at ω0 with 0.75 % modal damping: the resonant amplitude is dominated by
  // mode 1, |x_end| ≈ F φ_end² / (2ζ ω0²) with φ mass-normalised; cases.md: 5.36e-4 m.
  const auto& model = definition.model;
  const double omega0 = Eigenfrequencies(model)(0);
  const Eigen::MatrixXcd z =
      Eigen::MatrixXcd(Eigen::MatrixXd(model.stiffness)) -
      omega0 * omega0 * Eigen::MatrixXcd(Eigen::MatrixXd(model.mass)) +
      std::complex<double>(0, omega0) * Eigen::MatrixXcd(Eigen::MatrixXd(model.damping));
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(20);
  f(19) = 25e3;
  const Eigen::VectorXcd x = z.partialPivLu().solve(f);
  CHECK(std::abs(x(19)) == doctest::Approx(5.36e-4).epsilon(5e-3));  // 3 digits published

  auto error = [](const char* text) {
    try {
      BuildModel(nlohmann::json::parse(text), ".");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error(R"({"type": "rod", "elements": 0, "length": 1, "area": 1, "young": 1,
                  "density": 1, "forcing": []})") == "model.elements: must be at least 1");
  CHECK(error(R"({"type": "rod", "elements": 2, "length": -1, "area": 1, "young": 1,
                  "density": 1, "forcing": []})") == "model.length: must be positive");
  CHECK(error(R"({"type": "rod", "elements": 2, "length": 1, "area": 1, "young": 1,
                  "forcing": []})") == "model.density: missing (required)");
}

}  // namespace
}  // namespace nfrc
