#include "validation/central_difference.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <deque>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/lemke.h"
#include "validation/time_law_check.h"

// Conventions of this implementation:
// - λ_c (N) is the contact force in the equation of motion at t_n; it makes the gaps at t_{n+1}
//   complementary. A contact is "in phase" at t_n while λ_c > 0: from the step before an
//   impact through the sticking phase to the first step whose multiplier vanishes.
// - Explicit laws see x_n and the half-step velocity (x_n − x_{n−1})/h, which is known.
// - Powers at the nodes use v_n = (x_{n+1} − x_{n−1})/2h and are integrated by the trapezoidal
//   rule. h·(f − Cv − f_nl − Gᵀλ)ᵀv_n is exactly the change of the scheme's half-step energy
//   ½v_{n+½}ᵀMv_{n+½} + ½x_nᵀKx_{n+1} (symmetric M, K), so input − damping − laws equals the
//   change of the mean of the two half-step energies around t0 and t0 + T: it matches the
//   nodal energy_change to O(h²) for a smooth motion and exactly on a periodic orbit, and the
//   kinetic energy an impact destroys appears in work_laws (Gᵀλ·v_n > 0 while approaching).

namespace nfrc {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Dense LU of the step matrix up to this many DOFs, sparse LU beyond.
constexpr int kDenseLimit = 200;
// Reciprocal condition number below which the step matrix counts as singular.
constexpr double kSingularRcond = 1e-14;
// The wall clock is read every this many steps.
constexpr long kClockInterval = 1024;

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// g0(φ) of a contact (m).
double InitialGap(const ContactGeometry& contact, double phase) {
  double gap = contact.gap;
  for (const auto& h : contact.gap_harmonics) {
    gap += h.cos * std::cos(h.harmonic * phase) + h.sin * std::sin(h.harmonic * phase);
  }
  return gap;
}

// n(x_dof − x_other) (m); the gap is g0 minus this.
double Approach(const ContactGeometry& contact, const Eigen::VectorXd& x) {
  double relative = x(contact.dof);
  if (contact.other >= 0) relative -= x(contact.other);
  return contact.direction * relative;
}

// Adds the contact force λ (N) as the residual sees it: +nλ on the DOF, −nλ on the other.
void AddContactForce(const ContactGeometry& contact, double lambda, Eigen::VectorXd* force) {
  (*force)(contact.dof) += contact.direction * lambda;
  if (contact.other >= 0) (*force)(contact.other) -= contact.direction * lambda;
}

// LU factorisation of a square sparse matrix, dense for small sizes.
class LuSolver {
 public:
  bool Factorize(const Eigen::SparseMatrix<double>& a) {
    dense_ = a.rows() <= kDenseLimit;
    if (dense_) {
      const Eigen::MatrixXd dense = Eigen::MatrixXd(a);
      dense_lu_.compute(dense);
      // The determinant would overflow for large n with M/h² entries; the condition estimate
      // does not.
      const double rcond = dense_lu_.rcond();
      return std::isfinite(rcond) && rcond > kSingularRcond;
    }
    sparse_ = a;
    sparse_.makeCompressed();
    sparse_lu_ = std::make_unique<Eigen::SparseLU<Eigen::SparseMatrix<double>>>();
    sparse_lu_->compute(sparse_);
    return sparse_lu_->info() == Eigen::Success;
  }
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const {
    if (dense_) return dense_lu_.solve(b);
    return sparse_lu_->solve(b);
  }

 private:
  bool dense_ = true;
  Eigen::PartialPivLU<Eigen::MatrixXd> dense_lu_;
  Eigen::SparseMatrix<double> sparse_;
  std::unique_ptr<Eigen::SparseLU<Eigen::SparseMatrix<double>>> sparse_lu_;
};

// Everything known about time t_n once x_{n+1} is: state, contact forces and the powers.
struct Node {
  double t = 0.0;
  double phase = 0.0;
  Eigen::VectorXd x, v;
  Eigen::VectorXd lambda;  // contact force of each rigid contact (N)
  double energy = 0.0;     // ½vᵀMv + ½xᵀKx (J)
  double power_input = 0.0, power_damping = 0.0, power_laws = 0.0;  // W

