#pragma once

#include <Eigen/Dense>
#include <map>
#include <memory>

#include "analysis/case.h"
#include "analysis/case_parameter.h"
#include "analysis/harmonic_system.h"

namespace nfrc {

// How ∂R/∂p is obtained.
enum class SensitivityMethod {
  kAffine,             // R is affine in p (forcing amplitudes, a cubic coefficient): a secant
                       // over a step of the parameter's own size is exact
  kCentralDifference,  // otherwise: (R(p + δ) − R(p − δ)) / 2δ
};

const char* ToString(SensitivityMethod method);

// The derivative of a case's harmonic-balance residual R(y, ω; p), and of its Jacobian R_y,
// with respect to a case field p, at fixed (y, ω): what continuation in p (fold and peak
// curves, ∂y/∂p = −R_y⁻¹ ∂R/∂p) needs. The systems at the values it evaluates are built once
// and cached (the last few), so repeated calls along a curve do not rebuild them.
class ParameterSensitivity {
 public:
  // `scale`: the parameter's typical size (e.g. max(|from|, |to|)), which sets the steps.
  ParameterSensitivity(const Case& the_case, const CaseParameter& parameter, double scale);

  SensitivityMethod method() const { return method_; }
  // The step of the secant or central difference at p.
  double Step(double p) const;

  // ∂R/∂p (and ∂R_y/∂p if `d_jacobian` is non-null) at (y, ω; p); false if a system cannot
  // be evaluated there. A case field the case rejects at p ± δ throws InputError.
  bool Evaluate(double p, const Eigen::VectorXd& y, double omega, Eigen::VectorXd* d_residual,
                Eigen::MatrixXd* d_jacobian = nullptr);

  // The system of the case with the field at p (cached).
  HarmonicSystem& System(double p);

 private:
  static constexpr size_t kCachedSystems = 6;

  const Case& case_;
  const CaseParameter& parameter_;
  double scale_;
  SensitivityMethod method_;
  std::map<double, std::unique_ptr<HarmonicSystem>> systems_;
};

}  // namespace nfrc
