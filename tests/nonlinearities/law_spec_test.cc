#include "nonlinearities/law_spec.h"

#include <doctest/doctest.h>

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

}  // namespace
}  // namespace nfrc