  bool InContact(int c) const { return lambda(c) > 0.0; }
};

// The central-difference recursion with forward-increment multipliers (see the header).
// The step is solved as x_{n+1} = x̂ − A⁻¹Gᵀλ with the gaps ĝ + Wλ, W = G A⁻¹ Gᵀ, so λ is
// the contact force in N acting in the equation of motion at t_n.
class Stepper {
 public:
  Stepper(const TransientModel& model, double h) : model_(model), h_(h) {
    n_ = model.num_dofs();
    const auto& m = model.model.mass;
    const auto& c = model.model.damping;
    Eigen::SparseMatrix<double> a = m / (h * h) + c / (2.0 * h);
    ok_ = step_lu_.Factorize(a);
    const int nc = static_cast<int>(model.rigid_contacts.size());
    ainv_gt_.resize(n_, nc);
    for (int k = 0; k < nc; ++k) {
      Eigen::VectorXd column = Eigen::VectorXd::Zero(n_);
      AddContactForce(model.rigid_contacts[k], 1.0, &column);
      ainv_gt_.col(k) = step_lu_.Solve(column);
    }
    w_.resize(nc, nc);
    for (int j = 0; j < nc; ++j) {
      for (int i = 0; i < nc; ++i) {
        // Gap rows are −n(x_dof − x_other), so the gap grows by +G A⁻¹Gᵀλ.
        w_(i, j) = Approach(model.rigid_contacts[i], ainv_gt_.col(j));
      }
    }
    f_.setZero(n_);
    f_nl_.setZero(n_);
    force_laws_.setZero(n_);
    lambda_.setZero(nc);
    gap_hat_.setZero(nc);
  }

  // x_0, v_0 and x_{−1} from a Taylor step with the initial acceleration
  // M a_0 = f_0 − C v_0 − K x_0 − f_nl(x_0, v_0). False if A or M cannot be factorised.
  bool Start(const Excitation& excitation, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
             std::string* message) {
    if (!ok_) {
      *message = "the step matrix M/h² + C/2h is singular";
      return false;
    }
    const auto& model = model_.model;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_);
    excitation.AddForce(0.0, rhs);
    Eigen::VectorXd f_nl = Eigen::VectorXd::Zero(n_);
    AddExplicitForces(excitation.Phase(0.0), x0, v0, &f_nl);
    rhs -= model.damping * v0 + model.stiffness * x0 + f_nl;
    LuSolver mass_lu;
    if (!mass_lu.Factorize(model.mass)) {
      *message = "the mass matrix could not be factorised";
      return false;
    }
    const Eigen::VectorXd a0 = mass_lu.Solve(rhs);
    x_ = x0;
    x_prev_ = x0 - h_ * v0 + 0.5 * h_ * h_ * a0;
    return true;
  }

