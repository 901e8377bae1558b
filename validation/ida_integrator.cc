#include "validation/ida_integrator.h"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <Eigen/SparseLU>
#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <deque>
#include <new>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"

namespace nfrc {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;
using Clock = std::chrono::steady_clock;

constexpr double kTwoPi = 6.283185307179586;
constexpr int kNumQuadratures = 4;  // ∫E dt, ∫fᵀv dt, ∫vᵀCv dt, ∫f_nlᵀv dt
constexpr int kMaxModeRounds = 8;
constexpr long kMaxEventsPerPeriod = 10000;
// A root reported this soon (× period) after a re-initialisation by the root just handled is
// that root again, not a new crossing.
constexpr double kRepeatedRootWindow = 1e-12;
constexpr int kConsistentIterations = 3;  // F is affine in the unknowns: 1 suffices, 2 checks
// Newton iterations of the projection onto the undifferentiated rows (affine for friction and
// linear springs: 1 suffices; a polynomial spring on the row needs a few).
constexpr int kProjectionIterations = 20;
// The quadratures grow with time and rtol·|q| with them; zeroing them this often keeps their
// error test and Newton test meaningful for one period's increment.
constexpr int kQuadratureResetPeriods = 32;
constexpr long kMaxStepsPerCall = 20000;  // then AdvanceTo looks at the wall clock
constexpr int kDenseResponseLimit = 300;  // DOFs up to which the linear response is dense

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string FlagName(int flag) {
  char* name = IDAGetReturnFlagName(flag);
  std::string text = name != nullptr ? name : "unknown IDA flag";
  free(name);  // IDA allocates it with malloc
  return text;
}

// Every SUNDIALS object of one run, freed in reverse order on every path.
struct Sundials {
  SUNContext context = nullptr;
  N_Vector y = nullptr;
  N_Vector yp = nullptr;
  N_Vector id = nullptr;
  N_Vector atol = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver solver = nullptr;
  void* ida = nullptr;

  Sundials() = default;
  Sundials(const Sundials&) = delete;
  Sundials& operator=(const Sundials&) = delete;
  ~Sundials() {
    if (ida != nullptr) IDAFree(&ida);
    if (solver != nullptr) SUNLinSolFree(solver);
    if (matrix != nullptr) SUNMatDestroy(matrix);
    for (N_Vector v : {y, yp, id, atol}) {
      if (v != nullptr) N_VDestroy(v);
    }
    if (context != nullptr) SUNContext_Free(&context);
  }
};

// max over DOFs of Σ_h |X_h| with (K − (hω)²M + ihωC) X_h = F_h: the linear response amplitude.
double LinearAmplitude(const LinearModel& model, const std::vector<ForcingTerm>& terms,
                       double omega) {
  const int n = model.num_dofs();
  std::vector<int> harmonics;
  for (const auto& term : terms) {
    if (std::find(harmonics.begin(), harmonics.end(), term.harmonic) == harmonics.end()) {
      harmonics.push_back(term.harmonic);
    }
  }
  using Complex = std::complex<double>;
  Eigen::VectorXd total = Eigen::VectorXd::Zero(n);
  for (int h : harmonics) {
    Eigen::VectorXcd force = Eigen::VectorXcd::Zero(n);
    for (const auto& term : terms) {
      if (term.harmonic == h) force(term.dof) += Complex(term.cos, -term.sin);
    }
    const double w = h * omega;
    Eigen::SparseMatrix<Complex> z = model.stiffness.cast<Complex>() -
                                     (w * w) * model.mass.cast<Complex>() +
                                     Complex(0.0, w) * model.damping.cast<Complex>();
    Eigen::VectorXcd response;
    if (n <= kDenseResponseLimit) {
      response = Eigen::MatrixXcd(z).fullPivLu().solve(force);
    } else {
      z.makeCompressed();
      Eigen::SparseLU<Eigen::SparseMatrix<Complex>> lu(z);
      if (lu.info() != Eigen::Success) return 0.0;
      response = lu.solve(force);
    }
    if (!response.allFinite()) return 0.0;
    total += response.cwiseAbs();
  }
  return n > 0 ? total.maxCoeff() : 0.0;
}

// Entries of a matrix as triplets shifted by (rows, columns).
Triplets Shifted(const Eigen::SparseMatrix<double>& matrix, int rows, int columns) {
  Triplets entries;
  for (int k = 0; k < matrix.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, k); it; ++it) {
      entries.emplace_back(rows + it.row(), columns + it.col(), it.value());
    }
  }
  return entries;
}

// Typical magnitudes of the unknowns: atol = rtol × absolute_scale_factor × scale.
struct Scales {
  double x = 1.0;       // m: displacements
  double v = 1.0;       // m/s: velocities
  double own = 1.0;     // N: laws' own unknowns (forces)
  double energy = 1.0;  // J·s: ∫E dt over a period
  double work = 1.0;    // J: works over a period
};

// One IDA integration of a TransientModel under an Excitation: residual, Jacobian, roots,
// mode iteration and re-initialisation, quadratures.
class IdaRun {
 public:
  IdaRun(TransientModel& model, const TransientOptions& options, const Excitation& excitation,
         double period)
      : model_(model),
        options_(options),
        excitation_(excitation),
        period_(period),
        deadline_(Clock::now() +
                  std::chrono::duration_cast<Clock::duration>(
                      std::chrono::duration<double>(std::min(options.max_seconds, 1e9)))) {
    n_ = model.num_dofs();
    int offset = 2 * n_;
    for (const auto& law : model.laws) {
      TimeLawLayout layout;
      layout.num_dofs = n_;
      layout.own_offset = offset;
      layouts_.push_back(layout);
      offset += law->NumOwn();
      root_offsets_.push_back(num_roots_);
      num_roots_ += law->NumRoots();
    }
    q_ = offset;
    size_ = q_ + kNumQuadratures;
    stiffness_ = Shifted(model.model.stiffness, n_, 0);
    damping_ = Shifted(model.model.damping, n_, n_);
    mass_ = Shifted(model.model.mass, n_, n_);
    k_sym_ = 0.5 * (model.model.stiffness +
                    Eigen::SparseMatrix<double>(model.model.stiffness.transpose()));
    m_sym_ = 0.5 * (model.model.mass + Eigen::SparseMatrix<double>(model.model.mass.transpose()));
    c_sym_ = model.model.damping + Eigen::SparseMatrix<double>(model.model.damping.transpose());
    differential_.assign(size_, true);
    for (int i = 0; i < n_; ++i) differential_[n_ + i] = !model.massless[i];
    for (size_t l = 0; l < model.laws.size(); ++l) {
      for (int k = 0; k < model.laws[l]->NumOwn(); ++k) {
        differential_[layouts_[l].Own(k)] = model.laws[l]->OwnIsDifferential(k);
      }
    }
    FindReducedRows();
    force_.resize(n_);
    f_nl_.resize(n_);
    scratch_.resize(n_);
    rootsfound_.assign(num_roots_, 0);
    last_fired_.assign(num_roots_, false);
    using LS = TransientOptions::LinearSolver;
    dense_ = options.linear_solver == LS::kDense ||
             (options.linear_solver == LS::kAuto && size_ <= TransientOptions::kDenseLimit);
  }

