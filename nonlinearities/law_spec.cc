#include "nonlinearities/law_spec.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/errors.h"

namespace nfrc {
namespace {

[[noreturn]] void Fail(const std::string& field, const std::string& problem) {
  throw InputError(field + ": " + problem);
}

void CheckDofs(int dof, int other, const LinearModel& model) {
  const int n = model.num_dofs();
  if (dof < 0 || dof >= n) Fail("dof", "DOF " + std::to_string(dof) + " is not in the model");
  if (other >= n) Fail("other", "DOF " + std::to_string(other) + " is not in the model");
  if (dof == other) Fail("other", "must differ from dof");
}

void CheckGeometry(const ContactGeometry& geometry, const LinearModel& model) {
  CheckDofs(geometry.dof, geometry.other, model);
  if (geometry.direction != 1.0 && geometry.direction != -1.0) {
    Fail("direction", "must be 1 (obstacle on the positive side) or -1");
  }
  if (!std::isfinite(geometry.gap)) Fail("gap", "must be finite");
  for (const ContactGeometry::GapHarmonic& h : geometry.gap_harmonics) {
    if (h.harmonic < 1) Fail("gap.harmonics", "harmonic must be at least 1 (use constant for 0)");
    if (!std::isfinite(h.cos) || !std::isfinite(h.sin)) Fail("gap.harmonics", "must be finite");
  }
}

// The geometry and obstacle of a Lagrangian or equality-based contact, and its force scale
// (`scale_field`: DLFT's "epsilon", the equality laws' "rho"; N/m, 0 = default).
void CheckLagrangian(const LagrangianContactSpec& contact, const LinearModel& model,
                     const char* scale_field = "epsilon") {
  CheckGeometry(contact.geometry, model);
  if (!(contact.obstacle_stiffness >= 0.0) || !std::isfinite(contact.obstacle_stiffness)) {
    Fail("obstacle_stiffness", "must be finite and > 0 (N/m; omit it for a rigid obstacle)");
  }
  if (contact.obstacle_stiffness > 0.0 && contact.geometry.other >= 0) {
    Fail("obstacle_stiffness", "not allowed with other: the second body is then part of the model");
  }
  if (!(contact.epsilon >= 0.0) || !std::isfinite(contact.epsilon)) {
    Fail(scale_field, "must be finite and > 0 (N/m; omit it for the default)");
  }
}

// The largest |diagonal entry| of `matrix` over `dofs`, else over every DOF; 0 if none.
double DiagonalScale(const Eigen::SparseMatrix<double>& matrix, const std::vector<int>& dofs) {
  double scale = 0.0;
  for (int dof : dofs) scale = std::max(scale, std::abs(matrix.coeff(dof, dof)));
  if (scale > 0.0) return scale;
  for (int dof = 0; dof < matrix.rows(); ++dof) {
    scale = std::max(scale, std::abs(matrix.coeff(dof, dof)));
  }
  return scale;
}

std::string Text(double value) {
  std::ostringstream text;
  text.precision(3);
  text << value;
  return text.str();
}

// The slip force μN must be a number: μ and N each finite can overflow together.
void CheckSlipForce(double mu, double normal_load) {
  if (!std::isfinite(mu * normal_load)) {
    Fail("normal_load", "mu * normal_load overflows (mu " + Text(mu) + ")");
  }
}

// InputError naming `field` unless `value` is 0 (a default) or lies within
// kUsefulParameterRatio either way of `reference` (skipped where the reference is 0).
void CheckScale(const char* field, double value, double reference, const char* unit,
                const char* what) {
  if (value == 0.0 || !(reference > 0.0)) return;
  const double low = reference / kUsefulParameterRatio;
  const double high = reference * kUsefulParameterRatio;
  if (value < low || value > high) {
    Fail(field,
         Text(value) + " " + unit + " lies outside its useful range [" + Text(low) + ", " +
             Text(high) + "] " + unit + ", " + Text(kUsefulParameterRatio) +
             " times either way of " + what + " (" + Text(reference) +
             "): beyond it the "
             "law's terms swamp the structure's, or vanish against them, in double precision");
  }
}

}  // namespace

void CheckLawRanges(const LawSpec& spec, const LinearModel& model) {
  const std::vector<int> dofs = LawDofs(spec);
  const double stiffness = DiagonalScale(model.stiffness, dofs);
  const double mass = DiagonalScale(model.mass, dofs);
  constexpr const char* kStiffness = "the model's stiffness at the law's DOFs";
  auto stiff = [&](const char* field, double value) {
    CheckScale(field, value, stiffness, "N/m", kStiffness);
  };
  // ρ of a friction equality (velocity per force): 1/√(k m), the admittance of the DOF.
  auto admittance = [&](const char* field, double value) {
    if (!(mass > 0.0) || !(stiffness > 0.0)) return;
    CheckScale(field, value, 1.0 / std::sqrt(stiffness * mass), "(m/s)/N",
               "1/sqrt(k m) at the law's DOFs");
  };
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, JenkinsSpec> || std::is_same_v<T, PenaltyContactSpec>) {
          stiff("stiffness", s.stiffness);
        } else if constexpr (std::is_same_v<T, DlftFrictionSpec>) {
          stiff("epsilon", s.epsilon);
        } else if constexpr (std::is_same_v<T, DlftContactSpec> ||
                             std::is_same_v<T, LcpContactSpec>) {
          stiff("epsilon", s.contact.epsilon);
          stiff("obstacle_stiffness", s.contact.obstacle_stiffness);
        } else if constexpr (std::is_same_v<T, EqualityContactSpec>) {
          stiff("rho", s.rho);
          stiff("obstacle_stiffness", s.obstacle_stiffness);
        } else if constexpr (std::is_same_v<T, ContactFrictionSpec>) {
          stiff("rho", s.rho);
          stiff("obstacle_stiffness", s.obstacle_stiffness);
          admittance("friction_rho", s.friction_rho);
        } else if constexpr (std::is_same_v<T, CoulombFrictionSpec>) {
          if (s.law == FrictionEquality::kMinMax || s.law == FrictionEquality::kHueber) {
            admittance("rho", s.rho);
          }
        }
      },
      spec);
}