  // Step n: from x_{n−1}, x_n computes x_{n+1} and fills `node` with the quantities at t_n.
  bool Step(const Excitation& excitation, long n, Node* node, std::string* message) {
    const auto& model = model_.model;
    const double t = static_cast<double>(n) * h_;
    const double phase = excitation.Phase(t);
    f_.setZero();
    excitation.AddForce(t, f_);
    v_half_ = (x_ - x_prev_) / h_;
    f_nl_.setZero();
    AddExplicitForces(phase, x_, v_half_, &f_nl_);
    rhs_ = f_ - model.stiffness * x_ - f_nl_ + model.mass * ((2.0 * x_ - x_prev_) / (h_ * h_)) +
           model.damping * (x_prev_ / (2.0 * h_));
    x_next_ = step_lu_.Solve(rhs_);

    const int nc = static_cast<int>(model_.rigid_contacts.size());
    lambda_.setZero();
    if (nc > 0) {
      const double next_phase = excitation.Phase(t + h_);
      bool any_penetration = false;
      for (int c = 0; c < nc; ++c) {
        const ContactGeometry& contact = model_.rigid_contacts[c];
        gap_hat_(c) = InitialGap(contact, next_phase) - Approach(contact, x_next_);
        any_penetration = any_penetration || gap_hat_(c) < 0.0;
      }
      if (any_penetration && !SolveMultipliers(message)) return false;
      if (any_penetration) x_next_ -= ainv_gt_ * lambda_;
    }
    if (!x_next_.allFinite()) {
      std::ostringstream out;
      out << "the displacement is not finite at t = " << t + h_;
      *message = out.str();
      return false;
    }

    node->t = t;
    node->phase = phase;
    node->x = x_;
    node->v = (x_next_ - x_prev_) / (2.0 * h_);
    node->lambda = lambda_;
    node->energy = 0.5 * node->v.dot(model.mass * node->v) + 0.5 * x_.dot(model.stiffness * x_);
    force_laws_ = f_nl_;
    for (int c = 0; c < nc; ++c)
      AddContactForce(model_.rigid_contacts[c], lambda_(c), &force_laws_);
    node->power_input = f_.dot(node->v);
    node->power_damping = node->v.dot(model.damping * node->v);
    node->power_laws = force_laws_.dot(node->v);
    return true;
  }

  // x_{n−1} ← x_n ← x_{n+1}.
  void Advance() {
    std::swap(x_prev_, x_);
    std::swap(x_, x_next_);
  }

 private:
  void AddExplicitForces(double phase, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                         Eigen::VectorXd* f_nl) const {
    for (const auto& law : model_.laws) {
      const bool explicit_force = law->ExplicitForce(phase, x, v, *f_nl);
      assert(explicit_force && "laws were checked by the constructor");
      (void)explicit_force;
    }
  }

  // 0 ≤ λ ⊥ ĝ + Wλ ≥ 0: a scalar for one contact, Lemke for several.
  bool SolveMultipliers(std::string* message) {
    if (gap_hat_.size() == 1) {
      lambda_(0) = std::max(0.0, -gap_hat_(0) / w_(0, 0));
      return true;
    }
    LemkeOptions options;
    options.warm_basis = warm_basis_;
    const LemkeResult result = SolveLcp(w_, gap_hat_, options);
    if (!result.ok()) {
      *message =
          "contact multipliers: Lemke " + ToString(result.status) + " (" + result.message + ")";
      return false;
    }
    lambda_ = result.z.cwiseMax(0.0);
    warm_basis_ = result.basic_z;
    return true;
  }

  const TransientModel& model_;
  double h_;
  int n_ = 0;
  bool ok_ = false;
  LuSolver step_lu_;
  Eigen::MatrixXd ainv_gt_;  // A⁻¹Gᵀ, one column per contact (m/N)
  Eigen::MatrixXd w_;        // Delassus matrix G A⁻¹ Gᵀ (m/N)
  std::vector<int> warm_basis_;
  Eigen::VectorXd x_prev_, x_, x_next_, v_half_, f_, f_nl_, force_laws_, rhs_, lambda_, gap_hat_;
};

// One period [t0, t0 + T) built from its nodes: samples (linear interpolation between steps),
// trapezoidal energy and work integrals, contact phase logs. Rigid contacts come first in
// law_signals and phases, then the explicit laws (whose phases are not tracked: empty logs).
class PeriodRecorder {
 public:
  PeriodRecorder(const TransientModel& model, const Excitation& excitation, long steps, int samples,
                 double period, double omega)
      : model_(model),
        excitation_(excitation),
        steps_(steps),
        samples_(samples),
        period_(period),
        omega_(omega) {}

