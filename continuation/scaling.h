#pragma once

#include <Eigen/Dense>
#include <vector>

#include "continuation/options.h"

namespace nfrc {

// Scales of u = (y, λ) defining the scaled norm ‖(Δy/s_y, Δλ/s_λ)‖₂ in which steps, tangents
// and Newton updates are measured, so that a problem in physical units and its
// nondimensional twin take the same steps. Unknowns of one scale group share one scale.
class Scaling {
 public:
  // groups: ScaleGroups() of the problem (any integer labels); lambda_scale > 0.
  Scaling(const std::vector<int>& groups, double lambda_scale, double relative_floor);

  int num_unknowns() const { return static_cast<int>(group_of_.size()); }

  // Raises each group's scale to ‖y_group‖_∞ when that is larger. Scales only grow, so the
  // scaling never oscillates along a branch and it follows deterministically from the
  // accepted points (which keeps physical-unit and nondimensional runs in lockstep).
  void Include(const Eigen::VectorXd& y);

  // Gives groups that are still zero everywhere the magnitude of the matching entries of
  // y_magnitude (a sensitivity such as s_λ·dy/dλ, which carries the unit of y).
  void SeedZeroGroups(const Eigen::VectorXd& y_magnitude);
  // Gives groups still zero the scale at which their columns of ∂R/∂y weigh as much as the
  // heaviest scaled column of the other groups (e.g. contact forces that are all zero at the
  // start and do not move with λ there); groups whose columns vanish keep the floor.
  void SeedZeroGroupsFromColumns(const Eigen::MatrixXd& jacobian_y);
  bool HasZeroGroup() const;

  // Scales of the n unknowns followed by s_λ.
  const Eigen::VectorXd& scales() const { return scales_; }
  double lambda_scale() const { return scales_(num_unknowns()); }

  Eigen::VectorXd ToScaled(const Eigen::VectorXd& du) const { return du.cwiseQuotient(scales_); }
  Eigen::VectorXd FromScaled(const Eigen::VectorXd& du_scaled) const {
    return du_scaled.cwiseProduct(scales_);
  }
  double Norm(const Eigen::VectorXd& du) const { return ToScaled(du).norm(); }
  // Unit vector (in the scaled norm) along the scaled image of the direction t.
  Eigen::VectorXd UnitScaled(const Eigen::VectorXd& t) const { return ToScaled(t).normalized(); }

 private:
  void Refresh();

  std::vector<int> group_of_;       // dense index of each unknown's group
  std::vector<double> group_size_;  // largest ‖y_group‖_∞ seen so far
  double relative_floor_;
  Eigen::VectorXd scales_;
};

// s_λ: options.lambda_scale, or max(|lambda_start|, |lambda_end|) when that is 0.
double LambdaScale(const ContinuationOptions& options);

}  // namespace nfrc