void CubicSpringSpec::Validate(const LinearModel& model) const {
  CheckDofs(dof, other, model);
  if (!std::isfinite(coefficient)) Fail("coefficient", "must be finite");
}

void PolynomialSpringSpec::Validate(const LinearModel& model) const {
  CheckDofs(dof, other, model);
  if (terms.empty()) Fail("terms", "expected a non-empty list");
  for (const PolynomialSpring::Term& term : terms) {
    if (term.power < 2) Fail("terms", "power must be at least 2 (linear terms belong in K)");
    if (!std::isfinite(term.coefficient)) Fail("terms", "coefficient must be finite");
  }
}

FrictionParameters CoulombFrictionSpec::Parameters() const {
  FrictionParameters parameters;
  parameters.equality = law;
  parameters.limit = mu * normal_load;
  parameters.rho = rho;
  parameters.alpha = alpha;
  parameters.delta = delta;
  return parameters;
}

void CoulombFrictionSpec::Validate(const LinearModel& model) const {
  CheckDofs(dof, other, model);
  if (!(mu >= 0.0) || !std::isfinite(mu)) Fail("mu", "must be non-negative");
  if (!(normal_load >= 0.0) || !std::isfinite(normal_load)) {
    Fail("normal_load", "must be non-negative");
  }
  CheckSlipForce(mu, normal_load);
  auto positive = [](const char* key, double value) {
    if (!(value > 0.0) || !std::isfinite(value)) Fail(key, "must be positive");
  };
  switch (law) {
    case FrictionEquality::kMinMax:
    case FrictionEquality::kHueber:
      positive("rho", rho);
      break;
    case FrictionEquality::kTanh:
    case FrictionEquality::kArctan:
      positive("alpha", alpha);
      break;
    case FrictionEquality::kPiecewiseLinear:
      positive("delta", delta);
      break;
    case FrictionEquality::kSign:
      break;
  }
}

