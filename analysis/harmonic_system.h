#pragma once

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "continuation/problem.h"
#include "core/condensation.h"
#include "core/fourier_transform.h"
#include "core/linear_model.h"
#include "core/nonlinearity.h"

namespace nfrc {

// The harmonic-balance equations R(y, ω) = Z_red(ω) x − F_red(ω) + Σ f_law(y, ω) of a
// linear model condensed onto the DOFs its laws (and the outputs) act on, plus the laws'
// own equations: the problem the continuation engine follows in ω.
class HarmonicSystem : public ContinuationProblem {
 public:
  // Retains the laws' DOFs; a problem without laws retains `output_dofs` (or the forced
  // DOFs). Other DOFs, outputs included, are recovered from the solution when asked for.
  HarmonicSystem(ModelDefinition model, HarmonicSet set,
                 std::vector<std::unique_ptr<Nonlinearity>> laws, std::vector<int> output_dofs,
                 Condensation::Method method = Condensation::Method::kAuto);

  int NumUnknowns() const override { return num_unknowns_; }
  bool Evaluate(const Eigen::VectorXd& y, double omega, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_omega) override;
  // Group 0: displacement coefficients (and own unknowns in metres); group i + 1: own
  // unknowns of law i.
  // Evaluate returns false, with last_error(), wherever an output is not finite.
  bool ChecksFiniteness() const override { return true; }
  std::vector<int> ScaleGroups() const override;
  // Displacement coefficients weigh 1, the laws' own unknowns own_step_weight(): the curve a
  // user reads is the motion's, while a law's own unknowns (a friction force's harmonics)
  // jump at every sample that switches branch and shrink the step at each kink.
  Eigen::VectorXd StepWeights() const override;
  // One block per harmonic (its cosine and sine coefficients of every retained DOF) when no
  // law writes into the displacement block and some law has own unknowns: the linear part is
  // then all of that block, and eliminating it leaves a dense solve on the laws' unknowns
  // (half the size for a friction force on one DOF).
  std::vector<std::vector<int>> EliminationBlocks() const override;
  // ‖(|δZ| |X| + |δF|)‖ over the displacement rows, from Condensation::EstimateRounding at
  // ω: the rounding of the condensed operator (large on fine meshes), which moves with ω.
  double ResidualNoise(const Eigen::VectorXd& y, double omega) override;
  // The default 0.3 keeps the accuracy of the Fig. 7 curves with fewer points than 1;
  // `nfrc_bench 11` prints points and accuracy for 1, 0.3, 0.1 and 0. Throws
  // std::invalid_argument outside [0, 1].
  double own_step_weight() const { return own_step_weight_; }
  void set_own_step_weight(double weight);

  // The linear response x = Z_red⁻¹ F_red at ω with the laws' own starting values.
  // Throws InputError if the linear dynamic stiffness is singular there.
  Eigen::VectorXd InitialGuess(double omega);

  // Coefficients of model DOF `dof` (HarmonicSet layout) in solution y at ω; DOFs that
  // were condensed out are recovered.
  Eigen::VectorXd DofCoefficients(const Eigen::VectorXd& y, double omega, int dof);

  // Coefficients of every model DOF (num_dofs × NumCoefficients, row = DOF) in solution y.
  Eigen::MatrixXd AllDofCoefficients(const Eigen::VectorXd& y, double omega);

  // The real condensed operator A and forcing b of the linear part at ω: R = A x − b + Σ f_law.
  const Eigen::MatrixXd& LinearOperator(double omega);
  const Eigen::VectorXd& LinearForcing(double omega);

  const FourierTransform& fourier() const { return fourier_; }
  const HarmonicSet& harmonic_set() const { return fourier_.harmonic_set(); }
  const LinearModel& model() const { return model_; }
  int num_displacement_unknowns() const { return num_displacement_unknowns_; }
  // Model DOF of each retained position (the condensed unknowns' DOF order).
  const std::vector<int>& retained() const { return retained_; }
  const std::vector<std::unique_ptr<Nonlinearity>>& laws() const { return laws_; }
  const NonlinearityContext& context(int law) const { return contexts_[law]; }
  // What Evaluate does before the laws: the linear part moved to ω and the laws bound, for
  // callers that linearise the laws themselves (Hill's assembly). False, with last_error(),
  // where the condensed operator cannot be formed at ω (a numerical failure, as there).
  bool Prepare(double omega);
  // Why the last Evaluate or Prepare returned false.
  const std::string& last_error() const { return last_error_; }

 private:
  void MoveTo(double omega);
  // out = (the cached operator or its ω-derivative)·x, after MoveTo.
  void ApplyOperator(bool derivative, const Eigen::Ref<const Eigen::VectorXd>& x,
                     Eigen::Ref<Eigen::VectorXd> out) const;
  // Calls every law's Bind once the condensation exists; InputError names the law.
  void BindLaws();

  LinearModel model_;
  FourierTransform fourier_;
  std::vector<std::unique_ptr<Nonlinearity>> laws_;
  std::vector<int> retained_;
  Condensation condensation_;
  std::vector<NonlinearityContext> contexts_;
  int num_displacement_unknowns_ = 0;
  int num_unknowns_ = 0;
  bool has_obstacles_ = false;
  bool bound_ = false;
  double own_step_weight_ = 0.3;  // see own_step_weight()
  // Real condensed operator and forcing (and ω-derivatives) cached for cached_omega_.
  double cached_omega_;
  Eigen::MatrixXd z_;
  Eigen::MatrixXd dz_;
  Eigen::VectorXd f_;
  Eigen::VectorXd df_;
  std::string last_error_;
};

}  // namespace nfrc
