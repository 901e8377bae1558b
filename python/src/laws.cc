// The laws as Python value classes, one per LawSpec alternative, with the case file's field
// names. They are copies: a case's laws are read, changed and assigned back (the Case
// validates them against its model then; a law alone cannot know the model's size).
#include <tuple>

#include "bindings.h"
#include "core/errors.h"
#include "nonlinearities/law_spec.h"

namespace nfrc::python {
namespace {

using namespace pybind11::literals;
using GapTerm = std::tuple<int, double, double>;  // (harmonic, cos, sin)

FrictionEquality ParseLaw(const std::string& name) {
  FrictionEquality law;
  if (!ParseFrictionEquality(name, &law)) {
    throw InputError("law: unknown friction law \"" + name +
                     "\" (known: min_max, hueber, tanh, arctan, piecewise_linear, sign)");
  }
  return law;
}

std::vector<GapTerm> GapTerms(const ContactGeometry& g) {
  std::vector<GapTerm> terms;
  for (const auto& h : g.gap_harmonics) terms.emplace_back(h.harmonic, h.cos, h.sin);
  return terms;
}

std::vector<ContactGeometry::GapHarmonic> GapHarmonics(const std::vector<GapTerm>& terms) {
  std::vector<ContactGeometry::GapHarmonic> harmonics;
  for (const auto& [k, c, s] : terms) harmonics.push_back({k, c, s});
  return harmonics;
}

ContactGeometry Geometry(int dof, double gap, int other, double direction,
                         const std::vector<GapTerm>& gap_harmonics) {
  ContactGeometry g;
  g.dof = dof;
  g.other = other;
  g.gap = gap;
  g.direction = direction;
  g.gap_harmonics = GapHarmonics(gap_harmonics);
  return g;
}

// Optional stiffnesses are 0 in the spec when absent; Python says None.
py::object OrNone(double value) { return value == 0.0 ? py::none() : py::cast(value); }
double FromOptional(const std::optional<double>& value, const char* field) {
  if (!value) return 0.0;
  if (!(*value > 0.0))
    throw InputError(std::string(field) + ": must be > 0 (None for the default)");
  return *value;
}

// The class's type name, field list (for the generic repr/eq/copy of the package) and the
// contact geometry fields, read through `geometry` (the spec's ContactGeometry).
template <typename Spec, typename Get>
void GeometryFields(py::class_<Spec>& cls, Get geometry) {
  cls.def_property(
         "dof", [geometry](const Spec& s) { return geometry(s).dof; },
         [geometry](Spec& s, int v) { geometry(s).dof = v; })
      .def_property(
          "other", [geometry](const Spec& s) { return geometry(s).other; },
          [geometry](Spec& s, int v) { geometry(s).other = v; })
      .def_property(
          "gap", [geometry](const Spec& s) { return geometry(s).gap; },
          [geometry](Spec& s, double v) { geometry(s).gap = v; })
      .def_property(
          "direction", [geometry](const Spec& s) { return geometry(s).direction; },
          [geometry](Spec& s, double v) { geometry(s).direction = v; })
      .def_property(
          "gap_harmonics", [geometry](const Spec& s) { return GapTerms(geometry(s)); },
          [geometry](Spec& s, const std::vector<GapTerm>& v) {
            geometry(s).gap_harmonics = GapHarmonics(v);
          });
}

template <typename Spec>
py::class_<Spec> LawClass(py::module_& m, const char* name, py::tuple fields) {
  py::class_<Spec> cls(m, name);
  cls.attr("type") = std::string(Spec::kType);
  cls.attr("_fields") = fields;
  return cls;
}

template <typename Spec>
void LagrangianFields(py::class_<Spec>& cls) {
  GeometryFields(
      cls, [](auto& s) -> auto& { return s.contact.geometry; });
  cls.def_property(
         "obstacle_stiffness", [](const Spec& s) { return OrNone(s.contact.obstacle_stiffness); },
         [](Spec& s, std::optional<double> v) {
           s.contact.obstacle_stiffness = FromOptional(v, "obstacle_stiffness");
         })
      .def_property(
          "epsilon", [](const Spec& s) { return OrNone(s.contact.epsilon); },
          [](Spec& s, std::optional<double> v) { s.contact.epsilon = FromOptional(v, "epsilon"); });
}

LagrangianContactSpec Lagrangian(int dof, double gap, std::optional<double> obstacle_stiffness,
                                 std::optional<double> epsilon, int other, double direction,
                                 const std::vector<GapTerm>& gap_harmonics) {
  LagrangianContactSpec c;
  c.geometry = Geometry(dof, gap, other, direction, gap_harmonics);
  c.obstacle_stiffness = FromOptional(obstacle_stiffness, "obstacle_stiffness");
  c.epsilon = FromOptional(epsilon, "epsilon");
  return c;
}

}  // namespace

void BindLaws(py::module_& m) {
  LawClass<CubicSpringSpec>(m, "CubicSpring", py::make_tuple("dof", "coefficient", "other"))
      .def(py::init([](int dof, double coefficient, int other) {
             return CubicSpringSpec{dof, other, coefficient};
           }),
           "dof"_a, "coefficient"_a, "other"_a = -1)
      .def_readwrite("dof", &CubicSpringSpec::dof)
      .def_readwrite("other", &CubicSpringSpec::other)
      .def_readwrite("coefficient", &CubicSpringSpec::coefficient);

  using Terms = std::vector<std::pair<int, double>>;  // (power, coefficient)
  LawClass<PolynomialSpringSpec>(m, "PolynomialSpring", py::make_tuple("dof", "terms", "other"))
      .def(py::init([](int dof, const Terms& terms, int other) {
             PolynomialSpringSpec s{dof, other, {}};
             for (const auto& [p, c] : terms) s.terms.push_back({p, c});
             return s;
           }),
           "dof"_a, "terms"_a, "other"_a = -1)
      .def_readwrite("dof", &PolynomialSpringSpec::dof)
      .def_readwrite("other", &PolynomialSpringSpec::other)
      .def_property(
          "terms",
          [](const PolynomialSpringSpec& s) {
            Terms terms;
            for (const auto& t : s.terms) terms.emplace_back(t.power, t.coefficient);
            return terms;
          },
          [](PolynomialSpringSpec& s, const Terms& terms) {
            s.terms.clear();
            for (const auto& [p, c] : terms) s.terms.push_back({p, c});
          });

  LawClass<CoulombFrictionSpec>(
      m, "CoulombFriction",
      py::make_tuple("dof", "mu", "normal_load", "law", "other", "rho", "alpha", "delta"))
      .def(py::init([](int dof, double mu, double normal_load, const std::string& law, int other,
                       double rho, double alpha, double delta) {
             return CoulombFrictionSpec{dof,           other, mu,    normal_load,
                                        ParseLaw(law), rho,   alpha, delta};
           }),
           "dof"_a, "mu"_a, "normal_load"_a, "law"_a = "min_max", "other"_a = -1, "rho"_a = 1.0,
           "alpha"_a = 0.0, "delta"_a = 0.0)
      .def_readwrite("dof", &CoulombFrictionSpec::dof)
      .def_readwrite("other", &CoulombFrictionSpec::other)
      .def_readwrite("mu", &CoulombFrictionSpec::mu)
      .def_readwrite("normal_load", &CoulombFrictionSpec::normal_load)
      .def_property(
          "law", [](const CoulombFrictionSpec& s) { return std::string(ToString(s.law)); },
          [](CoulombFrictionSpec& s, const std::string& v) { s.law = ParseLaw(v); })
      .def_readwrite("rho", &CoulombFrictionSpec::rho)
      .def_readwrite("alpha", &CoulombFrictionSpec::alpha)
      .def_readwrite("delta", &CoulombFrictionSpec::delta);

  LawClass<JenkinsSpec>(m, "Jenkins",
                        py::make_tuple("dof", "mu", "normal_load", "stiffness", "other"))
      .def(py::init([](int dof, double mu, double normal_load, double stiffness, int other) {
             return JenkinsSpec{dof, other, mu, normal_load, stiffness};
           }),
           "dof"_a, "mu"_a, "normal_load"_a, "stiffness"_a, "other"_a = -1)
      .def_readwrite("dof", &JenkinsSpec::dof)
      .def_readwrite("other", &JenkinsSpec::other)
      .def_readwrite("mu", &JenkinsSpec::mu)
      .def_readwrite("normal_load", &JenkinsSpec::normal_load)
      .def_readwrite("stiffness", &JenkinsSpec::stiffness);

  LawClass<DlftFrictionSpec>(m, "DlftFriction",
                             py::make_tuple("dof", "mu", "normal_load", "epsilon", "other"))
      .def(py::init([](int dof, double mu, double normal_load, std::optional<double> epsilon,
                       int other) {
             return DlftFrictionSpec{dof, other, mu, normal_load, FromOptional(epsilon, "epsilon")};
           }),
           "dof"_a, "mu"_a, "normal_load"_a, "epsilon"_a = py::none(), "other"_a = -1)
      .def_readwrite("dof", &DlftFrictionSpec::dof)
      .def_readwrite("other", &DlftFrictionSpec::other)
      .def_readwrite("mu", &DlftFrictionSpec::mu)
      .def_readwrite("normal_load", &DlftFrictionSpec::normal_load)
      .def_property(
          "epsilon", [](const DlftFrictionSpec& s) { return OrNone(s.epsilon); },
          [](DlftFrictionSpec& s, std::optional<double> v) {
            s.epsilon = FromOptional(v, "epsilon");
          });

  auto penalty = LawClass<PenaltyContactSpec>(
      m, "PenaltyContact",
      py::make_tuple("dof", "gap", "stiffness", "other", "direction", "gap_harmonics"));
  penalty
      .def(py::init([](int dof, double gap, double stiffness, int other, double direction,
                       const std::vector<GapTerm>& gap_harmonics) {
             return PenaltyContactSpec{Geometry(dof, gap, other, direction, gap_harmonics),
                                       stiffness};
           }),
           "dof"_a, "gap"_a, "stiffness"_a, "other"_a = -1, "direction"_a = 1.0,
           "gap_harmonics"_a = std::vector<GapTerm>{})
      .def_readwrite("stiffness", &PenaltyContactSpec::stiffness);
  GeometryFields(
      penalty, [](auto& s) -> auto& { return s.geometry; });

  auto dlft =
      LawClass<DlftContactSpec>(m, "DlftContact",
                                py::make_tuple("dof", "gap", "obstacle_stiffness", "epsilon",
                                               "other", "direction", "gap_harmonics"));
  dlft.def(py::init([](int dof, double gap, std::optional<double> obstacle_stiffness,
                       std::optional<double> epsilon, int other, double direction,
                       const std::vector<GapTerm>& gap_harmonics) {
             return DlftContactSpec{Lagrangian(dof, gap, obstacle_stiffness, epsilon, other,
                                               direction, gap_harmonics)};
           }),
           "dof"_a, "gap"_a, "obstacle_stiffness"_a = py::none(), "epsilon"_a = py::none(),
           "other"_a = -1, "direction"_a = 1.0, "gap_harmonics"_a = std::vector<GapTerm>{});
  LagrangianFields(dlft);

  auto lcp =
      LawClass<LcpContactSpec>(m, "LcpContact",
                               py::make_tuple("dof", "gap", "obstacle_stiffness", "epsilon",
                                              "smoothing", "other", "direction", "gap_harmonics"));
  lcp.def(py::init([](int dof, double gap, std::optional<double> obstacle_stiffness,
                      std::optional<double> epsilon, double smoothing, int other, double direction,
                      const std::vector<GapTerm>& gap_harmonics) {
            return LcpContactSpec{
                Lagrangian(dof, gap, obstacle_stiffness, epsilon, other, direction, gap_harmonics),
                smoothing};
          }),
          "dof"_a, "gap"_a, "obstacle_stiffness"_a = py::none(), "epsilon"_a = py::none(),
          "smoothing"_a = 0.0, "other"_a = -1, "direction"_a = 1.0,
          "gap_harmonics"_a = std::vector<GapTerm>{})
      .def_readwrite("smoothing", &LcpContactSpec::smoothing);
  LagrangianFields(lcp);

  auto equality =
      LawClass<EqualityContactSpec>(m, "EqualityContact",
                                    py::make_tuple("dof", "gap", "obstacle_stiffness", "rho",
                                                   "other", "direction", "gap_harmonics"));
  equality
      .def(py::init([](int dof, double gap, std::optional<double> obstacle_stiffness,
                       std::optional<double> rho, int other, double direction,
                       const std::vector<GapTerm>& gap_harmonics) {
             return EqualityContactSpec{Geometry(dof, gap, other, direction, gap_harmonics),
                                        FromOptional(obstacle_stiffness, "obstacle_stiffness"),
                                        FromOptional(rho, "rho")};
           }),
           "dof"_a, "gap"_a, "obstacle_stiffness"_a = py::none(), "rho"_a = py::none(),
           "other"_a = -1, "direction"_a = 1.0, "gap_harmonics"_a = std::vector<GapTerm>{})
      .def_property(
          "obstacle_stiffness",
          [](const EqualityContactSpec& s) { return OrNone(s.obstacle_stiffness); },
          [](EqualityContactSpec& s, std::optional<double> v) {
            s.obstacle_stiffness = FromOptional(v, "obstacle_stiffness");
          })
      .def_property(
          "rho", [](const EqualityContactSpec& s) { return OrNone(s.rho); },
          [](EqualityContactSpec& s, std::optional<double> v) { s.rho = FromOptional(v, "rho"); });
  GeometryFields(
      equality, [](auto& s) -> auto& { return s.geometry; });

  auto contact_friction = LawClass<ContactFrictionSpec>(
      m, "ContactFriction",
      py::make_tuple("dof", "gap", "tangent_dof", "mu", "tangent_other", "obstacle_stiffness",
                     "rho", "friction_rho", "other", "direction", "gap_harmonics"));
  contact_friction
      .def(py::init([](int dof, double gap, int tangent_dof, double mu, int tangent_other,
                       std::optional<double> obstacle_stiffness, std::optional<double> rho,
                       double friction_rho, int other, double direction,
                       const std::vector<GapTerm>& gap_harmonics) {
             ContactFrictionSpec s;
             s.geometry = Geometry(dof, gap, other, direction, gap_harmonics);
             s.obstacle_stiffness = FromOptional(obstacle_stiffness, "obstacle_stiffness");
             s.tangent_dof = tangent_dof;
             s.tangent_other = tangent_other;
             s.mu = mu;
             s.rho = FromOptional(rho, "rho");
             s.friction_rho = friction_rho;
             return s;
           }),
           "dof"_a, "gap"_a, "tangent_dof"_a, "mu"_a, "tangent_other"_a = -1,
           "obstacle_stiffness"_a = py::none(), "rho"_a = py::none(), "friction_rho"_a = 1.0,
           "other"_a = -1, "direction"_a = 1.0, "gap_harmonics"_a = std::vector<GapTerm>{})
      .def_readwrite("tangent_dof", &ContactFrictionSpec::tangent_dof)
      .def_readwrite("tangent_other", &ContactFrictionSpec::tangent_other)
      .def_readwrite("mu", &ContactFrictionSpec::mu)
      .def_readwrite("friction_rho", &ContactFrictionSpec::friction_rho)
      .def_property(
          "obstacle_stiffness",
          [](const ContactFrictionSpec& s) { return OrNone(s.obstacle_stiffness); },
          [](ContactFrictionSpec& s, std::optional<double> v) {
            s.obstacle_stiffness = FromOptional(v, "obstacle_stiffness");
          })
      .def_property(
          "rho", [](const ContactFrictionSpec& s) { return OrNone(s.rho); },
          [](ContactFrictionSpec& s, std::optional<double> v) { s.rho = FromOptional(v, "rho"); });
  GeometryFields(
      contact_friction, [](auto& s) -> auto& { return s.geometry; });
}

}  // namespace nfrc::python
