#include "core/lcp_siconos.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

// Siconos's headers declare their C functions extern "C" themselves.
#include <LCP_Solvers.h>
#include <LinearComplementarityProblem.h>
#include <NumericsMatrix.h>
#include <SolverOptions.h>
#include <lcp_cst.h>

namespace nfrc {
namespace {

// Owns the Siconos objects of one solve, so that every exit path frees them.
class SiconosProblem {
 public:
  SiconosProblem(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, int solver_id) : q_(q) {
    const int n = static_cast<int>(q.size());
    // Siconos's dense storage is column-major like Eigen's default.
    matrix_ = NM_create(NM_DENSE, n, n);
    std::memcpy(matrix_->matrix0, m.data(), sizeof(double) * n * n);
    problem_.size = n;
    problem_.M = matrix_;
    problem_.q = q_.data();
    options_ = solver_options_create(solver_id);
  }
  ~SiconosProblem() {
    solver_options_delete(options_);  // frees the members, not the struct
    std::free(options_);
    NM_clear(matrix_);  // frees the storage, not the struct
    std::free(matrix_);
  }
  SiconosProblem(const SiconosProblem&) = delete;
  SiconosProblem& operator=(const SiconosProblem&) = delete;

  LinearComplementarityProblem* problem() { return &problem_; }
  SolverOptions* options() { return options_; }

 private:
  Eigen::VectorXd q_;  // Siconos takes a non-const q
  NumericsMatrix* matrix_ = nullptr;
  LinearComplementarityProblem problem_{};
  SolverOptions* options_ = nullptr;
};

}  // namespace

std::string ToString(SiconosLcpSolver solver) {
  switch (solver) {
    case SiconosLcpSolver::kLexicoLemke:
      return "lexicolemke";
    case SiconosLcpSolver::kPivotLemke:
      return "pivot-lemke";
    case SiconosLcpSolver::kEnum:
      return "enum";
  }
  return "unknown";
}

SiconosLcpResult SolveLcpSiconos(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                                 SiconosLcpSolver solver, int max_iterations) {
  if (M.rows() != M.cols() || q.size() != M.rows()) {
    throw std::invalid_argument("SolveLcpSiconos: M is " + std::to_string(M.rows()) + "x" +
                                std::to_string(M.cols()) + ", q has " + std::to_string(q.size()) +
                                " entries");
  }
  const int n = static_cast<int>(q.size());
  SiconosLcpResult r;
  r.z = Eigen::VectorXd::Zero(n);
  r.w = Eigen::VectorXd::Zero(n);
  if (n == 0) {
    r.ok = true;
    r.info = 0;
    r.message = "empty problem";
    return r;
  }
  const int id = solver == SiconosLcpSolver::kLexicoLemke  ? SICONOS_LCP_LEMKE
                 : solver == SiconosLcpSolver::kPivotLemke ? SICONOS_LCP_PIVOT
                                                           : SICONOS_LCP_ENUM;
  SiconosProblem siconos(M, q, id);
  SolverOptions* options = siconos.options();
  if (max_iterations > 0) options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iterations;
  int info = -1;
  switch (solver) {
    case SiconosLcpSolver::kLexicoLemke:
      lcp_lexicolemke(siconos.problem(), r.z.data(), r.w.data(), &info, options);
      break;
    case SiconosLcpSolver::kPivotLemke:
      options->iparam[SICONOS_LCP_IPARAM_PIVOTING_METHOD_TYPE] = SICONOS_LCP_PIVOT_LEMKE;
      lcp_pivot(siconos.problem(), r.z.data(), r.w.data(), &info, options);
      break;
    case SiconosLcpSolver::kEnum:
      lcp_enum_init(siconos.problem(), options, 1);
      lcp_enum(siconos.problem(), r.z.data(), r.w.data(), &info, options);
      lcp_enum_reset(siconos.problem(), options, 1);
      break;
  }
  r.info = info;
  r.ok = info == 0;
  r.iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
  // Siconos's error measure, relative to ‖q‖ (its tolerance is the solver's default); it
  // overwrites w with M z + q, so it gets a copy and r.w stays the solver's.
  Eigen::VectorXd w = r.w;
  lcp_compute_error(siconos.problem(), r.z.data(), w.data(), options->dparam[SICONOS_DPARAM_TOL],
                    &r.error);
  r.complementarity = r.w.cwiseProduct(r.z).lpNorm<Eigen::Infinity>();
  r.feasibility = std::max({0.0, -r.w.minCoeff(), -r.z.minCoeff()});
  r.equation_residual = (r.w - M * r.z - q).lpNorm<Eigen::Infinity>();
  r.message = ToString(solver) + ": info " + std::to_string(info) + ", " +
              std::to_string(r.iterations) + " iterations, error " + std::to_string(r.error);
  return r;
}

}  // namespace nfrc
