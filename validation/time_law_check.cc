#include "validation/time_law_check.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace nfrc {

DaeView MakeDaeView(const TimeLaw& law, const TimeLawLayout& layout, double t, double phase,
                    const Eigen::VectorXd& y, const Eigen::VectorXd& yp) {
  const int n = layout.num_dofs;
  DaeView s;
  s.t = t;
  s.phase = phase;
  s.num_dofs = n;
  new (&s.x) Eigen::Map<const Eigen::VectorXd>(y.data(), n);
  new (&s.v) Eigen::Map<const Eigen::VectorXd>(y.data() + n, n);
  new (&s.xdot) Eigen::Map<const Eigen::VectorXd>(yp.data(), n);
  new (&s.a) Eigen::Map<const Eigen::VectorXd>(yp.data() + n, n);
  new (&s.own) Eigen::Map<const Eigen::VectorXd>(y.data() + layout.own_offset, law.NumOwn());
  new (&s.own_dot) Eigen::Map<const Eigen::VectorXd>(yp.data() + layout.own_offset, law.NumOwn());
  return s;
}

namespace {

Eigen::VectorXd LawResidual(const TimeLaw& law, const TimeLawLayout& layout, double t, double phase,
                            const Eigen::VectorXd& y, const Eigen::VectorXd& yp) {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(y.size());
  law.Residual(layout, MakeDaeView(law, layout, t, phase, y, yp), r);
  return r;
}

}  // namespace

TimeLawCheck CheckTimeLawJacobian(const TimeLaw& law, const TimeLawLayout& layout, double t,
                                  double phase, const Eigen::VectorXd& y, const Eigen::VectorXd& yp,
                                  double cj, double step) {
  const int size = static_cast<int>(y.size());
  std::vector<Eigen::Triplet<double>> entries;
  law.Jacobian(layout, MakeDaeView(law, layout, t, phase, y, yp), cj, &entries);
  Eigen::MatrixXd analytic = Eigen::MatrixXd::Zero(size, size);
  for (const auto& e : entries) analytic(e.row(), e.col()) += e.value();

  Eigen::MatrixXd numeric(size, size);
  for (int j = 0; j < size; ++j) {
    const double h = step * std::max(1.0, std::abs(y(j)));
    Eigen::VectorXd yu = y, yd = y;
    yu(j) += h;
    yd(j) -= h;
    const double hp = step * std::max(1.0, std::abs(yp(j)));
    Eigen::VectorXd pu = yp, pd = yp;
    pu(j) += hp;
    pd(j) -= hp;
    numeric.col(j) =
        (LawResidual(law, layout, t, phase, yu, yp) - LawResidual(law, layout, t, phase, yd, yp)) /
            (2 * h) +
        cj *
            (LawResidual(law, layout, t, phase, y, pu) -
             LawResidual(law, layout, t, phase, y, pd)) /
            (2 * hp);
  }
  TimeLawCheck check;
  check.scale = numeric.cwiseAbs().maxCoeff();
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const double error = std::abs(analytic(i, j) - numeric(i, j));
      if (error > check.max_abs_error) {
        check.max_abs_error = error;
        std::ostringstream out;
        out << "row " << i << ", column " << j << ": analytic " << analytic(i, j)
            << ", finite difference " << numeric(i, j);
        check.worst = out.str();
      }
    }
  }
  return check;
}

}  // namespace nfrc
