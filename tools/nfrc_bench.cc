// Benchmarks of the foundation (prints figures; asserts nothing):
//   1. the Duffing FRC with H = 7 (cases/duffing.json): wall time, points, Newton per point;
//   2. the friction oscillator FRC, N = 10, N_φ = 60 (cases/friction/frc_n10.json);
//   3. condensation of sparse chain models (10^4 and 10^5 DOFs) onto 2 DOFs with H = 20:
//      time per frequency (factorisation + Schur complement + ω-derivatives of all harmonics).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "core/condensation.h"
#include "tools/run_case.h"

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

void BenchCase(const std::string& name, int repeats) {
  const std::string path = std::string(NFRC_SOURCE_DIR) + "/cases/" + name;
  std::vector<double> times;
  nfrc::Branch branch;
  for (int r = 0; r < repeats; ++r) {
    nfrc::Case the_case = nfrc::LoadCase(path);
    const auto start = Clock::now();
    auto system = nfrc::MakeSystem(the_case);
    const Eigen::VectorXd guess = nfrc::StartingGuess(the_case, *system, nullptr);
    branch = nfrc::Trace(*system, the_case.continuation, nullptr, &guess);
    times.push_back(Seconds(start));
  }
  const auto& s = branch.summary;
  std::printf("%s: %s, %d points, %d folds, %d unknowns\n", name.c_str(),
              nfrc::ToString(s.reason), s.num_points, s.num_folds,
              static_cast<int>(branch.points.front().y.size()));
  std::printf("  wall time      %.2f ms (median of %d runs)\n", 1e3 * Median(times), repeats);
  std::printf("  per point      %.3f ms\n", 1e3 * Median(times) / s.num_points);
  std::printf("  Newton/point   %.2f (%d iterations, %d rejected steps)\n",
              static_cast<double>(s.total_newton_iterations) / s.num_points,
              s.total_newton_iterations, s.num_rejected_steps);
}

// Clamped chain of n unit masses and unit springs, 1 % stiffness-proportional damping.
nfrc::LinearModel Chain(int n) {
  std::vector<Eigen::Triplet<double>> k, m;
  for (int i = 0; i < n; ++i) {
    m.emplace_back(i, i, 1.0);
    k.emplace_back(i, i, i + 1 < n ? 2.0 : 1.0);
    if (i + 1 < n) {
      k.emplace_back(i, i + 1, -1.0);
      k.emplace_back(i + 1, i, -1.0);
    }
  }
  nfrc::LinearModel model;
  model.mass.resize(n, n);
  model.stiffness.resize(n, n);
  model.mass.setFromTriplets(m.begin(), m.end());
  model.stiffness.setFromTriplets(k.begin(), k.end());
  model.damping = 0.01 * model.stiffness;
  return model;
}

void BenchChain(int n, int frequencies) {
  const nfrc::HarmonicSet set(20, false);
  nfrc::Condensation condensation(Chain(n), {n / 2, n - 1}, set, {{n - 1, 1, 1.0, 0.0}},
                                  nfrc::Condensation::Method::kSparse);
  std::vector<double> times;
  for (int f = 0; f < frequencies; ++f) {
    const double omega = 1e-3 * (1.0 + 0.1 * f);  // below the chain's cut-off frequency 2
    const auto start = Clock::now();
    condensation.Update(omega);
    times.push_back(Seconds(start));
  }
  std::printf("sparse chain %6d DOFs -> 2 DOFs, H=20 (21 harmonics): %.1f ms per frequency "
              "(median of %d)\n", n, 1e3 * Median(times), frequencies);
}

}  // namespace

int main() {
  BenchCase("duffing.json", 5);
  BenchCase("friction/frc_n10.json", 3);
  BenchChain(10000, 5);
  BenchChain(100000, 5);
  return 0;
}