void JenkinsSpec::Validate(const LinearModel& model) const {
  CheckDofs(dof, other, model);
  if (!(mu >= 0.0) || !std::isfinite(mu)) Fail("mu", "must be non-negative");
  if (!(normal_load >= 0.0) || !std::isfinite(normal_load)) {
    Fail("normal_load", "must be non-negative");
  }
  CheckSlipForce(mu, normal_load);
  if (!(stiffness > 0.0) || !std::isfinite(stiffness)) {
    Fail("stiffness", "must be finite and > 0 (N/m)");
  }
}

void PenaltyContactSpec::Validate(const LinearModel& model) const {
  CheckGeometry(geometry, model);
  if (!(stiffness > 0.0) || !std::isfinite(stiffness))
    Fail("stiffness", "must be finite and > 0 (N/m)");
}

void DlftContactSpec::Validate(const LinearModel& model) const { CheckLagrangian(contact, model); }

void LcpContactSpec::Validate(const LinearModel& model) const {
  CheckLagrangian(contact, model);
  if (!(smoothing >= 0.0) || !std::isfinite(smoothing)) {
    Fail("smoothing", "must be finite and >= 0 (m; 0 = exact complementarity)");
  }
}

void EqualityContactSpec::Validate(const LinearModel& model) const {
  CheckLagrangian(LagrangianContactSpec{geometry, obstacle_stiffness, rho}, model, "rho");
}

void ContactFrictionSpec::Validate(const LinearModel& model) const {
  CheckLagrangian(LagrangianContactSpec{geometry, obstacle_stiffness, rho}, model, "rho");
  const int n = model.num_dofs();
  if (tangent_dof < 0 || tangent_dof >= n) {
    Fail("tangent_dof", "DOF " + std::to_string(tangent_dof) + " is not in the model");
  }
  if (tangent_other >= n) {
    Fail("tangent_other", "DOF " + std::to_string(tangent_other) + " is not in the model");
  }
  if (tangent_dof == geometry.dof || tangent_dof == geometry.other) {
    Fail("tangent_dof", "must differ from the contact's dof and other");
  }
  if (tangent_other >= 0 && (tangent_other == tangent_dof || tangent_other == geometry.dof ||
                             tangent_other == geometry.other)) {
    Fail("tangent_other", "must differ from tangent_dof and the contact's dof and other");
  }
  if (!(mu >= 0.0) || !std::isfinite(mu)) Fail("mu", "must be non-negative");
  if (!(friction_rho > 0.0) || !std::isfinite(friction_rho)) {
    Fail("friction_rho", "must be finite and > 0");
  }
}

void DlftFrictionSpec::Validate(const LinearModel& model) const {
  CheckDofs(dof, other, model);
  if (!(mu >= 0.0) || !std::isfinite(mu)) Fail("mu", "must be non-negative");
  if (!(normal_load >= 0.0) || !std::isfinite(normal_load)) {
    Fail("normal_load", "must be non-negative");
  }
  CheckSlipForce(mu, normal_load);
  if (!(epsilon >= 0.0) || !std::isfinite(epsilon)) {
    Fail("epsilon", "must be finite and > 0 (N/m; omit it for the default)");
  }
  if (epsilon == 0.0 && !(EpsilonFor(model) > 0.0)) {
    Fail("epsilon", "no default: the model's stiffness at the DOF is not positive; give epsilon");
  }
}

double DlftFrictionSpec::EpsilonFor(const LinearModel& model) const {
  if (epsilon > 0.0) return epsilon;
  const Eigen::SparseMatrix<double>& k = model.stiffness;
  double sum = k.coeff(dof, dof);
  if (other >= 0) sum = 0.5 * (sum + k.coeff(other, other));
  return sum;
}