  void Begin(const Node& start) {
    const int n = model_.num_dofs();
    const int nc = static_cast<int>(model_.rigid_contacts.size());
    record_ = PeriodRecord();
    record_.t0 = start.t;
    record_.period = period_;
    record_.t = Eigen::VectorXd::LinSpaced(samples_, 0.0, samples_ - 1.0) * (period_ / samples_);
    record_.t.array() += start.t;
    record_.x.setZero(n, samples_);
    record_.v.setZero(n, samples_);
    record_.law_signals.resize(nc + model_.laws.size());
    for (int c = 0; c < nc; ++c) {
      record_.law_signals[c] = {{"gap", Eigen::VectorXd::Zero(samples_)},
                                {"force", Eigen::VectorXd::Zero(samples_)}};
      record_.phases.push_back({"rigid_contact", "contact", start.InContact(c), {}});
    }
    for (const auto& law : model_.laws) record_.phases.push_back({law->type(), "", false, {}});
    start_energy_ = start.energy;
    scale_ = Scale(start);
  }

  // The interval from node a to node b, b the j-th node of the period (1 ≤ j ≤ steps).
  void AddInterval(const Node& a, const Node& b, long j) {
    const double h = b.t - a.t;
    record_.work_input += 0.5 * h * (a.power_input + b.power_input);
    record_.work_damping += 0.5 * h * (a.power_damping + b.power_damping);
    record_.work_laws += 0.5 * h * (a.power_laws + b.power_laws);
    record_.mean_energy += 0.5 * h * (a.energy + b.energy);
    scale_ = std::max(scale_, Scale(b));
    if (j < steps_) {
      for (int c = 0; c < static_cast<int>(model_.rigid_contacts.size()); ++c) {
        if (a.InContact(c) != b.InContact(c))
          record_.phases[c].changes.push_back({b.t, b.InContact(c)});
      }
    }
    // Samples i at step position i·steps/samples in [j − 1, j).
    const long long first = ((j - 1LL) * samples_ + steps_ - 1) / steps_;
    for (long long i = first; i < samples_ && i * steps_ < j * static_cast<long long>(samples_);
         ++i) {
      const double theta = static_cast<double>(i * steps_ - (j - 1LL) * samples_) / samples_;
      Sample(a, b, static_cast<int>(i), theta);
    }
  }

  PeriodRecord Finish(const Node& end) {
    record_.mean_energy /= period_;
    record_.energy_change = end.energy - start_energy_;
    return std::move(record_);
  }

  // max|z| over the period's nodes, z = (x, v/ω).
  double scale() const { return scale_; }

 private:
  double Scale(const Node& node) const {
    return std::max(node.x.cwiseAbs().maxCoeff(), node.v.cwiseAbs().maxCoeff() / omega_);
  }

  void Sample(const Node& a, const Node& b, int i, double theta) {
    const int n = model_.num_dofs();
    const Eigen::VectorXd x = (1.0 - theta) * a.x + theta * b.x;
    const Eigen::VectorXd v = (1.0 - theta) * a.v + theta * b.v;
    record_.x.col(i) = x;
    record_.v.col(i) = v;
    const double t = record_.t(i);
    const double phase = excitation_.Phase(t);
    const int nc = static_cast<int>(model_.rigid_contacts.size());
    for (int c = 0; c < nc; ++c) {
      const ContactGeometry& contact = model_.rigid_contacts[c];
      record_.law_signals[c][0].second(i) = InitialGap(contact, phase) - Approach(contact, x);
      record_.law_signals[c][1].second(i) = (1.0 - theta) * a.lambda(c) + theta * b.lambda(c);
    }
    if (model_.laws.empty()) return;
    Eigen::VectorXd y(2 * n), yp = Eigen::VectorXd::Zero(2 * n);
    y << x, v;
    yp.head(n) = v;
    TimeLawLayout layout;
    layout.num_dofs = n;
    layout.own_offset = 2 * n;
    for (size_t l = 0; l < model_.laws.size(); ++l) {
      // The scheme keeps no modes; a law's signals may depend on its mode (a penalty contact
      // reports its force only when closed), so the mode is first set from the sampled state.
      TimeLaw& law = *model_.laws[l];
      const DaeView view = MakeDaeView(law, layout, t, phase, y, yp);
      law.InitMode(layout, view);
      const auto signals = law.Signals(layout, view);
      auto& stored = record_.law_signals[nc + l];
      if (stored.empty()) {
        for (const auto& [name, value] : signals) {
          stored.push_back({name, Eigen::VectorXd::Zero(samples_)});
        }
      }
      for (size_t k = 0; k < signals.size() && k < stored.size(); ++k) {
        stored[k].second(i) = signals[k].second;
      }
    }
  }

