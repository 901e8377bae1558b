#include "nonlinearities/law_spec.h"

#include <doctest/doctest.h>

#include "core/errors.h"

namespace nfrc {
namespace {

// RemapLawDofs renumbers dof and other of every law type (a reduced model's numbering) and
// leaves "against ground" (−1) alone; LawDofs reads them back.
TEST_CASE("law specs: RemapLawDofs renumbers every law's DOFs") {
  std::vector<int> new_index(10, -1);
  new_index[7] = 0;
  new_index[3] = 1;
  CubicSpringSpec cubic;
  cubic.dof = 7;
  cubic.other = 3;
  PolynomialSpringSpec polynomial;
  polynomial.dof = 3;
  CoulombFrictionSpec friction;
  friction.dof = 3;
  friction.other = 7;
  PenaltyContactSpec penalty;
  penalty.geometry.dof = 7;
  DlftContactSpec dlft;
  dlft.contact.geometry.dof = 3;
  dlft.contact.geometry.other = 7;
  LcpContactSpec lcp;
  lcp.contact.geometry.dof = 7;
  const std::vector<std::pair<LawSpec, std::vector<int>>> cases = {
      {cubic, {0, 1}}, {polynomial, {1}}, {friction, {1, 0}},
      {penalty, {0}},  {dlft, {1, 0}},    {lcp, {0}},
  };
  for (const auto& [spec, expected] : cases) {
    LawSpec remapped = spec;
    RemapLawDofs(remapped, new_index);
    CHECK(LawDofs(remapped) == expected);
  }
}

// A two-DOF model, stiffness 2e9 N/m and mass 4 kg on the diagonal (the rod's orders).
LinearModel TwoDofs() {
  LinearModel model;
  model.stiffness.resize(2, 2);
  model.stiffness.insert(0, 0) = 2e9;
  model.stiffness.insert(1, 1) = 2e9;
  model.mass.resize(2, 2);
  model.mass.insert(0, 0) = 4.0;
  model.mass.insert(1, 1) = 4.0;
  model.damping.resize(2, 2);
  return model;
}

TEST_CASE("law specs: parameters far outside the model's scale are refused with their range") {
  const LinearModel model = TwoDofs();
  EqualityContactSpec contact;
  contact.geometry.dof = 1;
  contact.geometry.gap = 1e-4;
  for (const double rho : {0.0, 2e9, 2e-3 * 1.0001, 2e21 * 0.9999}) {
    CAPTURE(rho);
    contact.rho = rho;
    CHECK_NOTHROW(CheckLawRanges(contact, model));
  }
  // The range is 1e12 either way of 2e9 N/m: [2e-3, 2e21].
  contact.rho = 1e300;
  CHECK_THROWS_WITH_AS(CheckLawRanges(contact, model),
                       doctest::Contains("rho: 1e+300 N/m lies outside its useful range [0.002, "
                                         "2e+21] N/m"),
                       InputError);
  DlftFrictionSpec dlft;
  dlft.dof = 1;
  dlft.mu = 0.3;
  dlft.normal_load = 10.0;
  dlft.epsilon = 1e-300;
  CHECK_THROWS_WITH_AS(CheckLawRanges(dlft, model), doctest::Contains("epsilon: 1e-300 N/m"),
                       InputError);
  // A friction equality's rho (velocity per force) against 1/sqrt(k m) = 1/sqrt(8e9).
  CoulombFrictionSpec friction;
  friction.dof = 0;
  friction.mu = 0.3;
  friction.normal_load = 10.0;
  friction.rho = 1.0;
  CHECK_NOTHROW(CheckLawRanges(friction, model));
  friction.rho = 1e20;
  CHECK_THROWS_WITH_AS(CheckLawRanges(friction, model),
                       doctest::Contains("rho: 1e+20 (m/s)/N lies outside its useful range"),
                       InputError);
  // The homotopy and the refinement set stiffnesses beyond the range on purpose: Validate,
  // which every built law goes through, leaves the range to Case::Validate.
  dlft.epsilon = 1e-300;
  CHECK_NOTHROW(dlft.Validate(model));
}

TEST_CASE("law specs: a slip force mu * normal_load that overflows names normal_load") {
  const LinearModel model = TwoDofs();
  JenkinsSpec jenkins;
  jenkins.dof = 0;
  jenkins.mu = 1e300;
  jenkins.normal_load = 1e300;
  jenkins.stiffness = 1e9;
  CHECK_THROWS_WITH_AS(jenkins.Validate(model),
                       doctest::Contains("normal_load: mu * normal_load overflows"), InputError);
  CoulombFrictionSpec coulomb;
  coulomb.dof = 0;
  coulomb.mu = 1e300;
  coulomb.normal_load = 1e300;
  CHECK_THROWS_WITH_AS(coulomb.Validate(model), doctest::Contains("normal_load"), InputError);
}

}  // namespace
}  // namespace nfrc
