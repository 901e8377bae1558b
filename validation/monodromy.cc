#include "validation/monodromy.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "core/errors.h"

namespace nfrc {
namespace {

using Clock = std::chrono::steady_clock;

// DOFs with a non-zero entry in their row of M (M is symmetric in every model, so a non-zero
// column would be one too); the rest are massless.
std::vector<int> MassiveDofs(const Eigen::SparseMatrix<double>& mass) {
  std::vector<bool> has_mass(static_cast<size_t>(mass.rows()), false);
  for (int k = 0; k < mass.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(mass, k); it; ++it) {
      if (it.value() != 0.0) has_mass[static_cast<size_t>(it.row())] = true;
    }
  }
  std::vector<int> dofs;
  for (size_t i = 0; i < has_mass.size(); ++i) {
    if (has_mass[i]) dofs.push_back(static_cast<int>(i));
  }
  return dofs;
}

// The components of z: (x_d, v_d) over the DOFs with mass d, then the free own unknowns o
// (indices into InitialState::own).
struct StateLayout {
  std::vector<int> dofs;
  std::vector<int> own;
  int size() const { return static_cast<int>(2 * dofs.size() + own.size()); }
};

// The laws' differential own unknowns that are free components of the state at on_orbit
// (TimeLaw::OwnStateScale > 0), with their scales; none when the start carries no own values.
void FreeOwnUnknowns(const TransientModel& model, const InitialState& on_orbit,
                     std::vector<int>* indices, std::vector<double>* scales) {
  int offset = 0;
  for (const auto& law : model.laws) {
    for (int k = 0; k < law->NumOwn(); ++k, ++offset) {
      if (offset >= on_orbit.own.size() || !law->OwnIsDifferential(k)) continue;
      const double scale = law->OwnStateScale(k, on_orbit.own(offset));
      if (scale > 0.0) {
        indices->push_back(offset);
        scales->push_back(scale);
      }
    }
  }
}

Eigen::VectorXd StateOf(const InitialState& s, const StateLayout& layout) {
  const int m = static_cast<int>(layout.dofs.size());
  Eigen::VectorXd z(layout.size());
  for (int i = 0; i < m; ++i) {
    z(i) = s.x(layout.dofs[i]);
    z(m + i) = s.v(layout.dofs[i]);
  }
  for (size_t i = 0; i < layout.own.size(); ++i) {
    z(2 * m + static_cast<int>(i)) = s.own(layout.own[i]);
  }
  return z;
}

// on_orbit with its state components replaced by z.
InitialState WithState(const InitialState& on_orbit, const StateLayout& layout,
                       const Eigen::VectorXd& z) {
  InitialState s = on_orbit;
  const int m = static_cast<int>(layout.dofs.size());
  for (int i = 0; i < m; ++i) {
    s.x(layout.dofs[i]) = z(i);
    s.v(layout.dofs[i]) = z(m + i);
  }
  for (size_t i = 0; i < layout.own.size(); ++i) {
    s.own(layout.own[i]) = z(2 * m + static_cast<int>(i));
  }
  return s;
}

}  // namespace

void MonodromyOptions::Validate() const {
  // Below 1e-10 the step is at IDA's tolerance; above 1e-2 the truncation error is ~1e-4.
  if (!(relative_step >= 1e-10 && relative_step <= 1e-2)) {
    throw InputError("validation.monodromy.relative_step: must be in [1e-10, 1e-2]");
  }
  if (!(scale >= 0.0) || !std::isfinite(scale)) {
    throw InputError("validation.monodromy.scale: must be finite and >= 0 (0: automatic)");
  }
}

