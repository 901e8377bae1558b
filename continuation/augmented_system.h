#pragma once

#include <Eigen/Dense>

#include "continuation/evaluator.h"
#include "continuation/scaling.h"

namespace nfrc {

// The scaled bordered matrix [[R_y D_y, R_λ s_λ] / r; cᵀ] acting on scaled increments
// (Δy/s_y, Δλ/s_λ): columns scaled by the unknowns' scales, rows of R by the residual
// scale r, so that its entries (and the LU's pivot choices) do not depend on units.
Eigen::MatrixXd AugmentedMatrix(const Linearization& linearization, const Scaling& scaling,
                                double residual_scale, const Eigen::VectorXd& last_row);
// The same into `a`, whose storage is kept when it already has the size: a corrector's
// iterations then fill one buffer (at 2 561 unknowns a new one is 52 MB of fresh pages).
void AugmentedMatrix(const Linearization& linearization, const Scaling& scaling,
                     double residual_scale, const Eigen::VectorXd& last_row, Eigen::MatrixXd* a);

// Solves a x = b by a partial-pivoting LU; false if a pivot is at rounding level against the
// largest (a numerically singular) or x is not finite. determinant_sign (optional): the sign
// of det a, set when true is returned.
bool SolveRegular(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                  int* determinant_sign = nullptr);

// Solves a x = b by one partial-pivoting LU of the whole matrix; falls back to a
// full-pivoting LU when that LU is (numerically) singular. False if x is not finite.
// With `elimination` (the Jacobian's blocks, whose indices are the same in the augmented
// matrix), SolveEliminating is tried first. determinant_sign (optional): the sign of det a
// from the factorisation that solved (0 after the full-pivoting fallback: a is singular to
// rounding, its sign undecided).
bool SolveAugmented(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                    const EliminationBlocks* elimination = nullptr,
                    int* determinant_sign = nullptr);

}  // namespace nfrc
