#include "validation/transient_model.h"

#include <map>
#include <memory>
#include <stdexcept>
#include <utility>

#include "core/input_fields.h"
#include "nonlinearities/coulomb_friction.h"
#include "nonlinearities/dlft_contact.h"
#include "nonlinearities/lcp_contact.h"
#include "nonlinearities/penalty_contact.h"
#include "nonlinearities/polynomial_spring.h"
#include "validation/contact_time_law.h"
#include "validation/friction_time_law.h"
#include "validation/spring_time_law.h"

namespace nfrc {
namespace {

// Adds the time-domain form of one harmonic law to `out`; `path` names it in messages.
using TimeLawFactory = void (*)(const Nonlinearity& law, const std::string& path,
                                TransientModel* out);

// Whether row `dof` of a matrix has no nonzero entry.
bool RowIsZero(const Eigen::SparseMatrix<double>& matrix, int dof) {
  for (int j = 0; j < matrix.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, j); it; ++it) {
      if (it.row() == dof && it.value() != 0.0) return false;
    }
  }
  return true;
}

void AddFriction(const Nonlinearity& law, const std::string& path, TransientModel* out) {
  const auto& friction = dynamic_cast<const CoulombFriction&>(law);
  const int dof = friction.dof(), other = friction.other();
  const bool massless = out->massless[dof] || (other >= 0 && out->massless[other]);
  // Sliding pins a massless, undamped slider to the spring force ∓μN (index 2): the integrator
  // differentiates that DOF's momentum row and the law's force becomes differential. A
  // damped massless DOF keeps its index-1 form (its row holds C v).
  auto undamped_massless = [&](int d) {
    return d >= 0 && out->massless[d] && RowIsZero(out->model.damping, d);
  };
  const bool differentiated = massless && IsExact(friction.parameters().equality) &&
                              (undamped_massless(dof) || undamped_massless(other));
  try {
    auto time_law = std::make_unique<FrictionTimeLaw>(dof, other, friction.parameters(), massless);
    time_law->set_differentiated(differentiated);
    out->laws.push_back(std::move(time_law));
  } catch (const std::invalid_argument& e) {
    throw InputError(path + ".law: " + e.what());
  }
  out->law_paths.push_back(path);
}

void AddSpring(const Nonlinearity& law, const std::string& path, TransientModel* out) {
  const auto& spring = dynamic_cast<const PolynomialSpring&>(law);
  out->laws.push_back(
      std::make_unique<SpringTimeLaw>(spring.type(), spring.dof(), spring.other(), spring.terms()));
  out->law_paths.push_back(path);
}

void AddPenalty(const Nonlinearity& law, const std::string& path, TransientModel* out) {
  const auto& penalty = dynamic_cast<const PenaltyContact&>(law);
  out->laws.push_back(
      std::make_unique<ContactTimeLaw>(penalty.type(), penalty.geometry(), penalty.stiffness()));
  out->law_paths.push_back(path);
}

// dlft_contact and lcp_contact: a flexible obstacle is a penalty spring of its stiffness in the
// time domain (the same solution set); a rigid one is a constraint for the explicit scheme.
template <typename Law>
void AddLagrangianContact(const Nonlinearity& law, const std::string& path, TransientModel* out) {
  const auto& contact = dynamic_cast<const Law&>(law);
  if (contact.obstacle_stiffness() > 0.0) {
    out->laws.push_back(std::make_unique<ContactTimeLaw>(contact.type(), contact.geometry(),
                                                         contact.obstacle_stiffness()));
    out->law_paths.push_back(path);
  } else {
    out->rigid_contacts.push_back(contact.geometry());
  }
}

// Case-file "type" → time-domain form. Adding a law with a time-domain form adds one line.
const std::map<std::string, TimeLawFactory>& TimeLawRegistry() {
  static const std::map<std::string, TimeLawFactory> registry = {
      {"coulomb_friction", &AddFriction},
      {"cubic_spring", &AddSpring},
      {"dlft_contact", &AddLagrangianContact<DlftContact>},
      {"lcp_contact", &AddLagrangianContact<LcpContact>},
      {"penalty_contact", &AddPenalty},
      {"polynomial_spring", &AddSpring},
  };
  return registry;
}

// A DOF is massless when its whole row and column of M vanish; a zero diagonal with coupling
// terms would make the DAE's index depend on the mass matrix's structure, which is refused.
std::vector<bool> MasslessDofs(const Eigen::SparseMatrix<double>& mass) {
  const int n = static_cast<int>(mass.rows());
  std::vector<bool> diagonal_zero(n, true), row_zero(n, true), column_zero(n, true);
  for (int j = 0; j < mass.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(mass, j); it; ++it) {
      if (it.value() == 0.0) continue;
      row_zero[it.row()] = false;
      column_zero[it.col()] = false;
      if (it.row() == it.col()) diagonal_zero[it.row()] = false;
    }
  }
  std::vector<bool> massless(n, false);
  for (int i = 0; i < n; ++i) {
    if (diagonal_zero[i] && !(row_zero[i] && column_zero[i])) {
      throw InputError("model.M: DOF " + std::to_string(i) +
                       " has no mass but is coupled to others through M; the transient "
                       "integration needs a massless DOF's whole row and column to be zero");
    }
    massless[i] = diagonal_zero[i];
  }
  return massless;
}

}  // namespace

TransientModel MakeTransientModel(const LinearModel& model, const std::vector<ForcingTerm>& forcing,
                                  const std::vector<std::unique_ptr<Nonlinearity>>& laws) {
  TransientModel out;
  out.model = model;
  out.forcing = forcing;
  out.massless = MasslessDofs(model.mass);
  const auto& registry = TimeLawRegistry();
  for (size_t i = 0; i < laws.size(); ++i) {
    const std::string path = "nonlinearities[" + std::to_string(i) + "]";
    const auto found = registry.find(laws[i]->type());
    if (found == registry.end()) {
      throw InputError(path + ".type: \"" + laws[i]->type() +
                       "\" has no time-domain form for the transient validation");
    }
    found->second(*laws[i], path, &out);
  }
  return out;
}

}  // namespace nfrc
