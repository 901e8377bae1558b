#include "analysis/case_parameter.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <sstream>
#include <type_traits>
#include <utility>
#include <variant>

#include "core/errors.h"

namespace nfrc {
namespace {

const double* GeometryField(const ContactGeometry& geometry, const std::string& field) {
  if (field == "gap") return &geometry.gap;
  return nullptr;
}

const double* LagrangianField(const LagrangianContactSpec& contact, const std::string& field) {
  if (field == "obstacle_stiffness") return &contact.obstacle_stiffness;
  if (field == "epsilon") return &contact.epsilon;
  return GeometryField(contact.geometry, field);
}

// The numeric field `field` of a law's specification, null if the law has none by that name.
const double* LawField(const LawSpec& spec, const std::string& field) {
  return std::visit(
      [&](const auto& law) -> const double* {
        using Spec = std::decay_t<decltype(law)>;
        if constexpr (std::is_same_v<Spec, CubicSpringSpec>) {
          if (field == "coefficient") return &law.coefficient;
        } else if constexpr (std::is_same_v<Spec, CoulombFrictionSpec>) {
          if (field == "mu") return &law.mu;
          if (field == "normal_load") return &law.normal_load;
          if (field == "rho") return &law.rho;
          if (field == "alpha") return &law.alpha;
          if (field == "delta") return &law.delta;
        } else if constexpr (std::is_same_v<Spec, JenkinsSpec>) {
          if (field == "mu") return &law.mu;
          if (field == "normal_load") return &law.normal_load;
          if (field == "stiffness") return &law.stiffness;
        } else if constexpr (std::is_same_v<Spec, PenaltyContactSpec>) {
          if (field == "stiffness") return &law.stiffness;
          return GeometryField(law.geometry, field);
        } else if constexpr (std::is_same_v<Spec, DlftContactSpec>) {
          return LagrangianField(law.contact, field);
        } else if constexpr (std::is_same_v<Spec, DlftFrictionSpec>) {
          if (field == "mu") return &law.mu;
          if (field == "normal_load") return &law.normal_load;
          if (field == "epsilon") return &law.epsilon;
        } else if constexpr (std::is_same_v<Spec, EqualityContactSpec>) {
          if (field == "obstacle_stiffness") return &law.obstacle_stiffness;
          if (field == "rho") return &law.rho;
          return GeometryField(law.geometry, field);
        } else if constexpr (std::is_same_v<Spec, ContactFrictionSpec>) {
          if (field == "mu") return &law.mu;
          if (field == "obstacle_stiffness") return &law.obstacle_stiffness;
          if (field == "rho") return &law.rho;
          if (field == "friction_rho") return &law.friction_rho;
          return GeometryField(law.geometry, field);
        } else if constexpr (std::is_same_v<Spec, LcpContactSpec>) {
          if (field == "smoothing") return &law.smoothing;
          return LagrangianField(law.contact, field);
        }
        return nullptr;
      },
      spec);
}

[[noreturn]] void Refuse(const std::string& path, const std::string& why) {
  throw InputError("parameter: \"" + path + "\" " + why);
}

// "<prefix>[<index>].<field>" split into index and field; nullopt if the text has another
// shape. (std::regex trips GCC 12's -Wmaybe-uninitialized under the sanitizers.)
std::optional<std::pair<std::string, std::string>> SplitIndexed(const std::string& text,
                                                                const std::string& prefix) {
  if (text.compare(0, prefix.size() + 1, prefix + "[") != 0) return std::nullopt;
  const size_t close = text.find("].", prefix.size() + 1);
  if (close == std::string::npos) return std::nullopt;
  std::string index = text.substr(prefix.size() + 1, close - prefix.size() - 1);
  std::string field = text.substr(close + 2);
  const auto digit = [](unsigned char c) { return std::isdigit(c) != 0; };
  const auto name = [](unsigned char c) { return std::islower(c) != 0 || c == '_'; };
  if (index.empty() || !std::all_of(index.begin(), index.end(), digit) || field.empty() ||
      !std::all_of(field.begin(), field.end(), name)) {
    return std::nullopt;
  }
  return std::make_pair(std::move(index), std::move(field));
}

}  // namespace

CaseParameter::CaseParameter(std::string path, const Case& the_case) : path_(std::move(path)) {
  if (const std::optional<std::string> why = Parse(the_case)) Refuse(path_, *why);
}

bool CaseParameter::Accepts(const std::string& path, const Case& the_case) {
  CaseParameter parameter;
  parameter.path_ = path;
  return !parameter.Parse(the_case).has_value();
}

std::optional<std::string> CaseParameter::Parse(const Case& the_case) {
  std::optional<std::pair<std::string, std::string>> parts;
  if ((parts = SplitIndexed(path_, "model.forcing")) &&
      (parts->second == "cos" || parts->second == "sin")) {
    kind_ = parts->second == "cos" ? Kind::kForcingCos : Kind::kForcingSin;
  } else if ((parts = SplitIndexed(path_, "nonlinearities"))) {
    kind_ = Kind::kLaw;
    field_ = parts->second;
  } else {
    return "is not a numeric case field: use model.forcing[i].cos|sin or "
           "nonlinearities[i].<field>";
  }
  if (parts->first.size() > 6) return "has an index out of range";
  index_ = std::stoi(parts->first);
  if (Field(the_case) == nullptr) return "names no numeric field of this case";
  return std::nullopt;
}

const double* CaseParameter::Field(const Case& the_case) const {
  if (kind_ == Kind::kLaw) {
    if (index_ >= static_cast<int>(the_case.laws.size())) return nullptr;
    return LawField(the_case.laws[static_cast<size_t>(index_)], field_);
  }
  const std::vector<ForcingTerm>& forcing = the_case.model.forcing;
  if (index_ >= static_cast<int>(forcing.size())) return nullptr;
  const ForcingTerm& term = forcing[static_cast<size_t>(index_)];
  return kind_ == Kind::kForcingCos ? &term.cos : &term.sin;
}

double CaseParameter::Get(const Case& the_case) const {
  const double* field = Field(the_case);
  if (field == nullptr) Refuse(path_, "names no numeric field of this case");
  return *field;
}

void CaseParameter::Set(Case* the_case, double value) const {
  // The field lies in *the_case, which is mutable here.
  double* field = const_cast<double*>(Field(*the_case));
  if (field == nullptr) Refuse(path_, "names no numeric field of this case");
  if (!std::isfinite(value)) Refuse(path_, "cannot be set to a non-finite value");
  *field = value;
}

Case CaseParameter::With(const Case& the_case, double value) const {
  Case changed = the_case;
  Set(&changed, value);
  changed.Validate();
  return changed;
}

void CheckStudyTarget(double from, double to) {
  if (!std::isfinite(to) || to == from) {
    throw InputError("to: must be finite and differ from the parameter's value in the case");
  }
  if (from != 0.0 && std::abs(to - from) > kMaxParameterSpan * std::abs(from)) {
    std::ostringstream message;
    message << "to: " << to << " lies more than " << kMaxParameterSpan << " times the case's value "
            << from
            << " away from it (the curve's steps are fractions of that span; go there in "
               "stages, each from the last's end)";
    throw InputError(message.str());
  }
}

}  // namespace nfrc
