#include "validation/transient_model.h"

#include <memory>
#include <stdexcept>
#include <utility>

#include "core/errors.h"
#include "validation/contact_friction_time_law.h"
#include "validation/contact_time_law.h"
#include "validation/friction_time_law.h"
#include "validation/jenkins_time_law.h"
#include "validation/spring_time_law.h"

namespace nfrc {
namespace {

// Whether row `dof` of a matrix has no nonzero entry.
bool RowIsZero(const Eigen::SparseMatrix<double>& matrix, int dof) {
  for (int j = 0; j < matrix.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, j); it; ++it) {
      if (it.row() == dof && it.value() != 0.0) return false;
    }
  }
  return true;
}

// The time-domain form of each law, one overload per specification: std::visit below makes
// the compiler require one for every law of the registry (nonlinearities/law_spec.h).
void AddTimeLaw(const CoulombFrictionSpec& friction, const std::string& path, TransientModel* out) {
  const int dof = friction.dof, other = friction.other;
  const bool massless = out->massless[dof] || (other >= 0 && out->massless[other]);
  // Sliding pins a massless, undamped slider to the spring force ∓μN (index 2): the integrator
  // differentiates that DOF's momentum row and the law's force becomes differential. A
  // damped massless DOF keeps its index-1 form (its row holds C v).
  auto undamped_massless = [&](int d) {
    return d >= 0 && out->massless[d] && RowIsZero(out->model.damping, d);
  };
  const FrictionParameters parameters = friction.Parameters();
  const bool differentiated = massless && IsExact(parameters.equality) &&
                              (undamped_massless(dof) || undamped_massless(other));
  try {
    auto time_law = std::make_unique<FrictionTimeLaw>(dof, other, parameters, massless);
    time_law->set_differentiated(differentiated);
    out->laws.push_back(std::move(time_law));
  } catch (const std::invalid_argument& e) {
    throw InputError(path + ".law: " + e.what());
  }
  out->law_paths.push_back(path);
}

void AddTimeLaw(const CubicSpringSpec& spring, const std::string& path, TransientModel* out) {
  out->laws.push_back(std::make_unique<SpringTimeLaw>(
      std::string(spring.kType), spring.dof, spring.other,
      std::vector<PolynomialSpring::Term>{{3, spring.coefficient}}));
  out->law_paths.push_back(path);
}

void AddTimeLaw(const PolynomialSpringSpec& spring, const std::string& path, TransientModel* out) {
  out->laws.push_back(std::make_unique<SpringTimeLaw>(std::string(spring.kType), spring.dof,
                                                      spring.other, spring.terms));
  out->law_paths.push_back(path);
}

void AddTimeLaw(const PenaltyContactSpec& penalty, const std::string& path, TransientModel* out) {
  out->laws.push_back(std::make_unique<ContactTimeLaw>(std::string(penalty.kType), penalty.geometry,
                                                       penalty.stiffness));
  out->law_paths.push_back(path);
}

// dlft_contact and lcp_contact: a flexible obstacle is a penalty spring of its stiffness in the
// time domain (the same solution set); a rigid one is a constraint for the explicit scheme.
void AddLagrangianContact(std::string_view type, const LagrangianContactSpec& contact,
                          const std::string& path, TransientModel* out) {
  if (contact.obstacle_stiffness > 0.0) {
    out->laws.push_back(std::make_unique<ContactTimeLaw>(std::string(type), contact.geometry,
                                                         contact.obstacle_stiffness));
    out->law_paths.push_back(path);
  } else {
    out->rigid_contacts.push_back(contact.geometry);
  }
}

void AddTimeLaw(const DlftContactSpec& spec, const std::string& path, TransientModel* out) {
  AddLagrangianContact(spec.kType, spec.contact, path, out);
}

void AddTimeLaw(const LcpContactSpec& spec, const std::string& path, TransientModel* out) {
  AddLagrangianContact(spec.kType, spec.contact, path, out);
}

// Signorini's law is exact in the time domain whatever its HBM formulation.
void AddTimeLaw(const EqualityContactSpec& spec, const std::string& path, TransientModel* out) {
  AddLagrangianContact(
      spec.kType, LagrangianContactSpec{spec.geometry, spec.obstacle_stiffness, 0.0}, path, out);
}

// DLFT friction is Coulomb's law in the time domain: the exact friction law (min_max).
void AddTimeLaw(const DlftFrictionSpec& spec, const std::string& path, TransientModel* out) {
  CoulombFrictionSpec coulomb;
  coulomb.dof = spec.dof;
  coulomb.other = spec.other;
  coulomb.mu = spec.mu;
  coulomb.normal_load = spec.normal_load;
  AddTimeLaw(coulomb, path, out);
}

// A hysteretic law: the slider's force is a differential own unknown (JenkinsTimeLaw).
void AddTimeLaw(const JenkinsSpec& spec, const std::string& path, TransientModel* out) {
  try {
    auto law = std::make_unique<JenkinsTimeLaw>(spec.dof, spec.other, spec.stiffness,
                                                spec.mu * spec.normal_load);
    // A massless DOF's v is algebraic: the relative velocity is read from ẋ.
    law->set_massless(out->massless[spec.dof] || (spec.other >= 0 && out->massless[spec.other]));
    out->laws.push_back(std::move(law));
  } catch (const std::invalid_argument& e) {
    throw InputError(path + "." + e.what());
  }
  out->law_paths.push_back(path);
}

// Contact with friction against a flexible obstacle: its penalty spring (the same solution set
// as the condensed obstacle of the harmonic law) and an exact Coulomb slider under its force.
// A preload is the model's harmonic-0 forcing, as in the harmonic law.
void AddTimeLaw(const ContactFrictionSpec& spec, const std::string& path, TransientModel* out) {
  try {
    auto law = std::make_unique<ContactFrictionTimeLaw>(spec.geometry, spec.obstacle_stiffness,
                                                        spec.tangent_dof, spec.tangent_other,
                                                        spec.mu, /*preload=*/0.0);
    bool massless = false;
    for (int dof : LawDofs(spec)) massless = massless || out->massless[dof];
    law->set_massless(massless);
    out->laws.push_back(std::move(law));
  } catch (const std::invalid_argument& e) {
    throw InputError(path + "." + e.what());
  }
  out->law_paths.push_back(path);
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

TransientModel MakeTransientModel(const ModelDefinition& model, const std::vector<LawSpec>& laws) {
  TransientModel out;
  out.model = model.model;
  out.forcing = model.forcing;
  out.massless = MasslessDofs(model.model.mass);
  for (size_t i = 0; i < laws.size(); ++i) {
    const std::string path = "nonlinearities[" + std::to_string(i) + "]";
    std::visit([&](const auto& spec) { AddTimeLaw(spec, path, &out); }, laws[i]);
    // A rigid contact is a constraint, not a law.
    out.law_sources.resize(out.laws.size(), static_cast<int>(i));
  }
  return out;
}

}  // namespace nfrc
