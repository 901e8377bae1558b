#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>
#include <vector>

#include "validation/excitation.h"
#include "validation/time_law.h"
#include "validation/transient_model.h"

namespace nfrc {

// The DAE that IDA integrates for a TransientModel under an Excitation, without SUNDIALS:
//   y = [x (n) | v (n) | laws' own unknowns | quadratures (kNumQuadratures)],
//   F = [ẋ − v | M v̇ + C v + K x + Σ f_nl − f(t) | laws' own rows | q̇ − integrands],
// the quadratures being ∫E dt, ∫fᵀv dt, ∫vᵀCv dt and ∫f_nlᵀv dt. It evaluates F, its Jacobian
// and the laws' root functions, and makes (y, ẏ) consistent in the laws' modes.
//
// Index reduction: the momentum row of an undamped massless DOF on which a law's differential
// own unknown acts (exact friction on a massless slider, index 2 while sliding) is
// differentiated in time; SnapAndProject/MakeConsistent bring the state back onto the original
// row at every restart.
class IdaDae {
 public:
  using Triplets = std::vector<Eigen::Triplet<double>>;
  static constexpr int kNumQuadratures = 4;

  // Keeps references to both; changes the laws' modes.
  IdaDae(TransientModel& model, const Excitation& excitation);

  int num_dofs() const { return n_; }
  int size() const { return size_; }
  int quadrature_offset() const { return q_; }
  int num_roots() const { return num_roots_; }
  // Whether y_j is differential (IDA's id vector); algebraic unknowns are not.
  bool differential(int j) const { return differential_[j]; }
  const Excitation& excitation() const { return excitation_; }
  // Where law l's rows and columns are, and the index of its first root function.
  const TimeLawLayout& layout(size_t l) const { return layouts_[l]; }
  int root_offset(size_t l) const { return root_offsets_[l]; }

  // What law l sees of (t, y, ẏ).
  DaeView View(size_t l, double t, const double* y, const double* yp) const;
  // F(t, y, ẏ), size(), with the reduced rows differentiated.
  void Residual(double t, const double* y, const double* yp, double* r) const;
  // Triplets of ∂F/∂y + cj ∂F/∂ẏ (explicit zeros kept: the pattern depends on the modes only).
  void Assemble(double t, const double* y, const double* yp, double cj, Triplets* out) const;
  // The laws' root functions, num_roots() of them.
  void Roots(double t, const double* y, const double* yp, double* g) const;

  // At a start: the laws' modes from the state, the differential own unknowns from the
  // original rows, then SettleModes. False (message()) if no consistent state exists.
  bool Initialise(double t, double* y, double* yp);
  // Consistent values in the current modes until every law accepts its mode.
  bool SettleModes(double t, double* y, double* yp);
  // Solves F = 0 for ẏ of the differential unknowns and for the algebraic unknowns, x and
  // the massed v held (after the projection onto the original rows, if any).
  bool MakeConsistent(double t, double* y, double* yp);
  bool has_reduced_rows() const { return !reduced_.empty(); }

  const std::string& message() const { return message_; }

 private:
  bool Fail(const std::string& message);
  // force_ = f(t) and f_nl_ = Σ f_nl at (t, y, ẏ).
  void Forces(double t, const double* y, const double* yp) const;
  void FindReducedRows();
  void OriginalRowJacobian(double t, const double* y, const double* yp) const;
  void OriginalResidual(double t, const double* y, const double* yp, double* r) const;
  bool SolveOriginalRows(double t, const std::vector<int>& columns, double* y, const double* yp);
  bool SnapAndProject(double t, double* y, const double* yp);

  TransientModel& model_;
  const Excitation& excitation_;
  int n_ = 0;
  int q_ = 0;  // index of the first quadrature in y
  int size_ = 0;
  int num_roots_ = 0;
  std::vector<TimeLawLayout> layouts_;
  std::vector<int> root_offsets_;
  std::vector<bool> differential_;
  // Index reduction: the DOFs whose momentum rows are differentiated, each DOF's index among
  // them (−1: none), an own unknown and the x column of each, and a flag per row of F.
  std::vector<int> reduced_, reduced_index_, reduced_own_columns_, reduced_x_columns_;
  std::vector<bool> reduced_rows_;
  mutable Eigen::MatrixXd j0_;  // ∂F/∂y of the reduced DOFs' original rows
  mutable Eigen::VectorXd rate_;
  mutable Triplets law_scratch_;
  Triplets stiffness_, damping_, mass_;  // K, C, M placed in the momentum rows of ∂F/∂y
  Eigen::SparseMatrix<double> k_sym_, m_sym_, c_sym_;
  mutable Eigen::VectorXd force_, f_nl_, scratch_;
  std::string message_;
};

}  // namespace nfrc
