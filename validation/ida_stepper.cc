#include "validation/ida_stepper.h"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>

#include "core/errors.h"
#include "validation/ida_dae.h"
#include "validation/linear_response.h"

namespace nfrc {
namespace {

using Clock = std::chrono::steady_clock;
using Triplets = IdaDae::Triplets;

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kNumQuadratures = IdaDae::kNumQuadratures;
// Handled roots in one segment beyond which the run is declared chattering.
constexpr long kMaxEventsPerSegment = 10000;
// A root reported this soon (× the shortest period) after a re-initialisation by the root just
// handled is that root again, not a new crossing.
constexpr double kRepeatedRootWindow = 1e-12;
constexpr long kMaxStepsPerCall = 20000;  // then AdvanceTo looks at the wall clock

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

// Typical magnitudes of the unknowns: atol = rtol × absolute_scale_factor × scale.
struct Scales {
  double x = 1.0;       // m: displacements
  double v = 1.0;       // m/s: velocities
  double own = 1.0;     // N: laws' own unknowns (forces)
  double energy = 1.0;  // J·s: ∫E dt over a period
  double work = 1.0;    // J: works over a period
};

// Scales at frequencies up to `omega`: x from the linear response (or the start, if larger), v
// = ω x, own unknowns (forces) the largest forcing amplitude (else K x), ∫E dt a period of the
// energy at that amplitude, works a period of F ω x. The quadratures stay in the error test
// with these atol, and the driver zeroes them periodically so that rtol·|q| stays of the order
// of one period's increment.
Scales MakeScales(const TransientModel& model, double omega, double period, double x_amplitude,
                  const StepperStart& start) {
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

// IDA's counters since its last (re)initialisation.
TransientStatistics Counters(void* ida) {
  TransientStatistics s;
  if (ida == nullptr) return s;
  IDAGetNumSteps(ida, &s.steps);
  IDAGetNumResEvals(ida, &s.residual_evaluations);
  IDAGetNumJacEvals(ida, &s.jacobian_evaluations);
  IDAGetNumNonlinSolvIters(ida, &s.nonlinear_iterations);
  IDAGetNumNonlinSolvConvFails(ida, &s.nonlinear_convergence_failures);
  IDAGetNumErrTestFails(ida, &s.error_test_failures);
  return s;
}

}  // namespace

// One IDA integration of the DAE under one excitation: set-up, stepping, roots, mode
// switches and re-initialisation.
class IdaStepper::Run {
 public:
  Run(TransientModel& model, const TransientOptions& options, const StepperStart& start)
      : model_(model),
        options_(options),
        excitation_(*start.excitation),
        dae_(model, excitation_),
        deadline_(start.deadline) {
    omega_max_ =
        excitation_.chirp ? std::max(excitation_.omega, excitation_.omega_end) : excitation_.omega;
    period_ = kTwoPi / omega_max_;  // the shortest excitation period: sets the largest step
    size_ = dae_.size();
    q_ = dae_.quadrature_offset();
    rootsfound_.assign(dae_.num_roots(), 0);
    last_fired_.assign(dae_.num_roots(), false);
    using LS = TransientOptions::LinearSolver;
    dense_ = options.linear_solver == LS::kDense ||
             (options.linear_solver == LS::kAuto && size_ <= TransientOptions::kDenseLimit);
    for (const auto& law : model_.laws) {
      LawPhaseLog log;
      log.type = law->type();
      log.phase_name = law->PhaseName();
      phase_logs_.push_back(log);
    }
  }

  const std::string& message() const { return message_; }
  double t() const { return t_; }
  Eigen::Map<const Eigen::VectorXd> X() const { return {Y(), dae_.num_dofs()}; }
  Eigen::Map<const Eigen::VectorXd> V() const { return {Y() + dae_.num_dofs(), dae_.num_dofs()}; }
  Eigen::Map<const Eigen::VectorXd> Own() const {
    return {Y() + 2 * dae_.num_dofs(), q_ - 2 * dae_.num_dofs()};
  }
  const std::vector<LawPhaseLog>& phase_logs() const { return phase_logs_; }

  StepperQuadratures Quadratures() const {
    const double* q = Y() + q_;
    return {q[0], q[1], q[2], q[3]};
  }

  TransientStatistics Statistics() const {
    TransientStatistics total = done_;
    total += Counters(sun_.ida);
    total.events = events_;
    return total;
  }