MonodromyResult ComputeMonodromy(TransientIntegrator& integrator, const TransientModel& model,
                                 double omega, const InitialState& on_orbit,
                                 const MonodromyOptions& options, const std::atomic<bool>* stop) {
  options.Validate();
  if (!(omega > 0.0) || !std::isfinite(omega)) {
    throw InputError("validation.omega: must be finite and > 0");
  }
  const int n = model.num_dofs();
  if (on_orbit.x.size() != n || on_orbit.v.size() != n) {
    throw InputError("validation.initial_state: needs x and v for every DOF");
  }
  const Clock::time_point clock_start = Clock::now();
  MonodromyResult result;
  auto finish = [&](bool ok, std::string message) {
    result.ok = ok;
    result.message = std::move(message);
    result.wall_seconds = std::chrono::duration<double>(Clock::now() - clock_start).count();
    return std::move(result);
  };
  result.state_dofs = MassiveDofs(model.model.mass);
  StateLayout layout;
  layout.dofs = result.state_dofs;
  std::vector<double> own_scales;
  FreeOwnUnknowns(model, on_orbit, &layout.own, &own_scales);
  result.state_own = layout.own;
  const int m = static_cast<int>(layout.dofs.size());
  if (m == 0) return finish(false, "no DOF has mass: the state is empty");
  const Eigen::VectorXd z0 = StateOf(on_orbit, layout);
  double scale = options.scale;
  if (scale == 0.0) {
    scale = std::max(z0.head(m).cwiseAbs().maxCoeff(), z0.tail(m).cwiseAbs().maxCoeff() / omega);
  }
  result.scale = scale;
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    return finish(false, "the state is at rest (or not finite): set validation.monodromy.scale");
  }

  std::string failure;
  InitialState end;
  auto stopped = [stop] { return stop != nullptr && stop->load(); };
  // z in one unit (m): velocities divided by ω, for the closure.
  Eigen::VectorXd unit = Eigen::VectorXd::Ones(2 * m);
  unit.tail(m) /= omega;
  if (stopped()) return finish(false, "stopped");
  ++result.integrations;
  if (!integrator.IntegratePeriods(omega, on_orbit, 1, &end, &failure)) {
    return finish(false, "period map at the orbit: " + failure);
  }
  if (!layout.own.empty() && end.own.size() != on_orbit.own.size()) {
    return finish(false, "the integrator does not report the laws' own unknowns");
  }
  result.closure = ((StateOf(end, layout).head(2 * m) - z0.head(2 * m)).cwiseProduct(unit))
                       .cwiseAbs()
                       .maxCoeff() /
                   scale;

  const int size = layout.size();
  result.matrix.resize(size, size);
  for (int j = 0; j < size; ++j) {
    const double h =
        options.relative_step *
        (j < 2 * m ? scale * (j < m ? 1.0 : omega) : own_scales[static_cast<size_t>(j - 2 * m)]);
    Eigen::VectorXd images[2];
    for (int side = 0; side < 2; ++side) {
      Eigen::VectorXd z = z0;
      z(j) += side == 0 ? h : -h;
      if (stopped()) return finish(false, "stopped");
      ++result.integrations;
      if (!integrator.IntegratePeriods(omega, WithState(on_orbit, layout, z), 1, &end, &failure)) {
        std::ostringstream out;
        out << "period map at z0 " << (side == 0 ? "+" : "-") << " h e_" << j << ": " << failure;
        return finish(false, out.str());
      }
      images[side] = StateOf(end, layout);
    }
    result.matrix.col(j) = (images[0] - images[1]) / (2.0 * h);
  }
  if (!result.matrix.allFinite()) return finish(false, "the monodromy matrix is not finite");

  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(result.matrix, /*computeEigenvectors=*/false);
  if (eigen.info() != Eigen::Success) return finish(false, "EigenSolver did not converge");
  const Eigen::VectorXcd values = eigen.eigenvalues();
  result.multipliers.assign(values.data(), values.data() + values.size());
  // Decreasing modulus; ties (a complex pair) by decreasing imaginary part, for a stable order.
  std::sort(result.multipliers.begin(), result.multipliers.end(),
            [](const std::complex<double>& a, const std::complex<double>& b) {
              if (std::abs(a) != std::abs(b)) return std::abs(a) > std::abs(b);
              return a.imag() > b.imag();
            });
  return finish(true, "");
}

}  // namespace nfrc