  const std::string& message() const { return message_; }
  double t() const { return t_; }
  long events() const { return events_; }
  long steps() const {
    long current = 0;
    if (sun_.ida != nullptr) IDAGetNumSteps(sun_.ida, &current);
    return steps_done_ + current;
  }
  Eigen::Map<const Eigen::VectorXd> X() const { return {Y(), n_}; }
  Eigen::Map<const Eigen::VectorXd> V() const { return {Y() + n_, n_}; }
  Eigen::Map<const Eigen::VectorXd> Q() const { return {Y() + q_, kNumQuadratures}; }
  double Energy() const {
    return 0.5 * V().dot(model_.model.mass * V()) + 0.5 * X().dot(model_.model.stiffness * X());
  }
  const std::vector<LawPhaseLog>& phase_logs() const { return phase_logs_; }

  // The laws' signals at the current state.
  std::vector<std::vector<std::pair<std::string, double>>> Signals() const {
    std::vector<std::vector<std::pair<std::string, double>>> signals;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      signals.push_back(model_.laws[l]->Signals(layouts_[l], View(l, t_, Y(), YP())));
    }
    return signals;
  }

  // Sets up IDA at t = 0 from (x0, v0) after choosing modes and consistent values.
  bool Start(const Eigen::VectorXd& x0, const Eigen::VectorXd& v0, const Scales& scales) {
    if (SUNContext_Create(nullptr, &sun_.context) != 0) return Fail("SUNContext_Create failed");
    sun_.y = N_VNew_Serial(size_, sun_.context);
    sun_.yp = N_VNew_Serial(size_, sun_.context);
    sun_.id = N_VNew_Serial(size_, sun_.context);
    sun_.atol = N_VNew_Serial(size_, sun_.context);
    if (!sun_.y || !sun_.yp || !sun_.id || !sun_.atol) return Fail("N_VNew_Serial failed");
    N_VConst(0.0, sun_.y);
    N_VConst(0.0, sun_.yp);
    Eigen::Map<Eigen::VectorXd> y(N_VGetArrayPointer(sun_.y), size_);
    y.head(n_) = x0;
    y.segment(n_, n_) = v0;
    Eigen::Map<Eigen::VectorXd> id(N_VGetArrayPointer(sun_.id), size_);
    Eigen::Map<Eigen::VectorXd> atol(N_VGetArrayPointer(sun_.atol), size_);
    const double factor = options_.relative_tolerance * options_.absolute_scale_factor;
    auto scale = [&](int j) {
      if (j < n_) return scales.x;
      if (j < 2 * n_) return scales.v;
      if (j < q_) return scales.own;
      return j == q_ ? scales.energy : scales.work;
    };
    for (int j = 0; j < size_; ++j) {
      id(j) = differential_[j] ? 1.0 : 0.0;
      atol(j) = factor * scale(j);
    }
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      model_.laws[l]->InitMode(layouts_[l], View(l, 0.0, Y(), YP()));
    }
    // The differential own unknowns start at zero: take them from the undifferentiated rows
    // (a sticking force from the start's displacements); a sliding one is snapped later.
    if (!reduced_.empty() && !SolveOriginalRows(0.0, reduced_own_columns_)) return false;
    for (const auto& law : model_.laws) {
      LawPhaseLog log;
      log.type = law->type();
      log.phase_name = law->PhaseName();
      phase_logs_.push_back(log);
    }
    if (!SettleModes(0.0)) return false;

    sun_.ida = IDACreate(sun_.context);
    if (sun_.ida == nullptr) return Fail("IDACreate failed");
    int flag = IDASetErrHandlerFn(sun_.ida, &IdaRun::ErrorHandler, this);
    if (flag == IDA_SUCCESS) flag = IDAInit(sun_.ida, &IdaRun::ResidualFn, 0.0, sun_.y, sun_.yp);
    if (flag == IDA_SUCCESS) flag = IDASetUserData(sun_.ida, this);
    if (flag == IDA_SUCCESS) {
      flag = IDASVtolerances(sun_.ida, options_.relative_tolerance, sun_.atol);
    }
    if (flag != IDA_SUCCESS) return Fail("IDA set-up failed: " + FlagName(flag));
    if (dense_) {
      sun_.matrix = SUNDenseMatrix(size_, size_, sun_.context);
      if (sun_.matrix) sun_.solver = SUNLinSol_Dense(sun_.y, sun_.matrix, sun_.context);
    } else {
      Triplets entries;
      Assemble(0.0, Y(), YP(), 1.0, &entries);
      const long capacity = static_cast<long>(entries.size()) + size_;
      sun_.matrix = SUNSparseMatrix(size_, size_, capacity, CSC_MAT, sun_.context);
      if (sun_.matrix) sun_.solver = SUNLinSol_KLU(sun_.y, sun_.matrix, sun_.context);
    }
    if (!sun_.matrix || !sun_.solver) return Fail("cannot create the linear solver");
    flag = IDASetLinearSolver(sun_.ida, sun_.solver, sun_.matrix);
    if (flag == IDA_SUCCESS) flag = IDASetJacFn(sun_.ida, &IdaRun::JacobianFn);
    if (flag == IDA_SUCCESS) flag = IDASetId(sun_.ida, sun_.id);
    // The algebraic unknowns stay in the error test (IDA's advice for index 1): suppressed, a
    // sticking force interpolated over the long steps of a stick phase was off by 1% and fired
    // its release root early.
    if (flag == IDA_SUCCESS) flag = IDASetSuppressAlg(sun_.ida, SUNFALSE);
    if (flag == IDA_SUCCESS) flag = IDASetMaxStep(sun_.ida, options_.max_step_fraction * period_);
    if (flag == IDA_SUCCESS) flag = IDASetMaxNumSteps(sun_.ida, kMaxStepsPerCall);
    if (flag == IDA_SUCCESS && num_roots_ > 0) {
      flag = IDARootInit(sun_.ida, num_roots_, &IdaRun::RootFn);
    }
    if (flag != IDA_SUCCESS) return Fail("IDA set-up failed: " + FlagName(flag));
    return true;
  }

  // Starts a period (or cycle) at the current time, ending at `stop`.
  bool BeginSegment(double stop) {
    stop_ = stop;
    roots_in_period_ = 0;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      phase_logs_[l].in_phase_at_start = model_.laws[l]->InPhase();
      phase_logs_[l].changes.clear();
    }
    const int flag = IDASetStopTime(sun_.ida, stop_);
    return flag == IDA_SUCCESS || Fail("IDASetStopTime: " + FlagName(flag));
  }

  // Zeroes the quadratures (a restart of IDA at the current time).
  bool ResetQuadratures() {
    last_fired_.assign(num_roots_, false);
    Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(sun_.y) + q_, kNumQuadratures).setZero();
    // A differentiated row drifts from its original between restarts: project here too.
    if (!reduced_.empty() && !MakeConsistent(t_)) return false;
    return Reinitialise();
  }

  // Integrates to tout ≤ the segment's stop, stopping at every root on the way.
  bool AdvanceTo(double tout) {
    while (tout - t_ > kRepeatedRootWindow * period_) {
      double t_return = t_;
      last_error_.clear();
      const int flag = IDASolve(sun_.ida, tout, &t_return, sun_.y, sun_.yp, IDA_NORMAL);
      t_ = t_return;
      if (flag == IDA_SUCCESS || flag == IDA_TSTOP_RETURN) return true;
      if (Clock::now() > deadline_) {
        std::ostringstream out;
        out << "wall-clock limit of " << options_.max_seconds << " s reached at t = " << t_;
        return Fail(out.str());
      }
      if (flag == IDA_ROOT_RETURN) {
        if (!HandleRoot()) return false;
        continue;
      }
      if (flag == IDA_TOO_MUCH_WORK) continue;  // only a pause to look at the clock
      std::ostringstream out;
      out << "IDA failed at t = " << t_ << ": " << FlagName(flag);
      if (!last_error_.empty()) out << " (" << last_error_ << ")";
      return Fail(out.str());
    }
    return true;
  }

 private:
  const double* Y() const { return N_VGetArrayPointer(sun_.y); }
  const double* YP() const { return N_VGetArrayPointer(sun_.yp); }

  bool Fail(const std::string& message) {
    message_ = message;
    return false;
  }

  DaeView View(size_t l, double t, const double* y, const double* yp) const {
    DaeView s;
    s.t = t;
    s.phase = excitation_.Phase(t);
    s.num_dofs = n_;
    const int own = layouts_[l].own_offset;
    const int num_own = model_.laws[l]->NumOwn();
    new (&s.x) Eigen::Map<const Eigen::VectorXd>(y, n_);
    new (&s.v) Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
    new (&s.xdot) Eigen::Map<const Eigen::VectorXd>(yp, n_);
    new (&s.a) Eigen::Map<const Eigen::VectorXd>(yp + n_, n_);
    new (&s.own) Eigen::Map<const Eigen::VectorXd>(y + own, num_own);
    new (&s.own_dot) Eigen::Map<const Eigen::VectorXd>(yp + own, num_own);
    return s;
  }

  // force_ = f(t) and f_nl_ = Σ f_nl at (t, y, ẏ).
  void Forces(double t, const double* y, const double* yp) const {
    force_.setZero();
    excitation_.AddForce(t, force_);
    f_nl_.setZero();
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      scratch_.setZero();
      model_.laws[l]->Force(layouts_[l], View(l, t, y, yp), scratch_);
      f_nl_ += scratch_;
    }
  }

  // Which momentum rows the integrator differentiates: those of massless DOFs with a zero
  // damping row on which a law's differential own unknown acts (∂F/∂own ≠ 0). Without such an
  // unknown an undamped massless row is left alone: K x = f of a linear row is then refused as
  // inconsistent, as before (its index-2 velocity is not this reduction's business).
  void FindReducedRows() {
    std::vector<bool> damped(n_, false);
    const Eigen::SparseMatrix<double>& damping = model_.model.damping;
    for (int k = 0; k < damping.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(damping, k); it; ++it) {
        if (it.value() != 0.0) damped[it.row()] = true;
      }
    }
    // The pattern of the laws' ∂F/∂y at a zero state (the momentum-row entries of own
    // unknowns do not depend on the state).
    const std::vector<double> zeros(size_, 0.0);
    Triplets entries;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      model_.laws[l]->Jacobian(layouts_[l], View(l, 0.0, zeros.data(), zeros.data()), 0.0,
                               &entries);
    }
    reduced_index_.assign(n_, -1);
    for (const auto& e : entries) {
      const int dof = e.row() - n_;
      if (dof < 0 || dof >= n_ || e.value() == 0.0 || e.col() < 2 * n_ || e.col() >= q_ ||
          !differential_[e.col()] || !model_.massless[dof] || damped[dof]) {
        continue;
      }
      if (reduced_index_[dof] < 0) {
        reduced_index_[dof] = static_cast<int>(reduced_.size());
        reduced_.push_back(dof);
        reduced_own_columns_.push_back(-1);
      }
      // One own unknown per row to start from (distinct), for SolveOriginalRows at t = 0.
      int& column = reduced_own_columns_[reduced_index_[dof]];
      if (column < 0 && std::find(reduced_own_columns_.begin(), reduced_own_columns_.end(),
                                  e.col()) == reduced_own_columns_.end()) {
        column = e.col();
      }
    }
    for (size_t i = 0; i < reduced_.size(); ++i) {
      reduced_x_columns_.push_back(reduced_[i]);
      // Rows sharing one own unknown (relative friction between two such DOFs): the others
      // start from their own x instead.
      if (reduced_own_columns_[i] < 0) reduced_own_columns_[i] = reduced_[i];
    }
    reduced_rows_.assign(size_, false);
    for (int dof : reduced_) reduced_rows_[n_ + dof] = true;
    j0_.resize(static_cast<Eigen::Index>(reduced_.size()), size_);
    rate_.resize(n_);
  }

  // j0_ = ∂F/∂y of the reduced DOFs' original momentum rows at (t, y): their K rows and the
  // laws' momentum-row entries (the mass and damping rows are zero).
  void OriginalRowJacobian(double t, const double* y, const double* yp) const {
    j0_.setZero();
    for (const auto& e : stiffness_) {
      const int i = reduced_index_[e.row() - n_];
      if (i >= 0) j0_(i, e.col()) += e.value();
    }
    law_scratch_.clear();
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      model_.laws[l]->Jacobian(layouts_[l], View(l, t, y, yp), 0.0, &law_scratch_);
    }
    for (const auto& e : law_scratch_) {
      if (e.row() < n_ || e.row() >= 2 * n_) continue;
      const int i = reduced_index_[e.row() - n_];
      if (i >= 0) j0_(i, e.col()) += e.value();
    }
  }

  // F with every momentum row in its original form; Residual then differentiates the reduced
  // ones: Σ_j J0(d, j) ẏ_j − ḟ_d(t), exactly d/dt of the original row.
  void Residual(double t, const double* y, const double* yp, double* r) const {
    OriginalResidual(t, y, yp, r);
    if (reduced_.empty()) return;
    OriginalRowJacobian(t, y, yp);
    rate_.setZero();
    excitation_.AddForceRate(t, rate_);
    const Eigen::Map<const Eigen::VectorXd> ydot(yp, size_);
    for (size_t i = 0; i < reduced_.size(); ++i) {
      const int dof = reduced_[i];
      r[n_ + dof] = j0_.row(static_cast<Eigen::Index>(i)).dot(ydot) - rate_(dof);
    }
  }

  void OriginalResidual(double t, const double* y, const double* yp, double* r) const {
    Eigen::Map<const Eigen::VectorXd> x(y, n_), v(y + n_, n_), xdot(yp, n_), a(yp + n_, n_);
    Eigen::Map<Eigen::VectorXd> res(r, size_);
    res.setZero();
    Forces(t, y, yp);
    res.head(n_) = xdot - v;
    res.segment(n_, n_) =
        model_.model.mass * a + model_.model.damping * v + model_.model.stiffness * x - force_;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      model_.laws[l]->Residual(layouts_[l], View(l, t, y, yp), res);
    }
    const double energy =
        0.5 * v.dot(model_.model.mass * v) + 0.5 * x.dot(model_.model.stiffness * x);
    res(q_) = yp[q_] - energy;
    res(q_ + 1) = yp[q_ + 1] - force_.dot(v);
    res(q_ + 2) = yp[q_ + 2] - v.dot(model_.model.damping * v);
    res(q_ + 3) = yp[q_ + 3] - f_nl_.dot(v);
  }

  // Triplets of ∂F/∂y + cj ∂F/∂ẏ; the quadrature rows are dense (explicit zeros kept, so the
  // sparsity pattern depends on the modes only). A differentiated row's is cj·J0 (its
  // ∂J0/∂y·ẏ part is left out: zero for laws linear in y within a mode, as friction, penalty
  // contact and linear springs are; only the Newton rate suffers otherwise).
  void Assemble(double t, const double* y, const double* yp, double cj, Triplets* out) const {
    out->clear();
    for (int i = 0; i < n_; ++i) {
      out->emplace_back(i, i, cj);
      out->emplace_back(i, n_ + i, -1.0);
    }
    out->insert(out->end(), stiffness_.begin(), stiffness_.end());
    out->insert(out->end(), damping_.begin(), damping_.end());
    for (const auto& e : mass_) out->emplace_back(e.row(), e.col(), cj * e.value());
    const size_t law_begin = out->size();
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      model_.laws[l]->Jacobian(layouts_[l], View(l, t, y, yp), cj, out);
    }
    const size_t law_end = out->size();
    Eigen::Map<const Eigen::VectorXd> x(y, n_), v(y + n_, n_);
    Forces(t, y, yp);
    const Eigen::VectorXd energy_x = k_sym_ * x;
    const Eigen::VectorXd energy_v = m_sym_ * v;
    const Eigen::VectorXd damping_v = c_sym_ * v;
    for (int k = 0; k < kNumQuadratures; ++k) out->emplace_back(q_ + k, q_ + k, cj);
    for (int j = 0; j < n_; ++j) {
      out->emplace_back(q_, j, -energy_x(j));
      out->emplace_back(q_, n_ + j, -energy_v(j));
      out->emplace_back(q_ + 1, n_ + j, -force_(j));
      out->emplace_back(q_ + 2, n_ + j, -damping_v(j));
      out->emplace_back(q_ + 3, n_ + j, -f_nl_(j));
    }
    // ∂(f_nlᵀv)/∂y through f_nl: the laws' momentum-row entries weighted by v.
    for (size_t k = law_begin; k < law_end; ++k) {
      const Eigen::Triplet<double> e = (*out)[k];
      if (e.row() >= n_ && e.row() < 2 * n_) {
        out->emplace_back(q_ + 3, e.col(), -v(e.row() - n_) * e.value());
      }
    }
    // The laws' momentum-row entries do not depend on cj (they are forces), so the entries of
    // a reduced row so far are J0's: scale them.
    if (reduced_.empty()) return;
    for (size_t k = 0; k < law_end; ++k) {
      const Eigen::Triplet<double> e = (*out)[k];
      if (reduced_rows_[e.row()])
        (*out)[k] = Eigen::Triplet<double>(e.row(), e.col(), cj * e.value());
    }
  }

  // Newton on the reduced DOFs' original (undifferentiated) momentum rows for the unknowns
  // y[columns] (one per reduced DOF), the rest held.
  bool SolveOriginalRows(double t, const std::vector<int>& columns) {
    double* y = N_VGetArrayPointer(sun_.y);
    const double* yp = YP();
    const int m = static_cast<int>(reduced_.size());
    Eigen::VectorXd residual(size_), g(m);
    Eigen::MatrixXd slope(m, m);
    for (int iteration = 0; iteration < kProjectionIterations; ++iteration) {
      OriginalResidual(t, y, yp, residual.data());
      OriginalRowJacobian(t, y, yp);
      for (int i = 0; i < m; ++i) {
        g(i) = residual(n_ + reduced_[i]);
        for (int c = 0; c < m; ++c) slope(i, c) = columns[c] >= 0 ? j0_(i, columns[c]) : 0.0;
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(slope);
      if (!lu.isInvertible()) {
        std::ostringstream out;
        out << "no consistent state at t = " << t
            << ": the massless DOFs' rows cannot be solved for their unknowns (singular)";
        return Fail(out.str());
      }
      const Eigen::VectorXd step = lu.solve(-g);
      if (!step.allFinite()) return Fail("no consistent state: non-finite projection");
      double largest = 0.0;
      for (int c = 0; c < m; ++c) {
        y[columns[c]] += step(c);
        largest = std::max(largest, std::abs(step(c)) / (1.0 + std::abs(y[columns[c]])));
      }
      if (largest <= 1e-15) break;
    }
    return true;
  }

  // Back onto the undifferentiated rows (their drift under the differentiated ones): the laws
  // snap the differential own unknowns their modes fix, then Newton on x of the reduced DOFs.
  bool ProjectReduced(double t) {
    double* y = N_VGetArrayPointer(sun_.y);
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      const int num_own = model_.laws[l]->NumOwn();
      if (num_own == 0) continue;
      Eigen::Map<Eigen::VectorXd> own(y + layouts_[l].own_offset, num_own);
      model_.laws[l]->SnapOwn(layouts_[l], View(l, t, Y(), YP()), own);
    }
    return SolveOriginalRows(t, reduced_x_columns_);
  }

  // Solves F = 0 for ẏ of the differential unknowns and for the algebraic unknowns, x and the
  // massed v held (F is affine in those, so one Newton step solves it; a second checks).
  bool MakeConsistent(double t) {
    if (!reduced_.empty() && !ProjectReduced(t)) return false;
    double* y = N_VGetArrayPointer(sun_.y);
    double* yp = N_VGetArrayPointer(sun_.yp);
    Eigen::VectorXd residual(size_);
    Triplets slope, value;
    for (int iteration = 0; iteration < kConsistentIterations; ++iteration) {
      Residual(t, y, yp, residual.data());
      Assemble(t, y, yp, 0.0, &value);
      Assemble(t, y, yp, 1.0, &slope);
      Triplets entries;
      for (const auto& e : value) {
        if (!differential_[e.col()]) entries.push_back(e);
      }
      for (const auto& e : slope) {
        if (differential_[e.col()]) entries.push_back(e);
      }
      for (const auto& e : value) {  // slope − value = ∂F/∂ẏ
        if (differential_[e.col()]) entries.emplace_back(e.row(), e.col(), -e.value());
      }
      Eigen::SparseMatrix<double> matrix(size_, size_);
      matrix.setFromTriplets(entries.begin(), entries.end());
      matrix.makeCompressed();
      Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
      lu.compute(matrix);
      if (lu.info() != Eigen::Success) {
        std::ostringstream out;
        out << "no consistent state at t = " << t << ": singular matrix (" << lu.lastErrorMessage()
            << ")";
        return Fail(out.str());
      }
      const Eigen::VectorXd step = lu.solve(-residual);
      if (!step.allFinite()) return Fail("no consistent state: non-finite solution");
      double largest = 0.0;
      for (int j = 0; j < size_; ++j) {
        double& unknown = differential_[j] ? yp[j] : y[j];
        unknown += step(j);
        largest = std::max(largest, std::abs(step(j)) / (1.0 + std::abs(unknown)));
      }
      if (largest <= 1e-13) break;
    }
    return true;
  }

  // Consistent values in the current modes, until every law accepts its mode.
  bool SettleModes(double t) {
    for (int round = 0; round < kMaxModeRounds; ++round) {
      if (!MakeConsistent(t)) return false;
      bool admissible = true;
      for (size_t l = 0; l < model_.laws.size(); ++l) {
        if (!model_.laws[l]->Admissible(layouts_[l], View(l, t, Y(), YP()))) admissible = false;
      }
      if (admissible) return true;
    }
    std::ostringstream out;
    out << "mode iteration did not settle in " << kMaxModeRounds << " rounds at t = " << t;
    return Fail(out.str());
  }

  bool Reinitialise() {
    steps_done_ = steps();
    int flag = IDAReInit(sun_.ida, t_, sun_.y, sun_.yp);
    if (flag == IDA_SUCCESS && stop_ > t_) flag = IDASetStopTime(sun_.ida, stop_);
    if (flag != IDA_SUCCESS) return Fail("IDAReInit: " + FlagName(flag));
    t_reinit_ = t_;
    return true;
  }

  bool HandleRoot() {
    IDAGetRootInfo(sun_.ida, rootsfound_.data());
    const bool just_restarted = t_ - t_reinit_ <= kRepeatedRootWindow * period_;
    std::vector<int> modes;
    std::vector<bool> phases;
    for (const auto& law : model_.laws) {
      modes.push_back(law->ModeIndex());
      phases.push_back(law->InPhase());
    }
    std::vector<bool> fired(num_roots_, false);
    bool handled = false;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      for (int k = 0; k < model_.laws[l]->NumRoots(); ++k) {
        const int root = root_offsets_[l] + k;
        if (rootsfound_[root] == 0) continue;
        fired[root] = true;
        if (just_restarted && last_fired_[root]) continue;
        model_.laws[l]->OnRoot(layouts_[l], View(l, t_, Y(), YP()), k);
        handled = true;
      }
    }
    if (!handled) return true;  // the root just handled, reported again: IDA continues
    if (!SettleModes(t_)) return false;
    long switches = 0;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      if (model_.laws[l]->ModeIndex() != modes[l]) ++switches;
      if (model_.laws[l]->InPhase() != phases[l]) {
        phase_logs_[l].changes.emplace_back(t_, model_.laws[l]->InPhase());
      }
    }
    events_ += switches;
    // Handled roots, switching or not, so that a root rejected again and again also stops.
    if (++roots_in_period_ > kMaxEventsPerPeriod) {
      std::ostringstream out;
      out << "chattering: more than " << kMaxEventsPerPeriod << " events in one period"
          << " at t = " << t_;
      return Fail(out.str());
    }
    // Restart even when the mode iteration returned to the old modes: IDA then re-evaluates
    // the root functions from consistent values instead of its interpolated ones.
    last_fired_ = fired;
    return Reinitialise();
  }

  bool FillSparse(SUNMatrix matrix) {
    Eigen::SparseMatrix<double> jacobian(size_, size_);
    jacobian.setFromTriplets(triplets_.begin(), triplets_.end());
    jacobian.makeCompressed();
    const long nnz = jacobian.nonZeros();
    const int* outer = jacobian.outerIndexPtr();
    const int* inner = jacobian.innerIndexPtr();
    const bool same = pattern_outer_.size() == static_cast<size_t>(size_ + 1) &&
                      std::equal(outer, outer + size_ + 1, pattern_outer_.begin()) &&
                      pattern_inner_.size() == static_cast<size_t>(nnz) &&
                      std::equal(inner, inner + nnz, pattern_inner_.begin());
    if (nnz > SUNSparseMatrix_NNZ(matrix) && SUNSparseMatrix_Reallocate(matrix, nnz) != 0) {
      return false;
    }
    // IDA zeroes the matrix, pattern included, before every call: write the pattern each time.
    sunindextype* pointers = SUNSparseMatrix_IndexPointers(matrix);
    sunindextype* rows = SUNSparseMatrix_IndexValues(matrix);
    for (int j = 0; j <= size_; ++j) pointers[j] = outer[j];
    for (long k = 0; k < nnz; ++k) rows[k] = inner[k];
    if (!same) {
      pattern_outer_.assign(outer, outer + size_ + 1);
      pattern_inner_.assign(inner, inner + nnz);
      // A new pattern needs a new symbolic factorisation.
      if (SUNLinSol_KLUReInit(sun_.solver, matrix, nnz, SUNKLU_REINIT_PARTIAL) != 0) return false;
    }
    std::copy(jacobian.valuePtr(), jacobian.valuePtr() + nnz, SUNSparseMatrix_Data(matrix));
    return true;
  }

  static int ResidualFn(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void* data) {
    static_cast<const IdaRun*>(data)->Residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                                               N_VGetArrayPointer(r));
    return 0;
  }

  static int JacobianFn(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector /*r*/,
                        SUNMatrix matrix, void* data, N_Vector, N_Vector, N_Vector) {
    auto* run = static_cast<IdaRun*>(data);
    run->Assemble(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), cj, &run->triplets_);
    if (!run->dense_) return run->FillSparse(matrix) ? 0 : -1;
    SUNMatZero(matrix);
    for (const auto& e : run->triplets_) SM_ELEMENT_D(matrix, e.row(), e.col()) += e.value();
    return 0;
  }

  static int RootFn(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype* g, void* data) {
    const auto* run = static_cast<const IdaRun*>(data);
    for (size_t l = 0; l < run->model_.laws.size(); ++l) {
      run->model_.laws[l]->Roots(run->layouts_[l],
                                 run->View(l, t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp)),
                                 g + run->root_offsets_[l]);
    }
    return 0;
  }

  static void ErrorHandler(int /*code*/, const char* module, const char* function, char* message,
                           void* data) {
    static_cast<IdaRun*>(data)->last_error_ =
        std::string(module) + "::" + function + ": " + message;
  }

  TransientModel& model_;
  const TransientOptions& options_;
  const Excitation& excitation_;
  double period_;
  Clock::time_point deadline_;
  int n_ = 0;
  int q_ = 0;
  int size_ = 0;
  int num_roots_ = 0;
  bool dense_ = true;
  std::vector<TimeLawLayout> layouts_;
  std::vector<int> root_offsets_;
  std::vector<bool> differential_;
  // Index reduction: the DOFs whose momentum rows are differentiated, each DOF's index among
  // them (−1: none), an own unknown and the x column of each, and a flag per row of F.
  std::vector<int> reduced_, reduced_index_, reduced_own_columns_, reduced_x_columns_;
  std::vector<bool> reduced_rows_;
  mutable Eigen::MatrixXd j0_;
  mutable Eigen::VectorXd rate_;
  mutable Triplets law_scratch_;
  Triplets stiffness_, damping_, mass_;
  Eigen::SparseMatrix<double> k_sym_, m_sym_, c_sym_;
  mutable Eigen::VectorXd force_, f_nl_, scratch_;
  Triplets triplets_;
  std::vector<int> pattern_outer_, pattern_inner_;
  std::vector<int> rootsfound_;
  std::vector<bool> last_fired_;
  std::vector<LawPhaseLog> phase_logs_;
  Sundials sun_;
  double t_ = 0.0;
  double t_reinit_ = -1.0;
  double stop_ = 0.0;
  long steps_done_ = 0;
  long events_ = 0;
  long roots_in_period_ = 0;
  std::string message_;
  std::string last_error_;
};

