#pragma once

#include "core/linear_model.h"

namespace nfrc {

// A 1-D elastic rod in axial vibration, clamped at x = 0, meshed by `elements` equal linear
// elements with consistent matrices Me = ρAl/6 [[2, 1], [1, 2]], Ke = EA/l [[1, −1], [−1, 1]]
// (SI units). Its DOFs are the free nodes 1..n; they are named "node1".."node<n−1>" and the
// free end "end". Damping is left zero (added by the caller).
struct RodParameters {
  int elements = 20;
  double length = 0.0;   // m
  double area = 0.0;     // m²
  double young = 0.0;    // Pa
  double density = 0.0;  // kg/m³

  // Throws std::invalid_argument naming the parameter if one is not positive.
  void Validate() const;
};

LinearModel BuildRod(const RodParameters& parameters);

}  // namespace nfrc
