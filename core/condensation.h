#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "core/harmonic_set.h"
#include "core/linear_model.h"

namespace nfrc {

// Exact condensation of a linear model onto retained DOFs, harmonic by harmonic:
//   Z_red = Z_rr − Z_rl Z_ll⁻¹ Z_lr,   F_red = F_r − Z_rl Z_ll⁻¹ F_l,
// with their ω-derivatives, and recovery of every DOF after a solve. Complex amplitudes
// follow DynamicStiffness's convention. Unknown vectors of the condensed problem are
// real and DOF-major: entry (r, c) of the retained DOF r's coefficient c is at
// r·NumCoefficients() + c.
class Condensation {
 public:
  enum class Method {
    kAuto,    // kModal where the model qualifies and some DOF is condensed; else dense below
              // kDenseLimit DOFs or above kDenseFill fill of Z_ll, else sparse
    kDense,   // dense LU per harmonic
    kSparse,  // SuiteSparse sparse LU per harmonic (KLU, or UMFPACK if fill is heavy)
    kModal,   // through the modes of the whole model (core/modal_receptance.h): small,
              // symmetric, proportionally damped models; a harmonic where the modal form is
              // unusable (an undamped resonance) takes the direct form as kAuto would
  };
  static constexpr int kDenseLimit = 64;
  static constexpr double kDenseFill = 0.2;

  // Throws std::invalid_argument if a retained DOF or a forcing DOF is out of range or
  // repeated in `retained`, a forcing harmonic is not in `set`, or kModal is asked of a
  // model that does not qualify (the reason named).
  Condensation(LinearModel model, std::vector<int> retained, HarmonicSet set,
               std::vector<ForcingTerm> forcing, Method method = Method::kAuto);
  ~Condensation();
  Condensation(Condensation&&) noexcept;
  Condensation& operator=(Condensation&&) noexcept;

  // The static split (default on): the stiffness part of the Schur complement is condensed
  // once, through the static modes −K_ll⁻¹K_lr, and only the mass and damping terms at each
  // ω. On fine meshes, where K_rr and K_rl K_ll⁻¹ K_lr cancel to many digits, this keeps
  // the rounding of Z_red(ω) from moving with ω (10⁵-element rod: 1.5e3 → 69 N/m, `nfrc_bench
  // 5`; tests/core/condensation_chain_test.cc). It is used when K_ll is regular; otherwise (a
  // mechanism once the retained DOFs are held) the direct form is. Set before Update.
  void set_static_split(bool on);
  // Whether the last Update used the static split (on some harmonic).
  bool static_split() const;
  // Whether the last Update condensed every harmonic through the modes (Method::kModal).
  bool modal() const;

  // Factorises and condenses at ω (no-op if already at ω). Throws std::runtime_error
  // naming the harmonic and ω if Z_ll is singular there.
  void Update(double omega);
  double omega() const { return omega_; }

  // Massless obstacles behind retained DOFs: compliance (m/N, ≥ 0; 0 = rigid or none) per
  // retained DOF. When any is non-zero the condensed unknowns of those DOFs are relative
  // displacements x − x_obs and Z, F and their derivatives are those of
  // relative_coordinates.h; Recover returns absolute displacements. Throws
  // std::invalid_argument for a wrong size or a negative or non-finite entry.
  void SetObstacleCompliance(std::vector<double> compliance);
  bool has_obstacles() const { return !compliance_.empty(); }

  const std::vector<int>& retained() const { return retained_; }
  const HarmonicSet& harmonic_set() const { return set_; }
  int num_retained() const { return static_cast<int>(retained_.size()); }
  int num_unknowns() const { return num_retained() * set_.NumCoefficients(); }

  // Complex condensed operator, its ω-derivative, condensed forcing and its ω-derivative
  // for the harmonic at `position` in harmonic_set().harmonics() (after Update).
  const Eigen::MatrixXcd& Z(int position) const;
  const Eigen::MatrixXcd& dZ(int position) const;
  const Eigen::VectorXcd& F(int position) const;
  const Eigen::VectorXcd& dF(int position) const;

  // Estimated rounding of Z and F at the current ω, per harmonic position: entry-wise
  // magnitudes |B δY| of the error that a step of iterative refinement finds in the interior
  // solves Y = Z_ll⁻¹ b (δY = Z_ll⁻¹ (b − Z_ll Y), B the rows that multiply Y), in the units
  // of Z and F. Two solves per harmonic: for a stalled corrector, not every evaluation.
  struct Rounding {
    std::vector<Eigen::MatrixXd> z;
    std::vector<Eigen::VectorXd> f;
  };
  Rounding EstimateRounding() const;

  // Real forms in the condensed unknown layout (after Update): the linear residual of the
  // condensed problem is RealOperator()·x − RealForcing().
  Eigen::MatrixXd RealOperator() const;
  Eigen::MatrixXd RealOperatorDerivative() const;
  Eigen::VectorXd RealForcing() const;
  Eigen::VectorXd RealForcingDerivative() const;
  // RealOperator() (or its derivative) written into `out`, num_unknowns() square: only the
  // entries the layout can make nonzero (the 2 × 2 block of each harmonic and retained pair)
  // are written, the others are left as they are. A cache zeroed once is then refreshed at
  // each ω without a fresh matrix, and a zeroed Jacobian takes the operator without a copy.
  void WriteRealOperator(bool derivative, Eigen::Ref<Eigen::MatrixXd> out) const;
  // out = RealOperator()·x (or its derivative's), num_unknowns() each, from the layout's
  // entries only, each row's sum in ascending column order from +0.0. With one retained DOF a
  // row has at most two terms, so this is any dense product's result bit for bit; with more,
  // a dense product's blocking may associate the terms otherwise (rounding apart).
  void ApplyRealOperator(bool derivative, const Eigen::Ref<const Eigen::VectorXd>& x,
                         Eigen::Ref<Eigen::VectorXd> out) const;
  // Rows of RealOperator() (or of its derivative) belonging to retained DOF i
  // (NumCoefficients × num_unknowns), and the matching rows of the forcing.
  Eigen::MatrixXd RealOperatorRows(int i, bool derivative) const;
  Eigen::VectorXd RealForcingRows(int i, bool derivative) const;

  // Coefficients of every DOF (num_dofs × NumCoefficients, row = DOF) given the retained
  // DOFs' coefficients x (condensed layout), at the current ω. With obstacles, x holds
  // relative displacements and must solve the condensed equations (the interface force is
  // read from them).
  Eigen::MatrixXd Recover(const Eigen::Ref<const Eigen::VectorXd>& x) const;

 private:
  struct Impl;
  LinearModel model_;
  std::vector<int> retained_;
  HarmonicSet set_;
  std::vector<ForcingTerm> forcing_;
  Method method_;
  std::vector<double> compliance_;  // empty: no obstacle
  double omega_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nfrc