  LawSignalValues Signals() const {
    LawSignalValues signals;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      signals.push_back(model_.laws[l]->Signals(dae_.layout(l), dae_.View(l, t_, Y(), YP())));
    }
    return signals;
  }

  // Sets up IDA at t = 0 from the start's state after choosing modes and consistent values.
  bool Start(const StepperStart& start) {
    if (SUNContext_Create(nullptr, &sun_.context) != 0) return Fail("SUNContext_Create failed");
    sun_.y = N_VNew_Serial(size_, sun_.context);
    sun_.yp = N_VNew_Serial(size_, sun_.context);
    sun_.id = N_VNew_Serial(size_, sun_.context);
    sun_.atol = N_VNew_Serial(size_, sun_.context);
    if (!sun_.y || !sun_.yp || !sun_.id || !sun_.atol) return Fail("N_VNew_Serial failed");
    N_VConst(0.0, sun_.y);
    N_VConst(0.0, sun_.yp);
    const int n = dae_.num_dofs();
    Eigen::Map<Eigen::VectorXd> y(MutableY(), size_);
    y.head(n) = start.x;
    y.segment(n, n) = start.v;
    if (start.own.size() > 0) {
      if (start.own.size() != q_ - 2 * n) {
        return Fail("the start has " + std::to_string(start.own.size()) +
                    " own unknowns, the laws " + std::to_string(q_ - 2 * n));
      }
      // Only the differential ones: the algebraic ones follow from consistency.
      for (int j = 2 * n; j < q_; ++j) {
        if (dae_.differential(j)) y(j) = start.own(j - 2 * n);
      }
    }
    double amplitude = LinearAmplitude(model_.model, excitation_.terms, excitation_.omega);
    if (excitation_.chirp) {
      // The response at both ends of the sweep; near a resonance inside it rtol governs anyway.
      amplitude = std::max(amplitude,
                           LinearAmplitude(model_.model, excitation_.terms, excitation_.omega_end));
    }
    const Scales scales = MakeScales(model_, omega_max_, period_, amplitude, start);
    Eigen::Map<Eigen::VectorXd> id(N_VGetArrayPointer(sun_.id), size_);
    Eigen::Map<Eigen::VectorXd> atol(N_VGetArrayPointer(sun_.atol), size_);
    const double factor = options_.relative_tolerance * options_.absolute_scale_factor;
    auto scale = [&](int j) {
      if (j < n) return scales.x;
      if (j < 2 * n) return scales.v;
      if (j < q_) return scales.own;
      return j == q_ ? scales.energy : scales.work;
    };
    for (int j = 0; j < size_; ++j) {
      id(j) = dae_.differential(j) ? 1.0 : 0.0;
      atol(j) = factor * scale(j);
    }
    if (!dae_.Initialise(0.0, MutableY(), MutableYP())) return Fail(dae_.message());

    sun_.ida = IDACreate(sun_.context);
    if (sun_.ida == nullptr) return Fail("IDACreate failed");
    int flag = IDASetErrHandlerFn(sun_.ida, &Run::ErrorHandler, this);
    if (flag == IDA_SUCCESS) flag = IDAInit(sun_.ida, &Run::ResidualFn, 0.0, sun_.y, sun_.yp);
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
      dae_.Assemble(0.0, Y(), YP(), 1.0, &entries);
      const long capacity = static_cast<long>(entries.size()) + size_;
      sun_.matrix = SUNSparseMatrix(size_, size_, capacity, CSC_MAT, sun_.context);
      if (sun_.matrix) sun_.solver = SUNLinSol_KLU(sun_.y, sun_.matrix, sun_.context);
    }
    if (!sun_.matrix || !sun_.solver) return Fail("cannot create the linear solver");
    flag = IDASetLinearSolver(sun_.ida, sun_.solver, sun_.matrix);
    if (flag == IDA_SUCCESS) flag = IDASetJacFn(sun_.ida, &Run::JacobianFn);
    if (flag == IDA_SUCCESS) flag = IDASetId(sun_.ida, sun_.id);
    // The algebraic unknowns stay in the error test (IDA's advice for index 1): suppressed, a
    // sticking force interpolated over the long steps of a stick phase was off by 1% and fired
    // its release root early.
    if (flag == IDA_SUCCESS) flag = IDASetSuppressAlg(sun_.ida, SUNFALSE);
    if (flag == IDA_SUCCESS) flag = IDASetMaxStep(sun_.ida, options_.max_step_fraction * period_);
    if (flag == IDA_SUCCESS) flag = IDASetMaxNumSteps(sun_.ida, kMaxStepsPerCall);
    if (flag == IDA_SUCCESS && dae_.num_roots() > 0) {
      flag = IDARootInit(sun_.ida, dae_.num_roots(), &Run::RootFn);
    }
    if (flag != IDA_SUCCESS) return Fail("IDA set-up failed: " + FlagName(flag));
    return true;
  }

