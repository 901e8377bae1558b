#include "nonlinearities/friction_equality.h"

#include <cmath>
#include <numbers>

namespace nfrc {

bool ParseFrictionEquality(const std::string& name, FrictionEquality* equality) {
  static const struct {
    const char* name;
    FrictionEquality value;
  } kNames[] = {{"min_max", FrictionEquality::kMinMax},
                {"hueber", FrictionEquality::kHueber},
                {"tanh", FrictionEquality::kTanh},
                {"arctan", FrictionEquality::kArctan},
                {"piecewise_linear", FrictionEquality::kPiecewiseLinear},
                {"sign", FrictionEquality::kSign}};
  for (const auto& entry : kNames) {
    if (name == entry.name) {
      *equality = entry.value;
      return true;
    }
  }
  return false;
}

const char* ToString(FrictionEquality equality) {
  switch (equality) {
    case FrictionEquality::kMinMax:
      return "min_max";
    case FrictionEquality::kHueber:
      return "hueber";
    case FrictionEquality::kTanh:
      return "tanh";
    case FrictionEquality::kArctan:
      return "arctan";
    case FrictionEquality::kPiecewiseLinear:
      return "piecewise_linear";
    case FrictionEquality::kSign:
      return "sign";
  }
  return "unknown";
}

bool IsExact(FrictionEquality equality) {
  return equality == FrictionEquality::kMinMax || equality == FrictionEquality::kHueber;
}

bool HasStickBranch(FrictionEquality equality) {
  return IsExact(equality) || equality == FrictionEquality::kPiecewiseLinear;
}

bool OnStickBranch(const FrictionParameters& p, double v, double r) {
  switch (p.equality) {
    case FrictionEquality::kMinMax:
      return p.rho * (r - p.limit) <= v && v <= p.rho * (r + p.limit);
    case FrictionEquality::kHueber:
      return std::abs(r - p.rho * v) <= p.limit;
    case FrictionEquality::kPiecewiseLinear:
      return std::abs(v) <= p.delta;
    default:
      return false;
  }
}

FrictionResidual EvaluateFrictionEquality(const FrictionParameters& p, double v, double r) {
  const double limit = p.limit;
  FrictionResidual out;
  switch (p.equality) {
    case FrictionEquality::kMinMax: {
      // Branches: negative sliding (r = +μN), positive sliding (r = −μN), sticking (v = 0).
      if (p.rho * (r + limit) - v < 0.0) {
        out = {p.rho * (r + limit), 0.0, p.rho, p.rho};
      } else if (p.rho * (r - limit) - v > 0.0) {
        out = {p.rho * (r - limit), 0.0, p.rho, -p.rho};
      } else {
        out = {v, 1.0, 0.0, 0.0};
      }
      break;
    }
    case FrictionEquality::kHueber: {
      const double trial = r - p.rho * v;
      if (std::abs(trial) <= limit) {
        out = {limit * p.rho * v, limit * p.rho, 0.0, p.rho * v};
      } else {
        const double s = trial > 0.0 ? 1.0 : -1.0;
        out = {r * std::abs(trial) - limit * trial, -p.rho * r * s + limit * p.rho,
               std::abs(trial) + r * s - limit, -trial};
      }
      break;
    }
    case FrictionEquality::kTanh: {
      const double t = std::tanh(p.alpha * v);
      out = {r + limit * t, limit * p.alpha * (1.0 - t * t), 1.0, t};
      break;
    }
    case FrictionEquality::kArctan: {
      const double scale = 2.0 / std::numbers::pi;
      out = {r + limit * scale * std::atan(p.alpha * v),
             limit * scale * p.alpha / (1.0 + p.alpha * p.alpha * v * v), 1.0,
             scale * std::atan(p.alpha * v)};
      break;
    }
    case FrictionEquality::kPiecewiseLinear: {
      if (v > p.delta) {
        out = {r + limit, 0.0, 1.0, 1.0};
      } else if (v < -p.delta) {
        out = {r - limit, 0.0, 1.0, -1.0};
      } else {
        out = {r + limit * v / p.delta, limit / p.delta, 1.0, v / p.delta};
      }
      break;
    }
    case FrictionEquality::kSign: {
      const double s = v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0);
      out = {r + limit * s, 0.0, 1.0, s};
      break;
    }
  }
  return out;
}

}  // namespace nfrc
