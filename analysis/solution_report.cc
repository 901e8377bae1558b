#include "analysis/solution_report.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace nfrc {

Eigen::VectorXd Angles(int num_samples) {
  Eigen::VectorXd theta(num_samples);
  for (int j = 0; j < num_samples; ++j) theta(j) = 2.0 * std::numbers::pi * j / num_samples;
  return theta;
}

SolutionReporter::SolutionReporter(HarmonicSystem& system, std::vector<int> output_dofs,
                                   std::vector<std::string> output_names)
    : system_(system),
      output_dofs_(std::move(output_dofs)),
      output_names_(std::move(output_names)),
      analyzer_(system, output_dofs_) {}

SolutionMeasures SolutionReporter::Measure(const Eigen::VectorXd& y, double omega) {
  SolutionMeasures m;
  m.response = analyzer_.Measure(y, omega);
  for (size_t i = 0; i < system_.laws().size(); ++i) {
    const auto& law = *system_.laws()[i];
    const NonlinearityContext& ctx = system_.context(static_cast<int>(i));
    LawReport report = law.Report(ctx, y, omega, analyzer_.fine());
    m.laws.push_back(std::move(report.diagnostics));
    const LawSummary& summary = report.summary;
    if (summary.min_gap) m.min_gap = std::min(m.min_gap.value_or(INFINITY), *summary.min_gap);
    if (summary.min_force) {
      m.min_force = std::min(m.min_force.value_or(INFINITY), *summary.min_force);
    }
  }
  return m;
}

SolutionSignals SolutionReporter::Signals(const Eigen::VectorXd& y, double omega) {
  SolutionSignals s;
  s.omega = omega;
  s.y = y;
  s.measures = Measure(y, omega);
  const FourierTransform& fine = analyzer_.fine();
  s.fine.names = {"theta", "t"};
  s.fine.columns = {Angles(fine.harmonic_set().num_samples())};
  s.fine.columns.push_back(s.fine.columns[0] / omega);
  const Eigen::MatrixXd& d = system_.fourier().DerivativeMatrix();
  std::vector<Eigen::VectorXd> coefficients;
  for (size_t i = 0; i < output_dofs_.size(); ++i) {
    coefficients.push_back(system_.DofCoefficients(y, omega, output_dofs_[i]));
    s.fine.names.push_back("x_" + output_names_[i]);
    s.fine.columns.push_back(fine.ToTime(coefficients.back()).col(0));
    s.fine.names.push_back("v_" + output_names_[i]);
    s.fine.columns.push_back(fine.ToTime(omega * (d * coefficients.back())).col(0));
  }
  for (size_t i = 0; i < system_.laws().size(); ++i) {
    const auto& law = system_.laws()[i];
    for (LawSignal& signal : law->Signals(system_.context(static_cast<int>(i)), y, omega, fine)) {
      s.fine.names.push_back("law" + std::to_string(i) + "_" + signal.name);
      s.fine.columns.push_back(std::move(signal.samples));
    }
  }

  // The laws' own samples (N_t, before truncation), when they have any.
  const FourierTransform& coarse = system_.fourier();
  SignalTable raw;
  raw.names = {"theta", "t"};
  raw.columns = {Angles(coarse.harmonic_set().num_samples())};
  raw.columns.push_back(raw.columns[0] / omega);
  for (size_t i = 0; i < output_dofs_.size(); ++i) {
    raw.names.push_back("x_" + output_names_[i]);
    raw.columns.push_back(coarse.ToTime(coefficients[i]).col(0));
  }
  const size_t num_fixed = raw.columns.size();
  for (size_t i = 0; i < system_.laws().size(); ++i) {
    const auto& law = system_.laws()[i];
    for (LawSignal& signal : law->RawSamples(system_.context(static_cast<int>(i)), y, omega)) {
      raw.names.push_back("law" + std::to_string(i) + "_" + signal.name);
      raw.columns.push_back(std::move(signal.samples));
    }
  }
  if (raw.columns.size() > num_fixed) s.samples = std::move(raw);
  return s;
}

}  // namespace nfrc
