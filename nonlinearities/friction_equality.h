#pragma once

#include <string>

namespace nfrc {

// Coulomb's law for a sliding velocity v and friction force r (acting on the slider),
// |r| ≤ μN, written as one equality Ψ(v, r) = 0 (Legrand & Pierre 2024, Sections 2–3), or
// an approximation of it. Every form is piecewise smooth; Derivatives gives the active
// branch's partial derivatives, used for the semismooth Newton Jacobian.
enum class FrictionEquality {
  kMinMax,  // v + min(0, ρ(r + μN) − v) + max(0, ρ(r − μN) − v)   (exact, default)
  kHueber,  // r·max(μN, |r − ρv|) − μN(r − ρv)                     (exact)
  kTanh,    // r + μN tanh(αv)                                      (regularised)
  kArctan,  // r + μN (2/π) arctan(αv)                              (regularised)
  kPiecewiseLinear,  // r = −μN v/δ for |v| ≤ δ, ∓μN beyond                  (approximation)
  kSign,             // r + μN sign(v)                                       (approximation)
};

// Case-file names: "min_max", "hueber", "tanh", "arctan", "piecewise_linear", "sign".
// Returns false for an unknown name.
bool ParseFrictionEquality(const std::string& name, FrictionEquality* equality);
const char* ToString(FrictionEquality equality);
// True for the laws that describe sticking exactly (min_max, hueber).
bool IsExact(FrictionEquality equality);

struct FrictionParameters {
  FrictionEquality equality = FrictionEquality::kMinMax;
  double limit = 0.0;  // μN, force units
  double rho = 1.0;    // ρ of the exact laws, velocity / force
  double alpha = 0.0;  // α of tanh and arctan, 1 / velocity
  double delta = 0.0;  // δ of the piecewise-linear law, velocity
};

// Ψ(v, r) and its partial derivatives on the active branch, including the one in the limit
// μN (for a normal load that varies, as in contact with friction).
struct FrictionResidual {
  double value = 0.0;
  double d_velocity = 0.0;
  double d_force = 0.0;
  double d_limit = 0.0;
};

// Whether the sample (v, r) lies on the law's sticking branch: the stick branch of the exact
// laws, the viscous band |v| ≤ δ of the piecewise-linear law; never for the others, which
// have no sticking.
bool OnStickBranch(const FrictionParameters& parameters, double velocity, double force);
bool HasStickBranch(FrictionEquality equality);

FrictionResidual EvaluateFrictionEquality(const FrictionParameters& parameters, double velocity,
                                          double force);

}  // namespace nfrc