  // Starts a segment at the current time, ending at `stop` (IDA's stop time).
  bool BeginSegment(double stop) {
    stop_ = stop;
    roots_in_segment_ = 0;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      phase_logs_[l].in_phase_at_start = model_.laws[l]->InPhase();
      phase_logs_[l].changes.clear();
    }
    const int flag = IDASetStopTime(sun_.ida, stop_);
    return flag == IDA_SUCCESS || Fail("IDASetStopTime: " + FlagName(flag));
  }

  // Zeroes the quadratures (a restart of IDA at the current time).
  bool ResetQuadratures() {
    last_fired_.assign(dae_.num_roots(), false);
    Eigen::Map<Eigen::VectorXd>(MutableY() + q_, kNumQuadratures).setZero();
    // A differentiated row drifts from its original between restarts: project here too.
    if (dae_.has_reduced_rows() && !dae_.MakeConsistent(t_, MutableY(), MutableYP())) {
      return Fail(dae_.message());
    }
    return Reinitialise();
  }

  // Integrates to tout ≤ the segment's stop, stopping at every root on the way.
  StepOutcome AdvanceTo(double tout) {
    while (tout - t_ > kRepeatedRootWindow * period_) {
      double t_return = t_;
      last_error_.clear();
      const int flag = IDASolve(sun_.ida, tout, &t_return, sun_.y, sun_.yp, IDA_NORMAL);
      t_ = t_return;
      if (flag == IDA_SUCCESS || flag == IDA_TSTOP_RETURN) return StepOutcome::kOk;
      if (Clock::now() > deadline_) return StepOutcome::kOutOfTime;
      if (flag == IDA_ROOT_RETURN) {
        if (!HandleRoot()) return StepOutcome::kFailed;
        continue;
      }
      if (flag == IDA_TOO_MUCH_WORK) continue;  // only a pause to look at the clock
      std::ostringstream out;
      out << "IDA failed at t = " << t_ << ": " << FlagName(flag);
      if (!last_error_.empty()) out << " (" << last_error_ << ")";
      Fail(out.str());
      return StepOutcome::kFailed;
    }
    return StepOutcome::kOk;
  }

 private:
  const double* Y() const { return N_VGetArrayPointer(sun_.y); }
  const double* YP() const { return N_VGetArrayPointer(sun_.yp); }
  double* MutableY() { return N_VGetArrayPointer(sun_.y); }
  double* MutableYP() { return N_VGetArrayPointer(sun_.yp); }

  bool Fail(const std::string& message) {
    message_ = message;
    return false;
  }

  // IDAReInit zeroes IDA's counters: bank them first.
  bool Reinitialise() {
    done_ += Counters(sun_.ida);
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
    std::vector<bool> fired(dae_.num_roots(), false);
    bool handled = false;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      for (int k = 0; k < model_.laws[l]->NumRoots(); ++k) {
        const int root = dae_.root_offset(l) + k;
        if (rootsfound_[root] == 0) continue;
        fired[root] = true;
        if (just_restarted && last_fired_[root]) continue;
        model_.laws[l]->OnRoot(dae_.layout(l), dae_.View(l, t_, Y(), YP()), k);
        handled = true;
      }
    }
    if (!handled) return true;  // the root just handled, reported again: IDA continues
    if (!dae_.SettleModes(t_, MutableY(), MutableYP())) return Fail(dae_.message());
    long switches = 0;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      if (model_.laws[l]->ModeIndex() != modes[l]) ++switches;
      if (model_.laws[l]->InPhase() != phases[l]) {
        phase_logs_[l].changes.emplace_back(t_, model_.laws[l]->InPhase());
      }
    }
    events_ += switches;
    // Handled roots, switching or not, so that a root rejected again and again also stops.
    if (++roots_in_segment_ > kMaxEventsPerSegment) {
      std::ostringstream out;
      out << "chattering: more than " << kMaxEventsPerSegment << " events in one period"
          << " at t = " << t_;
      return Fail(out.str());
    }
    // Restart even when the mode iteration returned to the old modes: IDA then re-evaluates
    // the root functions from consistent values instead of its interpolated ones.
    last_fired_ = fired;
    return Reinitialise();
  }

  // The KLU matrix from triplets_; a new sparsity pattern gets a new symbolic factorisation.
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
      if (SUNLinSol_KLUReInit(sun_.solver, matrix, nnz, SUNKLU_REINIT_PARTIAL) != 0) return false;
    }
    std::copy(jacobian.valuePtr(), jacobian.valuePtr() + nnz, SUNSparseMatrix_Data(matrix));
    return true;
  }

  static int ResidualFn(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void* data) {
    static_cast<const Run*>(data)->dae_.Residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                                                 N_VGetArrayPointer(r));
    return 0;
  }

  static int JacobianFn(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector /*r*/,
                        SUNMatrix matrix, void* data, N_Vector, N_Vector, N_Vector) {
    auto* run = static_cast<Run*>(data);
    run->dae_.Assemble(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), cj, &run->triplets_);
    if (!run->dense_) return run->FillSparse(matrix) ? 0 : -1;
    SUNMatZero(matrix);
    for (const auto& e : run->triplets_) SM_ELEMENT_D(matrix, e.row(), e.col()) += e.value();
    return 0;
  }

  static int RootFn(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype* g, void* data) {
    static_cast<const Run*>(data)->dae_.Roots(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), g);
    return 0;
  }

  static void ErrorHandler(int /*code*/, const char* module, const char* function, char* message,
                           void* data) {
    static_cast<Run*>(data)->last_error_ = std::string(module) + "::" + function + ": " + message;
  }

  TransientModel& model_;
  const TransientOptions& options_;
  Excitation excitation_;  // a copy: the DAE refers to it for the run's life
  IdaDae dae_;
  Clock::time_point deadline_;
  double omega_max_ = 1.0;  // highest excitation frequency (rad/s)
  double period_ = 1.0;     // the shortest excitation period, 2π/omega_max_ (s)
  int size_ = 0;
  int q_ = 0;
  bool dense_ = true;
  Triplets triplets_;
  std::vector<int> pattern_outer_, pattern_inner_;
  std::vector<int> rootsfound_;
  std::vector<bool> last_fired_;
  std::vector<LawPhaseLog> phase_logs_;
  Sundials sun_;
  double t_ = 0.0;
  double t_reinit_ = -1.0;
  double stop_ = 0.0;
  TransientStatistics done_;  // IDA's counters before the last re-initialisation
  long events_ = 0;
  long roots_in_segment_ = 0;
  std::string message_;
  std::string last_error_;
};

