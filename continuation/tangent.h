#pragma once

#include <Eigen/Dense>

#include "continuation/augmented_system.h"
#include "continuation/evaluator.h"
#include "continuation/scaling.h"

namespace nfrc {

// Tangents are unit vectors in scaled coordinates (Δy/s_y, Δλ/s_λ); Scaling::FromScaled
// turns them into directions of the unscaled curve.

// Tangent at the first point: the null vector of the scaled [R_y, R_λ], with its λ component
// of the sign of lambda_direction. From the border Δλ = 1 by one LU, checked to be a null
// vector; else (a start at a fold) from a rank-revealing QR. False if the null space is not
// one-dimensional. orientation (optional): OrientationIndex of the tangent, from the same LU
// (0 after the QR: undecided).
bool InitialTangent(const Linearization& linearization, const Scaling& scaling,
                    double residual_scale, double lambda_direction, Eigen::VectorXd* tangent_scaled,
                    int* orientation = nullptr);

// Tangent from the bordered system [[R_y, R_λ]; τ_prevᵀ] τ = [0; 1], normalised: the border
// fixes the orientation (τᵀ τ_prev > 0) and keeps the system regular at simple folds.
// orientation (optional): OrientationIndex of the returned tangent, from the same LU (0 where
// it is undecided). Replacing the border b by τ = s/‖s‖, s the solution (bᵀs = 1), is a rank-one
// change of the last row: det [J; τᵀ] = det [J; bᵀ] (1 + (τ − b)ᵀ s) = det [J; bᵀ] ‖s‖, so
// both determinants have one sign and the index costs no second factorisation.
bool NextTangent(const Linearization& linearization, const Scaling& scaling, double residual_scale,
                 const Eigen::VectorXd& previous_scaled, Eigen::VectorXd* tangent_scaled,
                 int* orientation = nullptr);

// The same from the factorisation of a corrector's last Newton matrix (CorrectorResult::
// last_step), whose border is previous_scaled and whose Jacobians were taken one Newton update
// before the point: that LU's solution refined by the point's own Jacobians in `linearization`
// (iterative refinement) until it is theirs to ~1e-10, so no factorisation of its own. The
// orientation is that LU's (the refinement converging fast, the two determinants share a sign).
// False where the refinement does not converge in two steps (a kink crossed in that update):
// the caller then factorises (the form above).
bool NextTangent(const AugmentedSolver& last_step, const Linearization& linearization,
                 const Scaling& scaling, double residual_scale,
                 const Eigen::VectorXd& previous_scaled, Eigen::VectorXd* tangent_scaled,
                 int* orientation = nullptr);

// The orientation index of a unit scaled tangent τ at a point: the sign of
// det [[R_y D_y, R_λ s_λ] / r; τᵀ] (+1 or −1; 0 if that matrix is singular to rounding).
// Along a branch of a continuous, piecewise-smooth R it keeps its sign through folds and
// across the corners where the active piece changes (the orientation of piecewise-linear
// continuation: the Jacobians on the two sides of a switching surface differ by a rank-one
// term that vanishes along it), whereas the rule τᵀτ_prev > 0 of NextTangent can point back
// along the branch past a corner that turns it by more than 90°. It changes sign at branch
// points. Positive scalings do not change it, so indices taken in different scalings compare.
int OrientationIndex(const Linearization& linearization, const Scaling& scaling,
                     double residual_scale, const Eigen::VectorXd& tangent_scaled);

}  // namespace nfrc
