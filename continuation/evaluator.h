#pragma once

#include <Eigen/Dense>
#include <memory>

#include "continuation/block_elimination.h"
#include "continuation/problem.h"

namespace nfrc {

// R and its derivatives at one point u = (y, λ).
struct Linearization {
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian_y;
  Eigen::VectorXd jacobian_lambda;
  // The problem's EliminationBlocks (null: none), for the linear solves with this Jacobian.
  std::shared_ptr<const EliminationBlocks> elimination;
};

// Calls ContinuationProblem::Evaluate on stacked points u = (y, λ), counts the calls and
// turns wrong sizes and non-finite output into a failed evaluation (the latter left to the
// problem where it says it checks: ContinuationProblem::ChecksFiniteness).
class Evaluator {
 public:
  explicit Evaluator(ContinuationProblem& problem);

  int num_unknowns() const { return n_; }
  int num_evaluations() const { return num_evaluations_; }

  // Residual and both Jacobians at u (size n + 1); false when they are not available.
  bool Linearize(const Eigen::VectorXd& u, Linearization* result);
  // ContinuationProblem::ResidualNoise at u; 0 where it is not a finite number >= 0.
  double ResidualNoise(const Eigen::VectorXd& u);
  // Residual only.
  bool Residual(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual);

 private:
  ContinuationProblem& problem_;
  int n_;
  bool checks_finiteness_;  // the problem's ChecksFiniteness()
  std::shared_ptr<const EliminationBlocks> elimination_;
  int num_evaluations_ = 0;
};

}  // namespace nfrc