// Scales at frequencies up to `omega`: x from the linear response (or the start, if larger), v
// = ω x, own unknowns (forces) the largest forcing amplitude (else K x), ∫E dt a period of the
// energy at that amplitude, works a period of F ω x. The quadratures stay in the error test
// with these atol, and are zeroed every kQuadratureResetPeriods so rtol·|q| stays of the order
// of one period's increment.
Scales MakeScales(const TransientModel& model, double omega, double period, double x_amplitude,
                  const InitialState& start) {
  Scales s;
  double x = x_amplitude;
  if (start.x.size() > 0) x = std::max(x, start.x.cwiseAbs().maxCoeff());
  if (start.v.size() > 0) x = std::max(x, start.v.cwiseAbs().maxCoeff() / omega);
  if (!(x > 0.0) || !std::isfinite(x)) x = 1.0;
  double force = 0.0;
  for (const auto& term : model.forcing) force = std::max(force, std::hypot(term.cos, term.sin));
  const Eigen::VectorXd k_diagonal = Eigen::VectorXd(model.model.stiffness.diagonal()).cwiseAbs();
  const Eigen::VectorXd m_diagonal = Eigen::VectorXd(model.model.mass.diagonal()).cwiseAbs();
  const double k_max = k_diagonal.size() > 0 ? k_diagonal.maxCoeff() : 0.0;
  const double m_max = m_diagonal.size() > 0 ? m_diagonal.maxCoeff() : 0.0;
  // Own unknowns are forces: the forcing amplitude, else the elastic force of the motion.
  double own = force > 0.0 ? force : k_max * x;
  if (!(own > 0.0)) own = 1.0;
  s.x = x;
  s.v = omega * x;
  s.own = own;
  const double energy = 0.5 * (k_max + m_max * omega * omega) * x * x;
  s.energy = energy > 0.0 ? energy * period : 1.0;
  const double work = std::max(own * omega * x, omega * energy) * period;
  s.work = work > 0.0 ? work : 1.0;
  return s;
}

