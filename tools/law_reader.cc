#include "tools/law_reader.h"

#include <cmath>
#include <map>

#include "tools/input_fields.h"

namespace nfrc {
namespace {

// "dof" and the optional "other" (−1: ground) of a law between two DOFs.
void ReadDofs(InputFields& fields, const LinearModel& model, int* dof, int* other) {
  *dof = fields.RequiredDof("dof", model);
  *other = fields.Has("other") ? fields.RequiredDof("other", model) : -1;
  if (*dof == *other) fields.Fail("other", "must differ from dof");
}

// "mu" and "normal_load" (N) of a friction law, both non-negative.
void ReadFrictionLimit(InputFields& fields, double* mu, double* normal_load) {
  *mu = fields.RequiredNumber("mu");
  *normal_load = fields.RequiredNumber("normal_load");
  if (*mu < 0.0) fields.Fail("mu", "must be non-negative");
  if (*normal_load < 0.0) fields.Fail("normal_load", "must be non-negative");
}

void ReadFields(InputFields& fields, const LinearModel& model, CubicSpringSpec* spec) {
  spec->coefficient = fields.RequiredNumber("coefficient");
  ReadDofs(fields, model, &spec->dof, &spec->other);
}

void ReadFields(InputFields& fields, const LinearModel& model, PolynomialSpringSpec* spec) {
  const nlohmann::json& list = fields.RequiredValue("terms");
  if (!list.is_array() || list.empty()) fields.Fail("terms", "expected a non-empty list");
  for (size_t i = 0; i < list.size(); ++i) {
    InputFields term(list[i], fields.path() + ".terms[" + std::to_string(i) + "]");
    const int power = term.RequiredInt("power");
    if (power < 2) term.Fail("power", "must be at least 2 (linear terms belong in K)");
    spec->terms.push_back(PolynomialSpring::Term{power, term.RequiredNumber("coefficient")});
    term.Finish();
  }
  ReadDofs(fields, model, &spec->dof, &spec->other);
}

void ReadFields(InputFields& fields, const LinearModel& model, CoulombFrictionSpec* spec) {
  ReadDofs(fields, model, &spec->dof, &spec->other);
  ReadFrictionLimit(fields, &spec->mu, &spec->normal_load);
  const std::string law = fields.OptionalString("law", "min_max");
  if (!ParseFrictionEquality(law, &spec->law)) {
    fields.Fail("law", "unknown friction law \"" + law +
                           "\" (known: min_max, hueber, tanh, arctan, piecewise_linear, sign)");
  }
  const bool exact = IsExact(spec->law);
  const bool regularised =
      spec->law == FrictionEquality::kTanh || spec->law == FrictionEquality::kArctan;
  const bool linear = spec->law == FrictionEquality::kPiecewiseLinear;
  // Each parameter is read only by the laws it belongs to: a stray one is an error.
  auto positive = [&](const std::string& key, bool wanted, double fallback) {
    if (!wanted) {
      if (fields.Has(key)) fields.Fail(key, "does not apply to law \"" + law + "\"");
      return fallback;
    }
    if (fallback == 0.0 && !fields.Has(key)) fields.Fail(key, "required by law \"" + law + "\"");
    const double value = fields.OptionalNumber(key, fallback);
    if (!(value > 0.0)) fields.Fail(key, "must be positive");
    return value;
  };
  spec->rho = positive("rho", exact, 1.0);
  spec->alpha = positive("alpha", regularised, 0.0);
  spec->delta = positive("delta", linear, 0.0);
}

void ReadFields(InputFields& fields, const LinearModel& model, JenkinsSpec* spec) {
  ReadDofs(fields, model, &spec->dof, &spec->other);
  ReadFrictionLimit(fields, &spec->mu, &spec->normal_load);
  spec->stiffness = fields.RequiredNumber("stiffness");
  if (!(spec->stiffness > 0.0) || !std::isfinite(spec->stiffness)) {
    fields.Fail("stiffness", "must be finite and > 0 (N/m)");
  }
}

void ReadFields(InputFields& fields, const LinearModel& model, DlftFrictionSpec* spec) {
  ReadDofs(fields, model, &spec->dof, &spec->other);
  ReadFrictionLimit(fields, &spec->mu, &spec->normal_load);
  if (fields.Has("epsilon")) {
    spec->epsilon = fields.RequiredNumber("epsilon");
    if (!(spec->epsilon > 0.0) || !std::isfinite(spec->epsilon)) {
      fields.Fail("epsilon", "must be finite and > 0 (N/m; omit it for the default)");
    }
  }
}

// "dof", "other", "direction" and "gap" (a number, or
// {"constant": g, "harmonics": [{"harmonic": k, "cos": a, "sin": b}]}).
ContactGeometry ReadGeometry(InputFields& fields, const LinearModel& model) {
  ContactGeometry geometry;
  geometry.dof = fields.RequiredDof("dof", model);
  if (fields.Has("other")) {
    geometry.other = fields.RequiredDof("other", model);
    if (geometry.other == geometry.dof) fields.Fail("other", "must differ from dof");
  }
  geometry.direction = fields.OptionalNumber("direction", 1.0);
  if (geometry.direction != 1.0 && geometry.direction != -1.0) {
    fields.Fail("direction", "must be 1 (obstacle on the positive side) or -1");
  }
  const nlohmann::json& gap = fields.RequiredValue("gap");
  if (gap.is_number()) {
    geometry.gap = gap.get<double>();
  } else if (gap.is_object()) {
    InputFields gap_fields(gap, fields.path() + ".gap");
    geometry.gap = gap_fields.OptionalNumber("constant", 0.0);
    if (gap_fields.Has("harmonics")) {
      const nlohmann::json& list = gap_fields.RequiredValue("harmonics");
      if (!list.is_array()) gap_fields.Fail("harmonics", "expected a list");
      for (size_t i = 0; i < list.size(); ++i) {
        InputFields term(list[i], gap_fields.path() + ".harmonics[" + std::to_string(i) + "]");
        ContactGeometry::GapHarmonic h;
        h.harmonic = term.RequiredInt("harmonic");
        if (h.harmonic < 1) term.Fail("harmonic", "must be at least 1 (use constant for 0)");
        h.cos = term.OptionalNumber("cos", 0.0);
        h.sin = term.OptionalNumber("sin", 0.0);
        term.Finish();
        geometry.gap_harmonics.push_back(h);
      }
    }
    gap_fields.Finish();
  } else {
    fields.Fail("gap", "expected a number (m) or an object {constant, harmonics}");
  }
  if (!std::isfinite(geometry.gap)) fields.Fail("gap", "must be finite");
  return geometry;
}

// "obstacle_stiffness" (N/m, absent: rigid, 0) of a contact with `geometry`.
double ReadObstacleStiffness(InputFields& fields, const ContactGeometry& geometry) {
  if (!fields.Has("obstacle_stiffness")) return 0.0;
  const double stiffness = fields.RequiredNumber("obstacle_stiffness");
  if (!(stiffness > 0.0) || !std::isfinite(stiffness)) {
    fields.Fail("obstacle_stiffness", "must be finite and > 0 (N/m; omit it for a rigid obstacle)");
  }
  if (geometry.other >= 0) {
    fields.Fail("obstacle_stiffness",
                "not allowed with other: the second body is then part of the model");
  }
  return stiffness;
}

// "rho" (N/m) of an equality-based contact: absent, the default (stored as 0).
double ReadContactRho(InputFields& fields) {
  if (!fields.Has("rho")) return 0.0;
  const double rho = fields.RequiredNumber("rho");
  if (!(rho > 0.0) || !std::isfinite(rho)) {
    fields.Fail("rho", "must be finite and > 0 (N/m; omit it for the default)");
  }
  return rho;
}

LagrangianContactSpec ReadLagrangian(InputFields& fields, const LinearModel& model) {
  LagrangianContactSpec spec;
  spec.geometry = ReadGeometry(fields, model);
  spec.obstacle_stiffness = ReadObstacleStiffness(fields, spec.geometry);
  if (fields.Has("epsilon")) {
    spec.epsilon = fields.RequiredNumber("epsilon");
    if (!(spec.epsilon > 0.0) || !std::isfinite(spec.epsilon)) {
      fields.Fail("epsilon", "must be finite and > 0 (N/m; omit it for the default)");
    }
  }
  return spec;
}

void ReadFields(InputFields& fields, const LinearModel& model, PenaltyContactSpec* spec) {
  spec->geometry = ReadGeometry(fields, model);
  spec->stiffness = fields.RequiredNumber("stiffness");
  if (!(spec->stiffness > 0.0) || !std::isfinite(spec->stiffness)) {
    fields.Fail("stiffness", "must be finite and > 0 (N/m)");
  }
}

void ReadFields(InputFields& fields, const LinearModel& model, DlftContactSpec* spec) {
  spec->contact = ReadLagrangian(fields, model);
}

void ReadFields(InputFields& fields, const LinearModel& model, LcpContactSpec* spec) {
  spec->contact = ReadLagrangian(fields, model);
  spec->smoothing = fields.OptionalNumber("smoothing", 0.0);
  if (!(spec->smoothing >= 0.0) || !std::isfinite(spec->smoothing)) {
    fields.Fail("smoothing", "must be finite and >= 0 (m; 0 = exact complementarity)");
  }
}

void ReadFields(InputFields& fields, const LinearModel& model, EqualityContactSpec* spec) {
  spec->geometry = ReadGeometry(fields, model);
  spec->obstacle_stiffness = ReadObstacleStiffness(fields, spec->geometry);
  spec->rho = ReadContactRho(fields);
}

void ReadFields(InputFields& fields, const LinearModel& model, ContactFrictionSpec* spec) {
  spec->geometry = ReadGeometry(fields, model);
  spec->obstacle_stiffness = ReadObstacleStiffness(fields, spec->geometry);
  spec->tangent_dof = fields.RequiredDof("tangent_dof", model);
  spec->tangent_other =
      fields.Has("tangent_other") ? fields.RequiredDof("tangent_other", model) : -1;
  spec->mu = fields.RequiredNumber("mu");
  if (!(spec->mu >= 0.0)) fields.Fail("mu", "must be non-negative");
  spec->rho = ReadContactRho(fields);
  spec->friction_rho = fields.OptionalNumber("friction_rho", 1.0);
  if (!(spec->friction_rho > 0.0) || !std::isfinite(spec->friction_rho)) {
    fields.Fail("friction_rho", "must be finite and > 0");
  }
}

using Reader = LawSpec (*)(InputFields&, const LinearModel&);

template <typename Spec>
LawSpec Read(InputFields& fields, const LinearModel& model) {
  Spec spec;
  ReadFields(fields, model, &spec);
  return spec;
}

// Every alternative of LawSpec under its kType: the registry is the variant itself, and a
// law without a ReadFields overload does not compile.
template <typename... Specs>
std::map<std::string, Reader> MakeReaders(const std::variant<Specs...>* /*tag*/) {
  return {{std::string(Specs::kType), &Read<Specs>}...};
}

const std::map<std::string, Reader>& Readers() {
  static const std::map<std::string, Reader> readers =
      MakeReaders(static_cast<const LawSpec*>(nullptr));
  return readers;
}

}  // namespace

LawSpec ReadLaw(const nlohmann::json& spec, const std::string& path, const LinearModel& model) {
  if (!spec.is_object()) throw InputError(path + ": expected an object");
  if (!spec.contains("type") || !spec.at("type").is_string()) {
    throw InputError(path + ".type: missing or not a string");
  }
  const std::string type = spec.at("type").get<std::string>();
  const auto& readers = Readers();
  const auto found = readers.find(type);
  if (found == readers.end()) {
    std::string known;
    for (const auto& [name, reader] : readers) known += (known.empty() ? "" : ", ") + name;
    throw InputError(path + ".type: unknown nonlinearity \"" + type + "\" (known: " + known + ")");
  }
  InputFields fields(spec, path);
  fields.RequiredString("type");
  LawSpec law = found->second(fields, model);
  fields.Finish();
  try {
    ValidateLaw(law, model);
  } catch (const InputError& error) {
    throw InputError(path + "." + error.what());
  }
  return law;
}

}  // namespace nfrc
