// Finite-difference check of the whole assembled harmonic-balance system R(y, ω): the
// condensed linear part, every law and their coupling, in y and in ω.
#include "analysis/harmonic_system.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "analysis/case.h"
#include "analysis/hill.h"
#include "continuation/evaluator.h"
#include "nonlinearities/jacobian_check.h"
#include "support/chain_case.h"

namespace nfrc {
namespace {

// Central differences with h = 1e-6 relative: truncation O(h²) ~ 1e-12 and round-off
// ~ 1e-16/1e-6 = 1e-10 relative; the nonsmooth laws switch branch only on a set of
// measure zero, which a random point avoids. 1e-6 leaves margin above both while a wrong
// term (a missing sign, a missing ω-derivative of the condensed operator) gives O(1).
constexpr double kRelativeStep = 1e-6;
constexpr double kJacobianTolerance = 1e-6;

ContactGeometry Gap(int dof, double gap) {
  ContactGeometry geometry;
  geometry.dof = dof;
  geometry.gap = gap;
  return geometry;
}

// A five-DOF damped chain (kg, N/m) with one law of each kind on different DOFs, condensed
// onto those DOFs: the interior DOF 2 is condensed out, so Z_red(ω) is a true Schur
// complement and its ω-derivative enters every row.
Case ChainWithEveryLaw() {
  Case c = testing::ChainCase(5);
  c.model.forcing = {ForcingTerm{0, 1, 0.3, 0.0}, ForcingTerm{4, 1, 0.0, 0.1}};
  c.harmonics = HarmonicSet(3, false, 32);
  c.laws.push_back(CubicSpringSpec{0, 1, 0.4});
  c.laws.push_back(testing::Friction(1, 0.3, 0.5));
  c.laws.push_back(PenaltyContactSpec{Gap(3, 0.05), 20.0});
  c.laws.push_back(DlftContactSpec{{Gap(4, 0.08), 50.0, 0.0}});
  c.continuation.lambda_start = 0.8;
  c.continuation.lambda_end = 1.6;
  c.output_dofs = {0};
  c.output_names = {"0"};
  return c;
}

TEST_CASE("harmonic system: the assembled R_y and R_omega match finite differences") {
  const Case the_case = ChainWithEveryLaw();
  the_case.Validate();
  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  std::mt19937 random(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (double omega : {0.9, 1.3}) {
    CAPTURE(omega);
    // The linear response plus a perturbation large enough to open and close the contacts
    // and to make the friction samples both stick and slip.
    Eigen::VectorXd y = system->InitialGuess(omega);
    for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += 0.05 * normal(random);
    const ResidualFunction residual = [&](const Eigen::VectorXd& at, double w, Eigen::VectorXd* r,
                                          Eigen::MatrixXd* jacobian, Eigen::VectorXd* d_omega) {
      REQUIRE(system->Evaluate(at, w, r, jacobian, d_omega));
    };
    const JacobianCheckResult check =
        CheckJacobian(residual, y, omega, kRelativeStep, /*typical_y=*/0.1);
    CAPTURE(check.worst_row);
    CAPTURE(check.worst_col);
    CHECK(check.y_error < kJacobianTolerance);
    CHECK(check.residual_error <= kSameResidual);
    CHECK(check.omega_error < kJacobianTolerance);
  }
}

TEST_CASE("harmonic system: non-finite outputs fail the evaluation itself, as the engine trusts") {
  std::unique_ptr<HarmonicSystem> system = BuildSystem(ChainWithEveryLaw());
  REQUIRE(system->ChecksFiniteness());  // the engine then skips its own pass over R_y
  constexpr double kOmega = 1.1;
  Eigen::VectorXd y = system->InitialGuess(kOmega);
  // The cubic spring's DOF at 1e120 m: its force k3·x³ ~ 1e360 N overflows.
  y(0) = 1e120;
  Eigen::VectorXd residual, d_omega;
  Eigen::MatrixXd jacobian;
  CHECK_FALSE(system->Evaluate(y, kOmega, &residual, &jacobian, &d_omega));
  CHECK(system->last_error().find("not finite at omega") != std::string::npos);
  CHECK_FALSE(system->Evaluate(y, kOmega, &residual, nullptr, nullptr));
  Evaluator evaluator(*system);
  Eigen::VectorXd u(y.size() + 1);
  u << y, kOmega;
  Linearization linearization;
  CHECK_FALSE(evaluator.Linearize(u, &linearization));
  CHECK_FALSE(evaluator.Residual(y, kOmega, &residual));
  // And finite where the spring's DOF is back at a physical amplitude.
  y(0) = 0.1;
  u(0) = 0.1;
  CHECK(evaluator.Linearize(u, &linearization));
}

// Recovering DOFs moves the condensation alone (no real forms): a later evaluation at the
// frequency the real forms were cached for must not read the moved condensation. A fresh
// system at that frequency is the reference, bit for bit.
TEST_CASE("harmonic system: recovering DOFs at another frequency leaves no stale state") {
  const Case the_case = ChainWithEveryLaw();
  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  std::unique_ptr<HarmonicSystem> fresh = BuildSystem(the_case);
  constexpr double kCached = 1.1, kOther = 0.9;
  const Eigen::VectorXd y = system->InitialGuess(kCached);
  REQUIRE(fresh->InitialGuess(kCached) == y);
  Eigen::VectorXd residual, d_omega, fresh_residual, fresh_d_omega;
  Eigen::MatrixXd jacobian, fresh_jacobian;
  REQUIRE(system->Evaluate(y, kCached, &residual, &jacobian, &d_omega));
  const Eigen::MatrixXd recovered = system->AllDofCoefficients(y, kOther);
  CHECK(recovered == fresh->AllDofCoefficients(y, kOther));
  CHECK(system->DofCoefficients(y, kOther, 2) == recovered.row(2).transpose());
  fresh = BuildSystem(the_case);
  const double noise = system->ResidualNoise(y, kCached);
  CHECK(noise > 0.0);  // DOF 2 is condensed out: the operator carries rounding
  CHECK(noise == fresh->ResidualNoise(y, kCached));
  REQUIRE(system->Evaluate(y, kCached, &residual, &jacobian, &d_omega));
  REQUIRE(fresh->Evaluate(y, kCached, &fresh_residual, &fresh_jacobian, &fresh_d_omega));
  CHECK(residual == fresh_residual);
  CHECK(jacobian == fresh_jacobian);
  CHECK(d_omega == fresh_d_omega);
}

// Two unit masses, undamped, friction on DOF 0 and DOF 1 condensed out with k_11 = 4 N/m: at
// ω = 2 rad/s the first harmonic's Z_ll = k_11 − ω²m_11 is exactly zero.
TEST_CASE("harmonic system: a singular condensed operator is a numerical failure, then cleared") {
  Case c = testing::ChainCase(2);
  Eigen::MatrixXd k(2, 2);
  k << 2.0, -1.0, -1.0, 4.0;
  c.model.model.stiffness = k.sparseView();
  c.model.model.damping = Eigen::SparseMatrix<double>(2, 2);
  c.model.forcing = {ForcingTerm{0, 1, 0.3, 0.0}};
  c.harmonics = HarmonicSet(3, false, 32);
  c.laws.push_back(testing::Friction(0, 0.3, 0.5));
  c.continuation.lambda_start = 1.5;
  c.continuation.lambda_end = 2.5;
  c.output_dofs = {0};
  c.output_names = {"0"};
  c.Validate();
  std::unique_ptr<HarmonicSystem> system = BuildSystem(c);
  constexpr double kRegular = 1.9, kInteriorResonance = 2.0;
  const Eigen::VectorXd y = system->InitialGuess(kRegular);
  Eigen::VectorXd residual, d_omega;
  Eigen::MatrixXd jacobian;
  REQUIRE(system->Evaluate(y, kRegular, &residual, &jacobian, &d_omega));
  // Every way in returns false with the cause; none throws.
  CHECK_FALSE(system->Prepare(kInteriorResonance));
  CHECK(system->last_error().find("singular") != std::string::npos);
  CHECK_FALSE(system->Evaluate(y, kInteriorResonance, &residual, &jacobian, &d_omega));
  CHECK(system->last_error().find("singular") != std::string::npos);
  Evaluator evaluator(*system);
  Eigen::VectorXd u(y.size() + 1);
  u << y, kInteriorResonance;
  Linearization linearization;
  CHECK_FALSE(evaluator.Linearize(u, &linearization));
  // Hill's assembly refuses the point by name (its callers report the analysis as failed).
  CHECK_THROWS_WITH_AS(AssembleHillPencil(*system, y, kInteriorResonance),
                       doctest::Contains("singular"), std::runtime_error);
  // Nothing of the failed move stays: back at a regular ω the system evaluates as a fresh one.
  std::unique_ptr<HarmonicSystem> fresh = BuildSystem(c);
  Eigen::VectorXd fresh_residual, fresh_d_omega;
  Eigen::MatrixXd fresh_jacobian;
  REQUIRE(system->Evaluate(y, kRegular, &residual, &jacobian, &d_omega));
  REQUIRE(fresh->Evaluate(y, kRegular, &fresh_residual, &fresh_jacobian, &fresh_d_omega));
  CHECK(residual == fresh_residual);
  CHECK(jacobian == fresh_jacobian);
  CHECK(d_omega == fresh_d_omega);
}

TEST_CASE("harmonic system: step weights are 1 on displacements and own_step_weight elsewhere") {
  const auto system = BuildSystem(ChainWithEveryLaw());
  const int nx = system->num_displacement_unknowns();
  REQUIRE(system->NumUnknowns() > nx);  // the friction law has its own unknowns
  for (const double weight : {0.3, 0.0, 1.0}) {
    if (weight != 0.3) system->set_own_step_weight(weight);  // 0.3 is the default
    const Eigen::VectorXd w = system->StepWeights();
    CHECK(w.head(nx).isOnes());
    CHECK(w.tail(w.size() - nx).isConstant(weight));
  }
  CHECK_THROWS_WITH_AS(system->set_own_step_weight(1.5), "own_step_weight: must lie in [0, 1]",
                       std::invalid_argument);
  CHECK_THROWS_AS(system->set_own_step_weight(std::nan("")), std::invalid_argument);
}

TEST_CASE("harmonic system: elimination blocks where only friction forces enter the motion") {
  // Every law kind: the contact and spring laws write ∂f/∂x, so nothing is eliminated.
  CHECK(BuildSystem(ChainWithEveryLaw())->EliminationBlocks().empty());

  // Friction alone (two laws, one relative): one block per harmonic, and the Jacobian at a
  // random point couples no two blocks (the promise the engine's Schur complement needs).
  Case c = testing::ChainCase(5);
  c.model.forcing = {ForcingTerm{0, 1, 0.3, 0.0}};
  c.harmonics = HarmonicSet(3, false, 32);
  c.laws.push_back(testing::Friction(1, 0.3, 0.5));
  c.laws.push_back(testing::Friction(3, 0.3, 0.5, 4));
  c.continuation.lambda_start = 0.8;
  c.continuation.lambda_end = 1.6;
  c.output_dofs = {0};
  c.output_names = {"0"};
  const auto system = BuildSystem(c);
  const std::vector<std::vector<int>> blocks = system->EliminationBlocks();
  REQUIRE(blocks.size() == 4);  // harmonics 0..3
  std::vector<int> block_of(system->NumUnknowns(), -1);
  int covered = 0;
  for (size_t k = 0; k < blocks.size(); ++k) {
    for (const int i : blocks[k]) {
      block_of[i] = static_cast<int>(k);
      ++covered;
    }
  }
  CHECK(covered == system->num_displacement_unknowns());
  std::mt19937 random(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd y = system->InitialGuess(1.1);
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += 0.05 * normal(random);
  Eigen::VectorXd residual, d_omega;
  Eigen::MatrixXd jacobian;
  REQUIRE(system->Evaluate(y, 1.1, &residual, &jacobian, &d_omega));
  for (int i = 0; i < system->NumUnknowns(); ++i) {
    for (int j = 0; j < system->NumUnknowns(); ++j) {
      if (block_of[i] >= 0 && block_of[j] >= 0 && block_of[i] != block_of[j]) {
        CHECK(jacobian(i, j) == 0.0);
      }
    }
  }
}

TEST_CASE("harmonic system: a case built in memory is copied and rebuilt with fewer harmonics") {
  Case fine = ChainWithEveryLaw();
  Case coarse = fine;
  coarse.harmonics = HarmonicSet(1, false);
  const auto fine_system = BuildSystem(fine);
  const auto coarse_system = BuildSystem(coarse);
  // 4 retained DOFs (the laws' DOFs 0, 1, 3, 4) plus the friction force: 5 signals.
  CHECK(fine_system->NumUnknowns() == 5 * 7);
  CHECK(coarse_system->NumUnknowns() == 5 * 3);
  CHECK(fine.harmonics.max_harmonic() == 3);  // the copy did not touch the original
}

}  // namespace
}  // namespace nfrc