std::string_view LawType(const LawSpec& spec) {
  return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::kType; }, spec);
}

const ContactGeometry* LawContactGeometry(const LawSpec& spec) {
  if (const auto* s = std::get_if<PenaltyContactSpec>(&spec)) return &s->geometry;
  if (const auto* s = std::get_if<DlftContactSpec>(&spec)) return &s->contact.geometry;
  if (const auto* s = std::get_if<LcpContactSpec>(&spec)) return &s->contact.geometry;
  if (const auto* s = std::get_if<EqualityContactSpec>(&spec)) return &s->geometry;
  if (const auto* s = std::get_if<ContactFrictionSpec>(&spec)) return &s->geometry;
  return nullptr;
}

std::vector<int> LawDofs(const LawSpec& spec) {
  if (const auto* s = std::get_if<ContactFrictionSpec>(&spec)) {
    std::vector<int> dofs = s->geometry.Dofs();
    dofs.push_back(s->tangent_dof);
    if (s->tangent_other >= 0) dofs.push_back(s->tangent_other);
    return dofs;
  }
  if (const ContactGeometry* geometry = LawContactGeometry(spec)) return geometry->Dofs();
  return std::visit(
      [](const auto& s) -> std::vector<int> {
        using T = std::decay_t<decltype(s)>;
        if constexpr (requires { s.dof; }) {
          return s.other < 0 ? std::vector<int>{s.dof} : std::vector<int>{s.dof, s.other};
        } else {
          static_assert(
              std::is_same_v<T, PenaltyContactSpec> || std::is_same_v<T, DlftContactSpec> ||
                  std::is_same_v<T, LcpContactSpec> || std::is_same_v<T, EqualityContactSpec> ||
                  std::is_same_v<T, ContactFrictionSpec>,
              "a law without dof/other must be a contact law");
          return {};
        }
      },
      spec);
}

void RemapLawDofs(LawSpec& spec, const std::vector<int>& new_index) {
  auto map = [&](int& dof) {
    if (dof >= 0) dof = new_index.at(static_cast<size_t>(dof));
  };
  std::visit(
      [&](auto& s) {
        if constexpr (requires { s.dof; }) {
          map(s.dof);
          map(s.other);
        } else if constexpr (requires { s.geometry; }) {
          map(s.geometry.dof);
          map(s.geometry.other);
          if constexpr (requires { s.tangent_dof; }) {
            map(s.tangent_dof);
            map(s.tangent_other);
          }
        } else {
          map(s.contact.geometry.dof);
          map(s.contact.geometry.other);
        }
      },
      spec);
}

std::optional<double> LawStiffness(const LawSpec& spec, const LinearModel& model) {
  if (const auto* s = std::get_if<JenkinsSpec>(&spec)) return s->stiffness;
  if (const auto* s = std::get_if<DlftFrictionSpec>(&spec)) return s->EpsilonFor(model);
  if (const auto* s = std::get_if<PenaltyContactSpec>(&spec)) return s->stiffness;
  return std::nullopt;
}

void SetLawStiffness(LawSpec& spec, double stiffness) {
  if (auto* s = std::get_if<JenkinsSpec>(&spec)) {
    s->stiffness = stiffness;
  } else if (auto* s = std::get_if<DlftFrictionSpec>(&spec)) {
    s->epsilon = stiffness;
  } else if (auto* s = std::get_if<PenaltyContactSpec>(&spec)) {
    s->stiffness = stiffness;
  } else {
    throw std::logic_error(std::string(LawType(spec)) + ": the law has no stiffness to set");
  }
}

void ValidateLaw(const LawSpec& spec, const LinearModel& model) {
  std::visit([&](const auto& s) { s.Validate(model); }, spec);
}

std::unique_ptr<Nonlinearity> MakeHarmonicLaw(const LawSpec& spec, const LinearModel& model) {
  ValidateLaw(spec, model);
  return std::visit([&](const auto& s) { return s.MakeHarmonic(model); }, spec);
}

}  // namespace nfrc
