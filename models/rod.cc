#include "models/rod.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace nfrc {

void RodParameters::Validate() const {
  if (elements < 1) throw std::invalid_argument("elements: must be at least 1");
  if (!(length > 0.0)) throw std::invalid_argument("length: must be positive");
  if (!(area > 0.0)) throw std::invalid_argument("area: must be positive");
  if (!(young > 0.0)) throw std::invalid_argument("young: must be positive");
  if (!(density > 0.0)) throw std::invalid_argument("density: must be positive");
}

LinearModel BuildRod(const RodParameters& p) {
  p.Validate();
  const int n = p.elements;
  const double l = p.length / n;
  const double m = p.density * p.area * l / 6.0;
  const double k = p.young * p.area / l;
  std::vector<Eigen::Triplet<double>> mass, stiffness;
  mass.reserve(4 * static_cast<size_t>(n));
  stiffness.reserve(4 * static_cast<size_t>(n));
  // Element e joins nodes e and e + 1; node 0 is clamped, so node i is DOF i − 1.
  for (int e = 0; e < n; ++e) {
    const int nodes[2] = {e - 1, e};
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        if (nodes[a] < 0 || nodes[b] < 0) continue;
        mass.emplace_back(nodes[a], nodes[b], m * (a == b ? 2.0 : 1.0));
        stiffness.emplace_back(nodes[a], nodes[b], k * (a == b ? 1.0 : -1.0));
      }
    }
  }
  LinearModel model;
  model.mass.resize(n, n);
  model.stiffness.resize(n, n);
  model.damping.resize(n, n);
  model.mass.setFromTriplets(mass.begin(), mass.end());
  model.stiffness.setFromTriplets(stiffness.begin(), stiffness.end());
  for (int i = 1; i < n; ++i) model.dof_names.push_back("node" + std::to_string(i));
  model.dof_names.push_back("end");
  return model;
}

}  // namespace nfrc
