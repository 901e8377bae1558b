#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/linear_model.h"
#include "nonlinearities/contact_geometry.h"
#include "nonlinearities/law_spec.h"
#include "validation/time_law.h"

namespace nfrc {

// What the transient integrators integrate: the full (uncondensed) linear model, its forcing
// terms and the time-domain laws. Rigid unilateral contacts are kept apart: they have no
// time-domain force law and only the explicit Lagrange-multiplier scheme handles them.
struct TransientModel {
  LinearModel model;
  std::vector<ForcingTerm> forcing;
  std::vector<std::unique_ptr<TimeLaw>> laws;
  std::vector<std::string> law_paths;  // "nonlinearities[i]" of each law, for messages
  std::vector<int> law_sources;        // i of each law: the harmonic law it stands for
  std::vector<ContactGeometry> rigid_contacts;
  // DOFs with no mass: zero row and column in M (their v is algebraic in the DAE).
  std::vector<bool> massless;

  int num_dofs() const { return model.num_dofs(); }
};

// The time-domain form of every law of a case: one overload per law specification, so a
// law without one does not compile. Rigid contacts (dlft_contact or lcp_contact without
// obstacle_stiffness) go to rigid_contacts. Throws InputError naming "nonlinearities[i]" for
// a bad law, and naming "model.M" for a massless DOF whose mass row or column is not
// entirely zero.
TransientModel MakeTransientModel(const ModelDefinition& model, const std::vector<LawSpec>& laws);

}  // namespace nfrc