  const TransientModel& model_;
  const Excitation& excitation_;
  long steps_;
  int samples_;
  double period_;
  double omega_;
  PeriodRecord record_;
  double start_energy_ = 0.0;
  double scale_ = 0.0;
};

// Smallest k in 2..max_period_multiple for which each of the latest steady_periods boundary
// states z repeats the one k periods earlier to steady_tolerance (relative to max|z| over the
// last k periods); 0 if none.
int PeriodMultiple(const std::deque<Eigen::VectorXd>& boundaries, const std::deque<double>& scales,
                   const TransientOptions& options) {
  const int size = static_cast<int>(boundaries.size());
  for (int multiple = 2; multiple <= options.max_period_multiple; ++multiple) {
    if (size < multiple + options.steady_periods) break;
    const double scale = *std::max_element(scales.end() - multiple, scales.end());
    bool periodic = true;
    for (int b = size - options.steady_periods; b < size && periodic; ++b) {
      const double d = (boundaries[b] - boundaries[b - multiple]).cwiseAbs().maxCoeff();
      periodic = scale <= 0.0 || d / scale < options.steady_tolerance;
    }
    if (periodic) return multiple;
  }
  return 0;
}

Eigen::VectorXd StateVector(const Node& node, double omega) {
  Eigen::VectorXd z(2 * node.x.size());
  z << node.x, node.v / omega;
  return z;
}

Eigen::VectorXd OrZeros(const Eigen::VectorXd& value, int n, const std::string& field) {
  if (value.size() == 0) return Eigen::VectorXd::Zero(n);
  if (value.size() != n) {
    throw InputError(field + ": has " + std::to_string(value.size()) + " entries, the model " +
                     std::to_string(n) + " DOFs");
  }
  return value;
}

}  // namespace