void CheckStart(const TransientModel& model, const InitialState& start) {
  const int n = model.num_dofs();
  if (start.x.size() != 0 && start.x.size() != n) {
    throw InputError("validation.initial_state.x: needs one value per DOF");
  }
  if (start.v.size() != 0 && start.v.size() != n) {
    throw InputError("validation.initial_state.v: needs one value per DOF");
  }
}

}  // namespace

IdaIntegrator::IdaIntegrator(TransientModel& model, TransientOptions options)
    : model_(model), options_(options) {
  options_.Validate();
  if (!model_.rigid_contacts.empty()) {
    throw InputError(
        "nonlinearities: IDA cannot integrate a rigid contact (no force law); use "
        "the central-difference scheme");
  }
  const int n = model_.num_dofs();
  if (model_.massless.empty()) {
    model_.massless.assign(n, true);
    const Eigen::SparseMatrix<double>& mass = model_.model.mass;
    for (int k = 0; k < mass.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(mass, k); it; ++it) {
        if (it.value() != 0.0) model_.massless[it.row()] = model_.massless[it.col()] = false;
      }
    }
  }
  assert(static_cast<int>(model_.massless.size()) == n);
}

IdaIntegrator::~IdaIntegrator() = default;

TransientResult IdaIntegrator::RunToSteadyState(double omega, const InitialState& start) {
  if (!(omega > 0.0) || !std::isfinite(omega)) {
    throw InputError("validation.omega: must be finite and > 0");
  }
  CheckStart(model_, start);
  const auto clock_start = Clock::now();
  const int n = model_.num_dofs();
  const double period = kTwoPi / omega;
  const int samples = options_.samples_per_period;
  TransientResult result;
  result.method = "ida";
  result.omega = omega;
  const Excitation excitation = Excitation::Harmonic(model_.forcing, omega);
  const Eigen::VectorXd x0 = start.x.size() > 0 ? start.x : Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd v0 = start.v.size() > 0 ? start.v : Eigen::VectorXd::Zero(n);
  IdaRun run(model_, options_, excitation, period);
  const Scales scales = MakeScales(model_, omega, period,
                                   LinearAmplitude(model_.model, model_.forcing, omega), start);
  auto finish = [&](TransientStatus status, const std::string& message) {
    result.status = status;
    result.message = message;
    result.steps = run.steps();
    result.events = run.events();
    result.t_end = run.t();
    result.wall_seconds = Seconds(clock_start);
    return result;
  };
  if (!run.Start(x0, v0, scales)) return finish(TransientStatus::kFailed, run.message());

  auto state = [&]() {
    Eigen::VectorXd z(2 * n);
    z << run.X(), run.V() / omega;
    return z;
  };
  std::deque<Eigen::VectorXd> boundaries{state()};
  int consecutive = 0;
  PeriodRecord record;
  for (int p = 1; p <= options_.max_periods; ++p) {
    const double t0 = (p - 1) * period;
    if (p > 1 && (p - 1) % kQuadratureResetPeriods == 0 && !run.ResetQuadratures()) {
      return finish(TransientStatus::kFailed, run.message());
    }
    if (!run.BeginSegment(p * period)) return finish(TransientStatus::kFailed, run.message());
    const Eigen::VectorXd q0 = run.Q();
    const double energy0 = run.Energy();
    record.t0 = t0;
    record.period = period;
    record.t.resize(samples);
    record.x.resize(n, samples);
    record.v.resize(n, samples);
    record.law_signals.assign(model_.laws.size(), {});
    for (int i = 0; i < samples; ++i) {
      record.t(i) = t0 + i * period / samples;
      if (i > 0 && !run.AdvanceTo(record.t(i))) {
        return finish(TransientStatus::kFailed, run.message());
      }
      record.x.col(i) = run.X();
      record.v.col(i) = run.V();
      const auto signals = run.Signals();
      for (size_t l = 0; l < signals.size(); ++l) {
        auto& out = record.law_signals[l];
        if (out.empty()) {
          for (const auto& [name, value] : signals[l]) {
            out.emplace_back(name, Eigen::VectorXd::Zero(samples));
          }
        }
        for (size_t k = 0; k < signals[l].size() && k < out.size(); ++k) {
          out[k].second(i) = signals[l][k].second;
        }
      }
    }
    if (!run.AdvanceTo(p * period)) return finish(TransientStatus::kFailed, run.message());
    const Eigen::VectorXd dq = run.Q() - q0;
    record.mean_energy = dq(0) / period;
    record.work_input = dq(1);
    record.work_damping = dq(2);
    record.work_laws = dq(3);
    record.energy_change = run.Energy() - energy0;
    record.phases = run.phase_logs();
    std::swap(result.last_period, record);
    result.periods = p;

    boundaries.push_back(state());
    if (static_cast<int>(boundaries.size()) > options_.max_period_multiple + 1) {
      boundaries.pop_front();
    }
    const Eigen::VectorXd& z = boundaries.back();
    const double size = z.cwiseAbs().maxCoeff();
    const double change = (z - boundaries[boundaries.size() - 2]).cwiseAbs().maxCoeff();
    const double difference = size > 0.0 ? change / size : change;
    result.period_differences.push_back(difference);
    consecutive = difference <= options_.steady_tolerance ? consecutive + 1 : 0;
    if (p >= options_.min_periods && consecutive >= options_.steady_periods) {
      return finish(TransientStatus::kPeriodic, "");
    }
    if (Seconds(clock_start) > options_.max_seconds) {
      std::ostringstream out;
      out << "wall-clock limit of " << options_.max_seconds << " s reached after " << p
          << " periods";
      return finish(TransientStatus::kFailed, out.str());
    }
  }
  // Not T-periodic: look for the smallest k with z(t) = z(t − kT).
  const Eigen::VectorXd& z = boundaries.back();
  const double size = std::max(z.cwiseAbs().maxCoeff(), 1e-300);
  for (int k = 2; k <= options_.max_period_multiple && k < static_cast<int>(boundaries.size());
       ++k) {
    const Eigen::VectorXd& earlier = boundaries[boundaries.size() - 1 - k];
    if ((z - earlier).cwiseAbs().maxCoeff() / size <= 10 * options_.steady_tolerance) {
      result.period_multiple = k;
      break;
    }
  }
  return finish(
      TransientStatus::kNotPeriodic,
      "no T-periodic steady state within " + std::to_string(options_.max_periods) + " periods");
}

