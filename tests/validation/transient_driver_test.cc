#include "validation/transient_driver.h"

#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "validation/stepper.h"
#include "validation/transient.h"

namespace nfrc {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kOmega = 2.0;  // rad/s
constexpr double kPeriod = 2 * kPi / kOmega;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Round-off of closed forms evaluated at t = pT (p ≤ 100): the phase ωt carries ~1e-13.
constexpr double kRoundOff = 1e-11;

// What a FakeStepper answers: a one-DOF state given in closed form, constant rates for the
// quadratures, a fixed amount of work per AdvanceTo call, and where it stops.
struct FakeBehaviour {
  std::function<double(double)> x;  // m
  std::function<double(double)> v;  // m/s
  StepperQuadratures rates;         // per second: J·s/s for the energy, W for the works
  TransientStatistics per_call;     // added by every AdvanceTo
  double fail_after = kInfinity;    // AdvanceTo beyond this time fails (s)
  double out_of_time_after = kInfinity;
  bool start_fails = false;
};

// A stepper whose answers are known analytically, to test the driver's rules alone. It also
// checks how it is driven: never backwards, never beyond the segment's end.
class FakeStepper : public TransientStepper {
 public:
  explicit FakeStepper(FakeBehaviour behaviour) : b_(std::move(behaviour)) {}

  std::string method() const override { return "fake"; }

  bool Start(const StepperStart& start) override {
    excitation_ = *start.excitation;
    statistics_ = TransientStatistics();
    t_ = reset_t_ = 0.0;
    segment_end_ = kInfinity;
    Update();
    if (b_.start_fails) {
      message_ = "fake start failure";
      return false;
    }
    return true;
  }

  bool BeginSegment(double t_end) override {
    segment_end_ = t_end;
    logs_ = {LawPhaseLog{"fake_law", "stick", true, {}}};
    return true;
  }

  StepOutcome AdvanceTo(double t) override {
    ++calls;
    statistics_ += b_.per_call;
    if (t < t_) backwards = true;
    if (t > segment_end_ * (1 + 1e-15)) beyond_segment = true;
    if (t > b_.fail_after) {
      t_ = b_.fail_after;
      message_ = "fake failure";
      return StepOutcome::kFailed;
    }
    if (t > b_.out_of_time_after) {
      t_ = b_.out_of_time_after;
      return StepOutcome::kOutOfTime;
    }
    t_ = t;
    Update();
    return StepOutcome::kOk;
  }

  bool ResetQuadratures() override {
    reset_t_ = t_;
    ++resets;
    return true;
  }

  double t() const override { return t_; }
  Eigen::Ref<const Eigen::VectorXd> x() const override { return x_; }
  Eigen::Ref<const Eigen::VectorXd> v() const override { return v_; }
  LawSignalValues Signals() const override { return {{{"x", x_(0)}, {"t", t_}}}; }
  const std::vector<LawPhaseLog>& PhaseLogs() const override { return logs_; }
  StepperQuadratures Quadratures() const override {
    const double dt = t_ - reset_t_;
    return {b_.rates.energy * dt, b_.rates.work_input * dt, b_.rates.work_damping * dt,
            b_.rates.work_laws * dt};
  }
  TransientStatistics Statistics() const override { return statistics_; }
  const std::string& message() const override { return message_; }

  long calls = 0;
  int resets = 0;
  bool backwards = false;
  bool beyond_segment = false;

 private:
  void Update() {
    x_ = Eigen::VectorXd::Constant(1, b_.x(t_));
    v_ = Eigen::VectorXd::Constant(1, b_.v(t_));
  }