CentralDifferenceIntegrator::CentralDifferenceIntegrator(TransientModel& model,
                                                         TransientOptions options)
    : model_(model), options_(std::move(options)) {
  options_.Validate();
  const int n = model_.num_dofs();
  if (n == 0) throw InputError("model: the explicit scheme needs at least one DOF");
  const std::string mass_error =
      "model.M: the explicit scheme needs a positive definite mass matrix";
  for (bool massless : model_.massless) {
    if (massless) throw InputError(mass_error);
  }
  Eigen::VectorXd scratch_x = Eigen::VectorXd::Zero(n), scratch_f = Eigen::VectorXd::Zero(n);
  for (size_t i = 0; i < model_.laws.size(); ++i) {
    if (!model_.laws[i]->ExplicitForce(0.0, scratch_x, scratch_x, scratch_f)) {
      const std::string path = i < model_.law_paths.size()
                                   ? model_.law_paths[i]
                                   : "nonlinearities[" + std::to_string(i) + "]";
      throw InputError(path + ": the " + model_.laws[i]->type() +
                       " law has no explicit force; the central-difference scheme cannot use it");
    }
  }
  for ([[maybe_unused]] const ContactGeometry& c : model_.rigid_contacts) {
    assert(c.dof >= 0 && c.dof < n && c.other < n);
  }

  // ω_max² is the largest eigenvalue of (K + the laws' stiffness bounds, M), symmetric parts.
  const Eigen::MatrixXd mass = Eigen::MatrixXd(model_.model.mass);
  const Eigen::MatrixXd mass_sym = 0.5 * (mass + mass.transpose());
  if (mass_sym.llt().info() != Eigen::Success) throw InputError(mass_error);
  const Eigen::MatrixXd stiffness = Eigen::MatrixXd(model_.model.stiffness);
  Eigen::MatrixXd stiffness_sym = 0.5 * (stiffness + stiffness.transpose());
  for (const auto& law : model_.laws) {
    for (const auto& [dof, k] : law->StiffnessBound()) stiffness_sym(dof, dof) += k;
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eigen(stiffness_sym, mass_sym,
                                                                  Eigen::EigenvaluesOnly);
  if (eigen.info() != Eigen::Success) throw InputError(mass_error);
  omega_max_ = std::sqrt(std::max(0.0, eigen.eigenvalues().maxCoeff()));
}

CentralDifferenceIntegrator::~CentralDifferenceIntegrator() = default;

double CentralDifferenceIntegrator::StepFor(double omega) const {
  if (!(omega > 0.0) || !std::isfinite(omega)) throw InputError("omega: must be positive");
  const double period = kTwoPi / omega;
  // Without stiffness there is no stability limit: one step per recorded sample.
  if (omega_max_ <= 0.0) return period / options_.samples_per_period;
  const double largest = options_.explicit_step_fraction * 2.0 / omega_max_;
  const double steps = std::max(1.0, std::ceil(period / largest * (1.0 - 1e-12)));
  return period / steps;
}

TransientResult CentralDifferenceIntegrator::RunToSteadyState(double omega,
                                                              const InitialState& start) {
  const Clock::time_point clock = Clock::now();
  const int n = model_.num_dofs();
  const double h = StepFor(omega);
  const double period = kTwoPi / omega;
  const long steps = std::lround(period / h);
  const Eigen::VectorXd x0 = OrZeros(start.x, n, "start.x");
  const Eigen::VectorXd v0 = OrZeros(start.v, n, "start.v");

  TransientResult result;
  result.method = "central_difference";
  result.omega = omega;
  const Excitation excitation = Excitation::Harmonic(model_.forcing, omega);
  Stepper stepper(model_, h);
  if (!stepper.Start(excitation, x0, v0, &result.message)) return result;
  PeriodRecorder recorder(model_, excitation, steps, options_.samples_per_period, period, omega);
  const int nc = static_cast<int>(model_.rigid_contacts.size());
  const int history = options_.max_period_multiple + options_.steady_periods + 1;
  std::deque<Eigen::VectorXd> boundaries;  // z at the latest period boundaries
  std::deque<double> scales;               // max|z| of the periods between them
  int consecutive = 0;
  Node previous, current;
  for (long k = 0;; ++k) {
    if (!stepper.Step(excitation, k, &current, &result.message)) break;
    stepper.Advance();
    result.steps = k + 1;
    result.t_end = current.t;
    if (k > 0) {
      const long j = k - (k - 1) / steps * steps;
      recorder.AddInterval(previous, current, j);
      for (int c = 0; c < nc; ++c) result.events += previous.InContact(c) != current.InContact(c);
    }
    if (k % steps == 0) {
      boundaries.push_back(StateVector(current, omega));
      if (k > 0) {
        result.periods = static_cast<int>(k / steps);
        scales.push_back(recorder.scale());
        result.last_period = recorder.Finish(current);
        const Eigen::VectorXd& z = boundaries.back();
        const double scale = scales.back();
        const double difference =
            scale > 0.0 ? (z - boundaries[boundaries.size() - 2]).cwiseAbs().maxCoeff() / scale
                        : 0.0;
        result.period_differences.push_back(difference);
        consecutive = difference < options_.steady_tolerance ? consecutive + 1 : 0;
        if (consecutive >= options_.steady_periods && result.periods >= options_.min_periods) {
          result.status = TransientStatus::kPeriodic;
          result.message = "periodic";
          break;
        }
        if (result.periods >= options_.min_periods) {
          result.period_multiple = PeriodMultiple(boundaries, scales, options_);
        }
        if (result.period_multiple > 0) {
          result.status = TransientStatus::kNotPeriodic;
          result.message = std::to_string(result.period_multiple) + "T-periodic";
          break;
        }
        if (result.periods >= options_.max_periods) {
          result.status = TransientStatus::kNotPeriodic;
          result.message =
              "not periodic after max_periods = " + std::to_string(options_.max_periods) +
              " periods";
          break;
        }
        while (static_cast<int>(boundaries.size()) > history) boundaries.pop_front();
        while (static_cast<int>(scales.size()) > history) scales.pop_front();
      }
      recorder.Begin(current);
    }
    if (k % kClockInterval == 0 && Seconds(clock) > options_.max_seconds) {
      result.message = "max_seconds passed at t = " + std::to_string(current.t);
      break;
    }
    std::swap(previous, current);
  }
  result.wall_seconds = Seconds(clock);
  return result;
}

ChirpResult CentralDifferenceIntegrator::RunChirp(const Excitation& chirp, int samples_per_cycle) {
  const Clock::time_point clock = Clock::now();
  if (samples_per_cycle < 1) throw InputError("samples_per_cycle: must be at least 1");
  if (!(chirp.duration > 0.0)) throw InputError("chirp.duration: must be positive");
  const double omega_high = std::max(chirp.omega, chirp.chirp ? chirp.omega_end : chirp.omega);
  if (!(omega_high > 0.0)) throw InputError("chirp.omega: must be positive");
  double largest = kTwoPi / (omega_high * samples_per_cycle);
  if (omega_max_ > 0.0)
    largest = std::min(largest, options_.explicit_step_fraction * 2.0 / omega_max_);
  const long steps = static_cast<long>(std::max(1.0, std::ceil(chirp.duration / largest)));
  const double h = chirp.duration / steps;
  const int n = model_.num_dofs();

  ChirpResult result;
  result.method = "central_difference";
  Stepper stepper(model_, h);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  if (!stepper.Start(chirp, zero, zero, &result.message)) return result;
  const int nc = static_cast<int>(model_.rigid_contacts.size());
  ChirpCycle cycle;
  cycle.max_abs = Eigen::VectorXd::Zero(n);
  double energy_integral = 0.0;
  Node previous, current;
  bool completed = true;
  for (long k = 0; k <= steps; ++k) {
    if (!stepper.Step(chirp, k, &current, &result.message)) {
      completed = false;
      break;
    }
    stepper.Advance();
    result.steps = k + 1;
    if (k > 0) {
      for (int c = 0; c < nc; ++c) result.events += previous.InContact(c) != current.InContact(c);
      // Cycle boundaries where the phase passes a multiple of 2π inside (t_{k−1}, t_k].
      double t_a = previous.t, phase_a = previous.phase, energy_a = previous.energy;
      for (double next = (std::floor(phase_a / kTwoPi) + 1.0) * kTwoPi; next <= current.phase;
           next += kTwoPi) {
        const double theta = (next - previous.phase) / (current.phase - previous.phase);
        const double t_c = previous.t + theta * (current.t - previous.t);
        const double energy_c = previous.energy + theta * (current.energy - previous.energy);
        const Eigen::VectorXd x_c = previous.x + theta * (current.x - previous.x);
        energy_integral += 0.5 * (t_c - t_a) * (energy_a + energy_c);
        cycle.max_abs = cycle.max_abs.cwiseMax(x_c.cwiseAbs());
        cycle.t_end = t_c;
        cycle.omega = kTwoPi / (cycle.t_end - cycle.t_start);
        cycle.mean_energy = energy_integral / (cycle.t_end - cycle.t_start);
        result.cycles.push_back(cycle);
        cycle = ChirpCycle();
        cycle.t_start = t_c;
        cycle.max_abs = x_c.cwiseAbs();
        energy_integral = 0.0;
        t_a = t_c;
        energy_a = energy_c;
      }
      energy_integral += 0.5 * (current.t - t_a) * (energy_a + current.energy);
    }
    cycle.max_abs = cycle.max_abs.cwiseMax(current.x.cwiseAbs());
    if (k % kClockInterval == 0 && Seconds(clock) > options_.max_seconds) {
      result.message = "max_seconds passed at t = " + std::to_string(current.t);
      completed = false;
      break;
    }
    std::swap(previous, current);
  }
  if (completed) {
    result.status = TransientStatus::kPeriodic;
    result.message = "completed";
  }
  result.wall_seconds = Seconds(clock);
  return result;
}

}  // namespace nfrc
