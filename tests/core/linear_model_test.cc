#include "core/linear_model.h"

#include <doctest/doctest.h>

#include <limits>
#include <stdexcept>

namespace nfrc {
namespace {

LinearModel Diagonal(int n) {
  LinearModel model;
  model.stiffness.resize(n, n);
  model.mass.resize(n, n);
  model.damping.resize(n, n);
  for (int i = 0; i < n; ++i) {
    model.stiffness.insert(i, i) = 2.0;
    model.mass.insert(i, i) = 1.0;
  }
  return model;
}

TEST_CASE("LinearModel finds DOFs by name") {
  LinearModel model = Diagonal(3);
  CHECK(model.num_dofs() == 3);
  CHECK(model.FindDof("end") == -1);
  model.dof_names = {"base", "middle", "end"};
  CHECK(model.FindDof("end") == 2);
  CHECK(model.FindDof("base") == 0);
  CHECK(model.FindDof("nowhere") == -1);
  CHECK_NOTHROW(model.Validate());
}

TEST_CASE("LinearModel validation names the field") {
  CHECK_NOTHROW(Diagonal(2).Validate());

  LinearModel empty;
  CHECK_THROWS_WITH_AS(empty.Validate(), doctest::Contains("stiffness"), std::invalid_argument);

  LinearModel wrong_size = Diagonal(3);
  wrong_size.damping.resize(2, 2);
  CHECK_THROWS_WITH_AS(wrong_size.Validate(), doctest::Contains("damping"), std::invalid_argument);

  LinearModel not_square = Diagonal(3);
  not_square.mass.resize(3, 2);
  CHECK_THROWS_WITH_AS(not_square.Validate(), doctest::Contains("mass"), std::invalid_argument);

  LinearModel stiffness_not_square = Diagonal(3);
  stiffness_not_square.stiffness.resize(3, 4);
  CHECK_THROWS_WITH_AS(stiffness_not_square.Validate(), doctest::Contains("stiffness"),
                       std::invalid_argument);

  LinearModel not_finite = Diagonal(3);
  not_finite.mass.coeffRef(1, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH_AS(not_finite.Validate(), doctest::Contains("mass"), std::invalid_argument);
  not_finite = Diagonal(3);
  not_finite.stiffness.coeffRef(0, 2) = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH_AS(not_finite.Validate(), doctest::Contains("stiffness"),
                       std::invalid_argument);

  LinearModel names = Diagonal(3);
  names.dof_names = {"a", "b"};
  CHECK_THROWS_WITH_AS(names.Validate(), doctest::Contains("dof_names"), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