  FakeBehaviour b_;
  Excitation excitation_;
  double t_ = 0.0;
  double reset_t_ = 0.0;
  double segment_end_ = kInfinity;
  Eigen::VectorXd x_, v_;
  std::vector<LawPhaseLog> logs_;
  TransientStatistics statistics_;
  std::string message_;
};

// One DOF, M = 1 kg, C = 0, K = ω² N/m: x = A cos ωt has the constant energy ½ω²A².
TransientModel OneDof() {
  TransientModel model;
  model.model.mass = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  model.model.damping = Eigen::MatrixXd::Zero(1, 1).sparseView();
  model.model.stiffness = Eigen::MatrixXd::Constant(1, 1, kOmega * kOmega).sparseView();
  return model;
}

TransientOptions Options(int min_periods, int steady_periods, int max_periods) {
  TransientOptions options;
  options.min_periods = min_periods;
  options.steady_periods = steady_periods;
  options.max_periods = max_periods;
  options.samples_per_period = 16;
  return options;
}

FakeBehaviour Harmonic(double amplitude, double frequency) {
  FakeBehaviour b;
  b.x = [=](double t) { return amplitude * std::cos(frequency * t); };
  b.v = [=](double t) { return -amplitude * frequency * std::sin(frequency * t); };
  return b;
}

// x takes the value boundaries[k] over [kT, (k + 1)T) (the last one beyond), v = 0: period p
// then has the difference |b_p − b_{p−1}| / max(|b_{p−1}|, |b_p|) exactly.
FakeBehaviour Steps(std::vector<double> boundaries) {
  FakeBehaviour b;
  b.x = [boundaries](double t) {
    const auto k = static_cast<size_t>(std::floor(t / kPeriod + 1e-9));
    return boundaries[std::min(k, boundaries.size() - 1)];
  };
  b.v = [](double) { return 0.0; };
  return b;
}

struct Run {
  TransientResult result;
  const FakeStepper* fake = nullptr;
  std::unique_ptr<TransientDriver> driver;
};

Run SteadyRun(FakeBehaviour behaviour, const TransientOptions& options,
              const TransientModel& model) {
  Run run;
  auto stepper = std::make_unique<FakeStepper>(std::move(behaviour));
  run.fake = stepper.get();
  run.driver = std::make_unique<TransientDriver>(model, options, std::move(stepper));
  run.result = run.driver->RunToSteadyState(kOmega, {});
  CHECK_FALSE(run.fake->backwards);
  CHECK_FALSE(run.fake->beyond_segment);
  return run;
}

TEST_CASE("Transient driver: an exactly periodic stepper is steady at the first allowed period") {
  const TransientModel model = OneDof();
  // (min_periods, steady_periods) → periods: max of the two, every difference being zero.
  const int cases[][3] = {{4, 2, 4}, {1, 3, 3}, {5, 1, 5}, {1, 1, 1}};
  for (const auto& c : cases) {
    CAPTURE(c[0]);
    CAPTURE(c[1]);
    const Run run = SteadyRun(Harmonic(0.5, kOmega), Options(c[0], c[1], 100), model);
    const TransientResult& r = run.result;
    CHECK(r.status == TransientStatus::kPeriodic);
    CHECK(r.message.empty());
    CHECK(r.method == "fake");
    CHECK(r.periods == c[2]);
    CHECK(r.period_multiple == 0);
    REQUIRE(r.period_differences.size() == static_cast<size_t>(c[2]));
    for (double d : r.period_differences) CHECK(d < kRoundOff);
    CHECK(std::abs(r.t_end - c[2] * kPeriod) < kRoundOff);
  }
}

TEST_CASE("Transient driver: the recorded period, its energy balance and signals") {
  const TransientModel model = OneDof();
  constexpr double kAmplitude = 0.5;  // m
  FakeBehaviour behaviour = Harmonic(kAmplitude, kOmega);
  const double energy = 0.5 * kOmega * kOmega * kAmplitude * kAmplitude;  // J
  behaviour.rates = {energy, 3.0, 2.0, 1.0};
  const Run run = SteadyRun(behaviour, Options(4, 2, 100), model);
  const PeriodRecord& record = run.result.last_period;
  REQUIRE(run.result.periodic());
  CHECK(std::abs(record.t0 - 3 * kPeriod) < kRoundOff);
  CHECK(record.period == kPeriod);
  REQUIRE(record.t.size() == 16);
  for (int i = 0; i < 16; ++i) {
    CHECK(std::abs(record.t(i) - (3 + i / 16.0) * kPeriod) < kRoundOff);
    CHECK(std::abs(record.x(0, i) - kAmplitude * std::cos(kOmega * record.t(i))) < kRoundOff);
    CHECK(std::abs(record.v(0, i) + kAmplitude * kOmega * std::sin(kOmega * record.t(i))) <
          kRoundOff);
  }
  CHECK(std::abs(record.mean_energy - energy) < kRoundOff);
  CHECK(std::abs(record.work_input - 3.0 * kPeriod) < kRoundOff);
  CHECK(std::abs(record.work_damping - 2.0 * kPeriod) < kRoundOff);
  CHECK(std::abs(record.work_laws - 1.0 * kPeriod) < kRoundOff);
  CHECK(std::abs(record.energy_change) < kRoundOff);
  REQUIRE(record.law_signals.size() == 1);
  REQUIRE(record.law_signals[0].size() == 2);
  CHECK(record.law_signals[0][0].first == "x");
  CHECK(record.law_signals[0][1].first == "t");
  CHECK((record.law_signals[0][0].second - record.x.row(0).transpose()).cwiseAbs().maxCoeff() ==
        0.0);
  CHECK((record.law_signals[0][1].second - record.t).cwiseAbs().maxCoeff() == 0.0);
  REQUIRE(record.phases.size() == 1);
  CHECK(record.phases[0].type == "fake_law");
}

TEST_CASE("Transient driver: a difference counts only strictly below steady_tolerance") {
  const TransientModel model = OneDof();
  // Differences 0.5, (0.5 − 2⁻¹⁰)/(1 − 2⁻¹⁰), then exactly 2⁻¹⁰, then 0, 0, ...
  const std::vector<double> boundaries = {0.25, 0.5, 1 - std::ldexp(1.0, -10), 1.0};
  TransientOptions options = Options(1, 2, 100);
  options.steady_tolerance = std::ldexp(1.0, -10);
  Run run = SteadyRun(Steps(boundaries), options, model);
  REQUIRE(run.result.periodic());
  REQUIRE(run.result.period_differences.size() == 5);
  CHECK(run.result.period_differences[0] == 0.5);
  CHECK(run.result.period_differences[2] == options.steady_tolerance);
  CHECK(run.result.period_differences[3] == 0.0);
  // Period 3 sits exactly at the tolerance, so the two counting periods are 4 and 5.
  CHECK(run.result.periods == 5);

  // A tolerance a hair above lets period 3 count: steady at 4.
  options.steady_tolerance = std::ldexp(1.0, -10) * (1 + 1e-12);
  run = SteadyRun(Steps(boundaries), options, model);
  CHECK(run.result.periods == 4);
  // min_periods holds it back even when the differences counted long before.
  options.min_periods = 7;
  run = SteadyRun(Steps(boundaries), options, model);
  CHECK(run.result.periods == 7);
}

TEST_CASE("Transient driver: a settling stepper is steady after the expected count") {
  // x = cos ωt + 0.1^{t/T}: d_p ≈ 0.9·10^{1−p} relative to max|z| ≈ 1, below 1e-6 from p = 7
  // (0.9e-6) and not at p = 6 (0.9e-5): with two counting periods, steady at 8.
  const TransientModel model = OneDof();
  FakeBehaviour b;
  const double rate = std::log(0.1) / kPeriod;
  b.x = [=](double t) { return std::cos(kOmega * t) + std::exp(rate * t); };
  b.v = [=](double t) { return -kOmega * std::sin(kOmega * t) + rate * std::exp(rate * t); };
  TransientOptions options = Options(4, 2, 100);
  options.steady_tolerance = 1e-6;
  const Run run = SteadyRun(b, options, model);
  REQUIRE(run.result.periodic());
  CHECK(run.result.periods == 8);
  CHECK(run.result.period_differences[5] > options.steady_tolerance);
  CHECK(run.result.period_differences[6] < options.steady_tolerance);
}

TEST_CASE("Transient driver: kT-periodic orbits are found only when max_periods is reached") {
  const TransientModel model = OneDof();
  for (int k : {2, 3, 5}) {
    CAPTURE(k);
    const Run run = SteadyRun(Harmonic(1.0, kOmega / k), Options(1, 2, 12), model);
    CHECK(run.result.status == TransientStatus::kNotPeriodic);
    CHECK(run.result.periods == 12);  // not stopped early at the kT orbit
    CHECK(run.result.period_multiple == k);
    CHECK(run.result.message.find(std::to_string(k) + "T-periodic") != std::string::npos);
    for (double d : run.result.period_differences) CHECK(d > 0.1);
  }
  // 3T needs boundaries 3 periods before each of the last two: 4 periods, not 3.
  CHECK(SteadyRun(Harmonic(1.0, kOmega / 3), Options(1, 2, 4), model).result.period_multiple == 3);
  CHECK(SteadyRun(Harmonic(1.0, kOmega / 3), Options(1, 2, 3), model).result.period_multiple == 0);
  // Beyond max_period_multiple: not found.
  TransientOptions options = Options(1, 2, 12);
  options.max_period_multiple = 4;
  CHECK(SteadyRun(Harmonic(1.0, kOmega / 5), options, model).result.period_multiple == 0);
}

TEST_CASE("Transient driver: the kT search uses the same strict rule") {
  const TransientModel model = OneDof();
  // Boundaries 1, 2, 1, 2, 1, 2 − 2⁻¹⁰: the last differs from the one 2T before by 2⁻¹⁰, and
  // the largest |z| over those two periods is 2, so by exactly 2⁻¹¹.
  const std::vector<double> boundaries = {1, 2, 1, 2, 1, 2 - std::ldexp(1.0, -10)};
  TransientOptions options = Options(1, 2, 5);
  options.steady_tolerance = std::ldexp(1.0, -11);
  Run run = SteadyRun(Steps(boundaries), options, model);
  CHECK(run.result.status == TransientStatus::kNotPeriodic);
  CHECK(run.result.period_multiple == 0);
  options.steady_tolerance = std::ldexp(1.0, -11) * (1 + 1e-12);
  run = SteadyRun(Steps(boundaries), options, model);
  CHECK(run.result.period_multiple == 2);
}

TEST_CASE("Transient driver: a stepper that never settles runs to max_periods") {
  const TransientModel model = OneDof();
  FakeBehaviour b;
  b.x = [](double t) { return std::cos(kOmega * t) + t / kPeriod; };
  b.v = [](double t) { return -kOmega * std::sin(kOmega * t) + 1 / kPeriod; };
  b.rates = {1.0, 2.0, 0.0, 0.0};
  const Run run = SteadyRun(b, Options(4, 2, 70), model);
  CHECK(run.result.status == TransientStatus::kNotPeriodic);
  CHECK(std::string(ToString(run.result.status)) == "not_periodic");
  CHECK(run.result.periods == 70);
  CHECK(run.result.period_multiple == 0);
  CHECK(run.result.period_differences.size() == 70);
  CHECK(run.result.message == "no T-periodic steady state within 70 periods");
  // The quadratures restarted at periods 33 and 65; the last period's works are unaffected.
  CHECK(run.fake->resets == 2);
  CHECK(std::abs(run.result.last_period.work_input - 2.0 * kPeriod) < kRoundOff);
  CHECK(std::abs(run.result.last_period.mean_energy - 1.0) < kRoundOff);
}

TEST_CASE("Transient driver: failures give a failed status with the stepper's message") {
  const TransientModel model = OneDof();
  FakeBehaviour failing = Harmonic(1.0, kOmega);
  failing.fail_after = 2.5 * kPeriod;
  Run run = SteadyRun(failing, Options(4, 2, 100), model);
  CHECK(run.result.status == TransientStatus::kFailed);
  CHECK(run.result.message == "fake failure");
  CHECK(run.result.periods == 2);  // the two whole periods before it
  CHECK(run.result.t_end == 2.5 * kPeriod);

  FakeBehaviour refusing = Harmonic(1.0, kOmega);
  refusing.start_fails = true;
  run = SteadyRun(refusing, Options(4, 2, 100), model);
  CHECK(run.result.status == TransientStatus::kFailed);
  CHECK(run.result.message == "fake start failure");
  CHECK(run.result.periods == 0);
  CHECK(run.fake->calls == 0);

  FakeBehaviour slow = Harmonic(1.0, kOmega);
  slow.out_of_time_after = 1.5 * kPeriod;
  run = SteadyRun(slow, Options(4, 2, 100), model);
  CHECK(run.result.status == TransientStatus::kFailed);
  CHECK(run.result.message.find("wall-clock limit of 600 s reached at t = ") == 0);
  CHECK(run.result.periods == 1);

  // The driver's own clock: a limit shorter than any call.
  TransientOptions options = Options(4, 2, 100);
  options.max_seconds = 1e-9;
  run = SteadyRun(Harmonic(1.0, kOmega), options, model);
  CHECK(run.result.status == TransientStatus::kFailed);
  CHECK(run.result.message.find("wall-clock limit of 1e-09 s") == 0);
}

TEST_CASE("Transient driver: statistics are the stepper's totals over the whole run") {
  const TransientModel model = OneDof();
  FakeBehaviour b = Harmonic(1.0, kOmega);
  b.per_call = {2, 3, 1, 4, 1, 1, 1};  // steps, residuals, Jacobians, Newton, failures, events
  for (bool failing : {false, true}) {
    CAPTURE(failing);
    if (failing) b.fail_after = 3.55 * kPeriod;
    const Run run = SteadyRun(b, Options(5, 2, 100), model);
    const TransientStatistics& s = run.result.statistics;
    const long calls = run.fake->calls;
    // 16 samples per period: 15 advances to samples and one to the period's end.
    CHECK(calls == (failing ? 3 * 16 + 9 : 5 * 16));
    CHECK(s.steps == 2 * calls);
    CHECK(s.residual_evaluations == 3 * calls);
    CHECK(s.jacobian_evaluations == calls);
    CHECK(s.nonlinear_iterations == 4 * calls);
    CHECK(s.nonlinear_convergence_failures == calls);
    CHECK(s.error_test_failures == calls);
    CHECK(s.events == calls);
    CHECK(run.result.steps == s.steps);
    CHECK(run.result.events == s.events);
  }
}

TEST_CASE("Transient driver: chirp cycles, their frequency, amplitude and energy") {
  const TransientModel model = OneDof();
  TransientOptions options = Options(4, 2, 100);
  // Constant frequency: cycle k ends at 2πk/ω exactly; the samples fall on phases 2πi/N.
  {
    const Excitation chirp = Excitation::Chirp({}, kOmega, kOmega, 10.3 * kPeriod);
    FakeBehaviour b = Harmonic(0.5, kOmega);
    b.rates.energy = 0.125 * kOmega * kOmega;
    b.per_call.steps = 1;
    auto stepper = std::make_unique<FakeStepper>(b);
    const FakeStepper* fake = stepper.get();
    TransientDriver driver(model, options, std::move(stepper));
    const ChirpResult r = driver.RunChirp(chirp, 32);
    REQUIRE(r.status == TransientStatus::kPeriodic);
    CHECK(r.method == "fake");
    CHECK_FALSE(fake->backwards);
    CHECK_FALSE(fake->beyond_segment);
    REQUIRE(r.cycles.size() == 10);
    for (size_t k = 0; k < r.cycles.size(); ++k) {
      const ChirpCycle& c = r.cycles[k];
      CHECK(std::abs(c.t_start - k * kPeriod) < kRoundOff);
      CHECK(std::abs(c.t_end - (k + 1) * kPeriod) < kRoundOff);
      CHECK(std::abs(c.omega - kOmega) < kRoundOff);
      CHECK(std::abs(c.max_abs(0) - 0.5) < kRoundOff);
      CHECK(std::abs(c.mean_energy - 0.125 * kOmega * kOmega) < kRoundOff);
    }
    // To the end of the duration: 10 cycles of 32 samples, then the remaining 0.3 T.
    CHECK(fake->t() == 10.3 * kPeriod);
    CHECK(r.statistics.steps == 10 * 32 + 1);
    CHECK(r.steps == r.statistics.steps);
  }
  // A sweep: each cycle spans 2π of phase, its ω is 2π over its duration.
  {
    const Excitation chirp = Excitation::Chirp({}, 1.0, 3.0, 40.0);
    auto stepper = std::make_unique<FakeStepper>(Harmonic(1.0, 1.0));
    TransientDriver driver(model, options, std::move(stepper));
    const ChirpResult r = driver.RunChirp(chirp, 8);
    REQUIRE(r.status == TransientStatus::kPeriodic);
    // φ(40) = (1 + 3)/2 · 40 = 80 rad: 12 whole cycles.
    REQUIRE(r.cycles.size() == 12);
    for (size_t k = 0; k < r.cycles.size(); ++k) {
      CHECK(std::abs(chirp.Phase(r.cycles[k].t_end) - 2 * kPi * (k + 1)) < 1e-12);
      CHECK(r.cycles[k].omega ==
            doctest::Approx(2 * kPi / (r.cycles[k].t_end - r.cycles[k].t_start)));
    }
  }
}

TEST_CASE("Transient driver: input errors") {
  const TransientModel model = OneDof();
  TransientDriver driver(model, Options(4, 2, 100),
                         std::make_unique<FakeStepper>(Harmonic(1.0, kOmega)));
  CHECK_THROWS_WITH_AS(driver.RunToSteadyState(0.0, {}), doctest::Contains("validation.omega"),
                       InputError);
  CHECK_THROWS_WITH_AS(driver.RunToSteadyState(1.0, {Eigen::VectorXd::Zero(2), {}}),
                       doctest::Contains("validation.initial_state.x"), InputError);
  CHECK_THROWS_AS(driver.RunChirp(Excitation::Harmonic({}, 1.0), 8), InputError);
  CHECK_THROWS_AS(driver.RunChirp(Excitation::Chirp({}, 1.0, 2.0, 10.0), 0), InputError);
  TransientOptions bad = Options(4, 2, 100);
  bad.steady_periods = 0;
  CHECK_THROWS_WITH_AS(
      TransientDriver(model, bad, std::make_unique<FakeStepper>(Harmonic(1.0, kOmega))),
      doctest::Contains("validation.transient.steady_periods"), InputError);
}

}  // namespace
}  // namespace nfrc