ChirpResult IdaIntegrator::RunChirp(const Excitation& chirp, int samples_per_cycle) {
  if (!chirp.chirp || !(chirp.duration > 0.0) || !(chirp.omega > 0.0) || !(chirp.omega_end > 0.0)) {
    throw InputError("validation.chirp: needs omega_start, omega_end and duration > 0");
  }
  if (samples_per_cycle < 1) throw InputError("validation.chirp.samples_per_cycle: must be >= 1");
  const auto clock_start = Clock::now();
  const int n = model_.num_dofs();
  const double omega_max = std::max(chirp.omega, chirp.omega_end);
  const double period = kTwoPi / omega_max;  // shortest cycle: sets the largest step
  ChirpResult result;
  result.method = "ida";
  IdaRun run(model_, options_, chirp, period);
  const InitialState rest{Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
  // The response at both ends of the sweep; near a resonance inside it rtol governs anyway.
  const double amplitude = std::max(LinearAmplitude(model_.model, chirp.terms, chirp.omega),
                                    LinearAmplitude(model_.model, chirp.terms, chirp.omega_end));
  auto finish = [&](TransientStatus status, const std::string& message) {
    result.status = status;
    result.message = message;
    result.steps = run.steps();
    result.events = run.events();
    result.wall_seconds = Seconds(clock_start);
    return result;
  };
  if (!run.Start(rest.x, rest.v, MakeScales(model_, omega_max, period, amplitude, rest))) {
    return finish(TransientStatus::kFailed, run.message());
  }
  // Time at which φ(t) = target, by Newton from `guess` (φ is increasing and convex/concave).
  auto phase_time = [&](double target, double guess) {
    double t = guess;
    for (int i = 0; i < 50; ++i) {
      const double step = (chirp.Phase(t) - target) / chirp.InstantaneousOmega(t);
      t -= step;
      if (std::abs(step) <= 1e-15 * std::max(1.0, std::abs(t))) break;
    }
    return t;
  };
  double t_start = 0.0;
  for (int k = 1;; ++k) {
    const double t_end =
        phase_time(kTwoPi * k, t_start + kTwoPi / chirp.InstantaneousOmega(t_start));
    if (t_end > chirp.duration) break;
    if (!run.BeginSegment(t_end)) return finish(TransientStatus::kFailed, run.message());
    const double q0 = run.Q()(0);
    ChirpCycle cycle;
    cycle.t_start = t_start;
    cycle.t_end = t_end;
    cycle.max_abs = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < samples_per_cycle; ++i) {
      const double t = t_start + i * (t_end - t_start) / samples_per_cycle;
      if (i > 0 && !run.AdvanceTo(t)) return finish(TransientStatus::kFailed, run.message());
      cycle.max_abs = cycle.max_abs.cwiseMax(run.X().cwiseAbs());
    }
    if (!run.AdvanceTo(t_end)) return finish(TransientStatus::kFailed, run.message());
    cycle.mean_energy = (run.Q()(0) - q0) / (t_end - t_start);
    cycle.omega = kTwoPi / (t_end - t_start);  // (φ(t_end) − φ(t_start)) / Δt
    result.cycles.push_back(std::move(cycle));
    t_start = t_end;
    if (k % kQuadratureResetPeriods == 0 && !run.ResetQuadratures()) {
      return finish(TransientStatus::kFailed, run.message());
    }
    if (Seconds(clock_start) > options_.max_seconds) {
      return finish(TransientStatus::kFailed, "wall-clock limit reached during the chirp");
    }
  }
  if (!run.BeginSegment(chirp.duration) || !run.AdvanceTo(chirp.duration)) {
    return finish(TransientStatus::kFailed, run.message());
  }
  return finish(TransientStatus::kPeriodic, "");
}

}  // namespace nfrc
