#pragma once

#include <Eigen/Dense>

#include "continuation/scaling.h"

namespace nfrc {

// Recognises a branch that returns to its first point (an isola or a closed loop), so the
// run stops after one turn instead of circling until max_points.
class ClosureDetector {
 public:
  // u_first = (y, λ) of the first point and its tangent direction (unscaled).
  ClosureDetector(const Eigen::VectorXd& u_first, const Eigen::VectorXd& tangent_first);

  // Called for each accepted step from u_previous to u_new. True when the branch, after
  // having moved away from the first point, passes it again: the first point projects
  // onto the step's chord within a quarter of the chord length, and the new tangent is
  // aligned with the first one (all in the scaled norm).
  bool Closes(const Scaling& scaling, const Eigen::VectorXd& u_previous,
              const Eigen::VectorXd& u_new, const Eigen::VectorXd& tangent_new);

 private:
  Eigen::VectorXd u_first_;
  Eigen::VectorXd tangent_first_;
  bool away_ = false;
};

}  // namespace nfrc
