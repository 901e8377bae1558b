#include "continuation/evaluator.h"

#include <cmath>
#include <stdexcept>

namespace nfrc {

Evaluator::Evaluator(ContinuationProblem& problem)
    : problem_(problem), n_(problem.NumUnknowns()), checks_finiteness_(problem.ChecksFiniteness()) {
  if (n_ < 1) throw std::invalid_argument("ContinuationProblem: NumUnknowns() must be positive");
  EliminationBlocks blocks = problem.EliminationBlocks();
  if (!blocks.empty()) {
    ValidateEliminationBlocks(blocks, n_);
    elimination_ = std::make_shared<const EliminationBlocks>(std::move(blocks));
  }
}

bool Evaluator::Linearize(const Eigen::VectorXd& u, Linearization* result) {
  ++num_evaluations_;
  if (!u.allFinite()) return false;
  result->residual.setZero(n_);
  // Sized, not zeroed: the problem fills every entry (ContinuationProblem::Evaluate), and
  // HarmonicSystem zeroes what its laws add to; a second pass over 321² entries cost 3 %.
  result->jacobian_y.resize(n_, n_);
  result->jacobian_lambda.setZero(n_);
  result->elimination = elimination_;
  const Eigen::VectorXd y = u.head(n_);
  if (!problem_.Evaluate(y, u(n_), &result->residual, &result->jacobian_y,
                         &result->jacobian_lambda)) {
    return false;
  }
  const bool sized = result->residual.size() == n_ && result->jacobian_y.rows() == n_ &&
                     result->jacobian_y.cols() == n_ && result->jacobian_lambda.size() == n_;
  return sized &&
         (checks_finiteness_ || (result->residual.allFinite() && AllFinite(result->jacobian_y) &&
                                 result->jacobian_lambda.allFinite()));
}

double Evaluator::ResidualNoise(const Eigen::VectorXd& u) {
  const double noise = problem_.ResidualNoise(u.head(n_), u(n_));
  return std::isfinite(noise) && noise > 0.0 ? noise : 0.0;
}

bool Evaluator::Residual(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual) {
  ++num_evaluations_;
  if (!y.allFinite() || !std::isfinite(lambda)) return false;
  residual->setZero(n_);
  if (!problem_.Evaluate(y, lambda, residual, nullptr, nullptr)) return false;
  return residual->size() == n_ && (checks_finiteness_ || residual->allFinite());
}

}  // namespace nfrc