IdaStepper::IdaStepper(TransientModel& model, const TransientOptions& options)
    : model_(model), options_(options) {
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

IdaStepper::~IdaStepper() = default;

bool IdaStepper::Start(const StepperStart& start) {
  run_ = std::make_unique<Run>(model_, options_, start);
  return run_->Start(start);
}

bool IdaStepper::BeginSegment(double t_end) { return run_->BeginSegment(t_end); }
StepOutcome IdaStepper::AdvanceTo(double t) { return run_->AdvanceTo(t); }
bool IdaStepper::ResetQuadratures() { return run_->ResetQuadratures(); }
double IdaStepper::t() const { return run_ ? run_->t() : 0.0; }
Eigen::Ref<const Eigen::VectorXd> IdaStepper::x() const { return run_->X(); }
Eigen::Ref<const Eigen::VectorXd> IdaStepper::v() const { return run_->V(); }
Eigen::VectorXd IdaStepper::own() const { return run_->Own(); }
LawSignalValues IdaStepper::Signals() const { return run_->Signals(); }
const std::vector<LawPhaseLog>& IdaStepper::PhaseLogs() const { return run_->phase_logs(); }
StepperQuadratures IdaStepper::Quadratures() const { return run_->Quadratures(); }

TransientStatistics IdaStepper::Statistics() const {
  return run_ ? run_->Statistics() : TransientStatistics();
}

const std::string& IdaStepper::message() const { return run_ ? run_->message() : message_; }

}  // namespace nfrc
