#pragma once

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "nonlinearities/contact_geometry.h"
#include "validation/excitation.h"
#include "validation/transient_model.h"

namespace nfrc {

// g0(φ) of a rigid contact at excitation phase φ (m).
double InitialGap(const ContactGeometry& contact, double phase);
// n(x_dof − x_other) (m); the gap is g0 minus this.
double Approach(const ContactGeometry& contact, const Eigen::VectorXd& x);

// Everything known about time t_n once x_{n+1} is: state, contact forces and the powers.
struct CentralDifferenceNode {
  double t = 0.0;
  double phase = 0.0;
  Eigen::VectorXd x, v;    // v_n = (x_{n+1} − x_{n−1})/2h
  Eigen::VectorXd lambda;  // contact force of each rigid contact (N)
  double energy = 0.0;     // ½vᵀMv + ½xᵀKx (J)
  double power_input = 0.0, power_damping = 0.0, power_laws = 0.0;  // W

  bool InContact(int c) const { return lambda(c) > 0.0; }
};

// The central-difference recursion with forward-increment Lagrange multipliers (Carpenter,
// Taylor & Katona 1991) at a fixed step h:
//   (M/h² + C/2h) x_{n+1} = f_n − K x_n − f_nl(x_n, v_{n−½}) + M(2x_n − x_{n−1})/h²
//                           + C x_{n−1}/2h + Σ n_c λ_c,
// the multipliers λ ≥ 0 making every gap at n+1 non-negative and complementary to λ (a
// scalar for one contact, Lemke's LCP for several). The step is solved as x_{n+1} = x̂ − A⁻¹Gᵀλ
// with the gaps ĝ + Wλ, W = G A⁻¹ Gᵀ, so λ is the contact force in N acting in the equation
// of motion at t_n. Laws must have an explicit force (TimeLaw::ExplicitForce).
class CentralDifferenceScheme {
 public:
  // Keeps a reference to `model`; factorises A = M/h² + C/2h (h in s).
  CentralDifferenceScheme(const TransientModel& model, double h);
  ~CentralDifferenceScheme();

  // x_0, v_0 and x_{−1} from a Taylor step with the initial acceleration
  // M a_0 = f_0 − C v_0 − K x_0 − f_nl(x_0, v_0). False if A or M cannot be factorised.
  bool Start(const Excitation& excitation, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
             std::string* message);
  // Step n: from x_{n−1}, x_n computes x_{n+1} and fills `node` with the quantities at t_n;
  // then shifts x_{n−1} ← x_n ← x_{n+1}.
  bool Step(const Excitation& excitation, long n, CentralDifferenceNode* node,
            std::string* message);

 private:
  class LuSolver;

  void AddExplicitForces(double phase, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                         Eigen::VectorXd* f_nl) const;
  // 0 ≤ λ ⊥ ĝ + Wλ ≥ 0.
  bool SolveMultipliers(std::string* message);

  const TransientModel& model_;
  double h_;
  int n_ = 0;
  bool ok_ = false;
  std::unique_ptr<LuSolver> step_lu_;
  Eigen::MatrixXd ainv_gt_;  // A⁻¹Gᵀ, one column per contact (m/N)
  Eigen::MatrixXd w_;        // Delassus matrix G A⁻¹ Gᵀ (m/N)
  std::vector<int> warm_basis_;
  Eigen::VectorXd x_prev_, x_, x_next_, v_half_, f_, f_nl_, force_laws_, rhs_, lambda_, gap_hat_;
};

}  // namespace nfrc
