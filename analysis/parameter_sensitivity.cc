#include "analysis/parameter_sensitivity.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <variant>

namespace nfrc {
namespace {

// Relative step of the central difference: near ε^(1/3) ≈ 6e-6, where its truncation (δ²)
// and rounding (ε/δ) errors balance.
constexpr double kCentralStep = 1e-5;

bool IsAffine(const Case& the_case, const CaseParameter& parameter) {
  if (parameter.IsLinear()) return true;
  // k₃u³ is linear in k₃; the other laws' fields enter through a projection, a penalty or a
  // complementarity, piecewise at best.
  const int law = parameter.LawIndex();
  return law >= 0 && std::holds_alternative<CubicSpringSpec>(the_case.laws[law]) &&
         parameter.field() == "coefficient";
}

}  // namespace

const char* ToString(SensitivityMethod method) {
  switch (method) {
    case SensitivityMethod::kAffine:
      return "affine";
    case SensitivityMethod::kCentralDifference:
      return "central_difference";
  }
  return "unknown";
}

ParameterSensitivity::ParameterSensitivity(const Case& the_case, const CaseParameter& parameter,
                                           double scale)
    : case_(the_case),
      parameter_(parameter),
      scale_(scale > 0.0 ? scale : 1.0),
      method_(IsAffine(the_case, parameter) ? SensitivityMethod::kAffine
                                            : SensitivityMethod::kCentralDifference) {}

double ParameterSensitivity::Step(double p) const {
  const double size = std::max(std::abs(p), scale_);
  return method_ == SensitivityMethod::kAffine ? size : kCentralStep * size;
}

bool ParameterSensitivity::Evaluate(double p, const Eigen::VectorXd& y, double omega,
                                    Eigen::VectorXd* d_residual, Eigen::MatrixXd* d_jacobian) {
  const double step = Step(p);
  // Affine: a forward secant from p (its system is the one in use); otherwise central.
  const double lo = method_ == SensitivityMethod::kAffine ? p : p - step;
  const double hi = p + step;
  Eigen::VectorXd r_lo, r_hi;
  Eigen::MatrixXd j_lo, j_hi;
  Eigen::MatrixXd* want_lo = d_jacobian != nullptr ? &j_lo : nullptr;
  Eigen::MatrixXd* want_hi = d_jacobian != nullptr ? &j_hi : nullptr;
  if (!System(hi).Evaluate(y, omega, &r_hi, want_hi, nullptr) ||
      !System(lo).Evaluate(y, omega, &r_lo, want_lo, nullptr)) {
    return false;
  }
  *d_residual = (r_hi - r_lo) / (hi - lo);
  if (d_jacobian != nullptr) *d_jacobian = (j_hi - j_lo) / (hi - lo);
  return true;
}

HarmonicSystem& ParameterSensitivity::System(double p) {
  auto found = systems_.find(p);
  if (found != systems_.end()) return *found->second;
  // Systems at a point's p and its p ± δ are what the next evaluations need.
  if (systems_.size() >= kCachedSystems) systems_.clear();
  auto built = BuildSystem(parameter_.With(case_, p));
  HarmonicSystem& system = *built;
  systems_.emplace(p, std::move(built));
  return system;
}

}  // namespace nfrc
