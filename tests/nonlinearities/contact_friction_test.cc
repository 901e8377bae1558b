// Contact with friction under the contact force: Jacobian, ω-derivative and Hill's velocity
// Jacobian against finite differences; its Signorini rows against equality_contact and its
// Coulomb rows under a constant contact force against coulomb_friction (both tested on their
// own); the zero set on stick and separation; the input checks.
#include "nonlinearities/contact_friction.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "nonlinearities/coulomb_friction.h"
#include "nonlinearities/equality_contact.h"
#include "nonlinearities/jacobian_check.h"

namespace nfrc {
namespace {

// Away from switches the law is piecewise linear in (g, λ, v, r) on every sample, so central
// differences are exact up to round-off: 1e-16 / 1e-7 relative over O(1)–O(10) entries.
constexpr double kFdTolerance = 1e-6;
constexpr double kFdStep = 1e-7;
// A sample whose switching functions are this far from zero cannot change branch under a
// perturbation of kFdStep·|y| (basis samples are bounded by 1, ω·k·|y| by ~30).
constexpr double kSwitchMargin = 1e-3;
// Rows compared with another law's: the same arithmetic in another order, round-off only.
constexpr double kSameRows = 1e-12;

constexpr double kRho = 2.5;          // N/m
constexpr double kFrictionRho = 0.7;  // velocity / force
constexpr double kMu = 0.4;

// Dofs() = [normal (, normal other), tangent (, tangent other)] at local positions 0, 1, ….
struct Setup {
  HarmonicSet set{5, false, 32};
  FourierTransform fourier{set};
  NonlinearityContext ctx;
  ContactFriction law;
  explicit Setup(bool others, double direction = 1.0) : law(Parameters(others, direction)) {
    ctx.fourier = &fourier;
    const int dofs = others ? 4 : 2;
    for (int i = 0; i < dofs; ++i) ctx.local_dofs.push_back(i);
    ctx.own_offset = dofs * set.NumCoefficients();
  }
  static ContactFriction::Parameters Parameters(bool others, double direction) {
    ContactFriction::Parameters p;
    p.geometry.dof = 0;
    p.geometry.other = others ? 1 : -1;
    p.geometry.direction = direction;
    p.geometry.gap = 0.2;
    p.geometry.gap_harmonics = {{2, 0.1, -0.05}};
    p.tangent_dof = others ? 2 : 1;
    p.tangent_other = others ? 3 : -1;
    p.mu = kMu;
    p.rho = kRho;
    p.friction_rho = kFrictionRho;
    return p;
  }
  int nc() const { return set.NumCoefficients(); }
  int Size() const { return ctx.own_offset + 2 * nc(); }
};

// The smallest distance of a sample from a switch of either equality, and whether every
// branch (contact/open, stick/slip) occurs on some sample.
struct Branches {
  double margin = INFINITY;
  bool contact = false, open = false, stick = false, slip = false;
};

Branches Classify(const Setup& s, const Eigen::VectorXd& y, double omega) {
  const ContactFriction::Samples samples = s.law.Sample(s.ctx, y, omega);
  Branches b;
  for (Eigen::Index j = 0; j < samples.gap.size(); ++j) {
    const double lambda = samples.normal(j), v = samples.velocity(j), r = samples.friction(j);
    const double normal_switch = lambda - kRho * samples.gap(j);
    const double limit = kMu * std::max(0.0, normal_switch);
    const double low = kFrictionRho * (r + limit) - v, high = kFrictionRho * (r - limit) - v;
    b.margin = std::min({b.margin, std::abs(normal_switch), std::abs(low), std::abs(high)});
    (normal_switch > 0.0 ? b.contact : b.open) = true;
    (low >= 0.0 && high <= 0.0 && normal_switch > 0.0 ? b.stick : b.slip) = true;
  }
  return b;
}

// Random states whose samples are all kSwitchMargin away from a switch and cover every branch.
std::vector<Eigen::VectorXd> States(const Setup& s, double omega, int count, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Eigen::VectorXd> states;
  const int nc = s.nc();
  for (int attempt = 0; attempt < 100000 && static_cast<int>(states.size()) < count; ++attempt) {
    Eigen::VectorXd y(s.Size());
    for (int i = 0; i < y.size(); ++i) y(i) = 0.3 * normal(rng) / (1 + i % nc);
    y(s.ctx.own_offset + s.set.CosIndex(0)) += 0.5;  // a mean compressive force
    y.segment(s.ctx.own_offset + nc, nc) *= 0.3;     // friction forces of the order of μλ
    const Branches b = Classify(s, y, omega);
    if (b.margin > kSwitchMargin && b.contact && b.open && b.stick && b.slip) states.push_back(y);
  }
  return states;
}

TEST_CASE("contact friction: Jacobian and omega-derivative match finite differences") {
  std::mt19937 rng(20261125);
  const double omega = 0.9;
  for (bool others : {false, true}) {
    for (double direction : {1.0, -1.0}) {
      CAPTURE(others);
      CAPTURE(direction);
      const Setup s(others, direction);
      const std::vector<Eigen::VectorXd> states = States(s, omega, 3, rng);
      REQUIRE(states.size() == 3);
      for (const Eigen::VectorXd& y : states) {
        const JacobianCheckResult result =
            CheckNonlinearityJacobian(s.law, s.ctx, nullptr, y, omega, kFdStep, 1.0);
        CHECK(result.y_error < kFdTolerance);
        CHECK(result.residual_error <= kSameResidual);
        CHECK(result.omega_error < kFdTolerance);
      }
    }
  }
}

// Hill's velocity block: the friction rows depend on the tangent displacements only through
// v = ωDx, so their x-columns are J_v·ωD; on a set with harmonic 0, D is singular, so the check
// compares J_v·ωD with the finite differences instead of inverting D.
TEST_CASE("contact friction: the velocity Jacobian for Hill's method matches finite differences") {
  std::mt19937 rng(20261126);
  const double omega = 0.9;
  for (bool others : {false, true}) {
    CAPTURE(others);
    const Setup s(others);
    const int nc = s.nc();
    const Eigen::VectorXd y = States(s, omega, 1, rng).at(0);
    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(y.size(), y.size());
    Eigen::MatrixXd velocity = Eigen::MatrixXd::Zero(y.size(), y.size());
    s.law.LinearizeForStability(s.ctx, y, omega, &jacobian, &velocity);
    const int tangent = s.ctx.DofOffset(s.law.TangentIndex());
    const int friction = s.ctx.own_offset + nc;
    Eigen::MatrixXd fd(nc, nc);
    for (int j = 0; j < nc; ++j) {
      const double h = kFdStep * std::max(1.0, std::abs(y(tangent + j)));
      Eigen::VectorXd plus = y, minus = y;
      plus(tangent + j) += h;
      minus(tangent + j) -= h;
      Eigen::VectorXd r_plus = Eigen::VectorXd::Zero(y.size()), r_minus = r_plus;
      s.law.Evaluate(s.ctx, plus, omega, r_plus, nullptr, nullptr);
      s.law.Evaluate(s.ctx, minus, omega, r_minus, nullptr, nullptr);
      fd.col(j) = (r_plus - r_minus).segment(friction, nc) / (2 * h);
    }
    const Eigen::MatrixXd block = velocity.block(friction, tangent, nc, nc);
    const Eigen::MatrixXd chained = block * omega * s.fourier.DerivativeMatrix();
    CHECK((chained - fd).norm() <= kFdTolerance * std::max(1.0, fd.norm()));
    CHECK(block.norm() > 0.0);  // some samples stick, so J_v is not zero
    if (others) {
      CHECK((velocity.block(friction, tangent + nc, nc, nc) + block).norm() == 0.0);
    }
  }
}

// In closed contact (g ≡ 0) under a constant force λ0 > 0 the friction rows are those of
// Coulomb friction under the normal load λ0 (mu·N = μλ0), and the Signorini rows those of
// equality_contact: the combined law adds no term of its own to either.
TEST_CASE("contact friction: its rows are equality_contact's and coulomb_friction's") {
  std::mt19937 rng(20261127);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double omega = 1.1, lambda0 = 1.7;
  const Setup s(false);
  const int nc = s.nc();
  Eigen::VectorXd y(s.Size());
  for (int i = 0; i < y.size(); ++i) y(i) = 0.3 * normal(rng) / (1 + i % nc);
  y.head(nc) = s.law.parameters().geometry.GapCoefficients(s.set);
  y.segment(s.ctx.own_offset, nc).setZero();
  y(s.ctx.own_offset + s.set.CosIndex(0)) = lambda0;
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(y.size());
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(y.size(), y.size());
  Eigen::VectorXd d_omega = Eigen::VectorXd::Zero(y.size());
  s.law.Evaluate(s.ctx, y, omega, residual, &jacobian, &d_omega);

  // Coulomb on [x_t | r̃] with its own unknowns right after the tangent DOF.
  FrictionParameters p;
  p.limit = kMu * lambda0;
  p.rho = kFrictionRho;
  const CoulombFriction coulomb(1, -1, p);
  NonlinearityContext friction_ctx = s.ctx;
  friction_ctx.local_dofs = {0};
  friction_ctx.own_offset = nc;
  Eigen::VectorXd yc(2 * nc);
  yc << y.segment(nc, nc), y.tail(nc);
  Eigen::VectorXd rc = Eigen::VectorXd::Zero(2 * nc), dc = rc;
  Eigen::MatrixXd jc = Eigen::MatrixXd::Zero(2 * nc, 2 * nc);
  coulomb.Evaluate(friction_ctx, yc, omega, rc, &jc, &dc);
  const int friction = s.ctx.own_offset + nc;
  CHECK((residual.segment(friction, nc) - rc.tail(nc)).norm() <= kSameRows);
  CHECK((residual.segment(nc, nc) - rc.head(nc)).norm() <= kSameRows);
  CHECK((jacobian.block(friction, nc, nc, nc) - jc.block(nc, 0, nc, nc)).norm() <= kSameRows);
  CHECK((jacobian.block(friction, friction, nc, nc) - jc.block(nc, nc, nc, nc)).norm() <=
        kSameRows);
  CHECK((d_omega.segment(friction, nc) - dc.tail(nc)).norm() <= kSameRows);

  // Signorini on [x_n | λ̃].
  const EqualityContact contact(Setup::Parameters(false, 1.0).geometry, 0.0, kRho);
  NonlinearityContext contact_ctx = friction_ctx;
  Eigen::VectorXd ye(2 * nc);
  ye << y.head(nc), y.segment(s.ctx.own_offset, nc);
  Eigen::VectorXd re = Eigen::VectorXd::Zero(2 * nc);
  Eigen::MatrixXd je = Eigen::MatrixXd::Zero(2 * nc, 2 * nc);
  contact.Evaluate(contact_ctx, ye, omega, re, &je, nullptr);
  const int normal_rows = s.ctx.own_offset;
  CHECK((residual.segment(normal_rows, nc) - re.tail(nc)).norm() <= kSameRows);
  CHECK((residual.head(nc) - re.head(nc)).norm() <= kSameRows);
  CHECK((jacobian.block(normal_rows, 0, nc, nc) - je.block(nc, 0, nc, nc)).norm() <= kSameRows);
}

// The law's rows vanish on states that satisfy the law on every sample: a closed contact
// sticking under |r| ≤ μλ, and a separated contact (λ = 0) with no friction force, whatever
// the sliding velocity; a sticking force beyond μλ, or a friction force while separated, does
// not satisfy them.
TEST_CASE("contact friction: the zero set is stick in contact and zero friction when open") {
  const Setup s(false);
  const int nc = s.nc();
  const int c0 = s.set.CosIndex(0), c1 = s.set.CosIndex(1);
  const double omega = 1.0, lambda = 2.0;
  auto law_rows = [&](const Eigen::VectorXd& y) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(y.size());
    s.law.Evaluate(s.ctx, y, omega, r, nullptr, nullptr);
    return Eigen::VectorXd(r.tail(2 * nc));
  };
  // Closed and stuck: g ≡ 0 (x_n = g0 through the gap harmonic too), λ ≡ 2, x_t constant.
  Eigen::VectorXd stuck = Eigen::VectorXd::Zero(s.Size());
  stuck.head(nc) = s.law.parameters().geometry.GapCoefficients(s.set);
  stuck(nc + c0) = 0.3;
  stuck(s.ctx.own_offset + c0) = lambda;
  stuck(s.ctx.own_offset + nc + c0) = 0.9 * kMu * lambda;
  CHECK(law_rows(stuck).norm() < 1e-12);
  Eigen::VectorXd too_much = stuck;
  too_much(s.ctx.own_offset + nc + c0) = 1.1 * kMu * lambda;
  CHECK(law_rows(too_much).norm() > 1e-3);
  // Open: g = g0 > 0 everywhere (x_n = 0), λ = 0, r = 0, the tangent DOF oscillating.
  Eigen::VectorXd open = Eigen::VectorXd::Zero(s.Size());
  open(nc + c1) = 0.5;
  CHECK(law_rows(open).norm() < 1e-12);
  Eigen::VectorXd rubbing = open;
  rubbing(s.ctx.own_offset + nc + c1) = 0.1;
  CHECK(law_rows(rubbing).norm() > 1e-3);
}

TEST_CASE("contact friction: bad parameters name the field") {
  ContactFriction::Parameters p = Setup::Parameters(false, 1.0);
  auto message = [](const ContactFriction::Parameters& q) {
    try {
      ContactFriction law(q);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  ContactFriction::Parameters q = p;
  q.tangent_dof = 0;
  CHECK(message(q).rfind("tangent_dof", 0) == 0);
  q = p;
  q.mu = -1.0;
  CHECK(message(q).rfind("mu", 0) == 0);
  q = p;
  q.friction_rho = 0.0;
  CHECK(message(q).rfind("friction_rho", 0) == 0);
  q = p;
  q.obstacle_stiffness = -1.0;
  CHECK(message(q).rfind("obstacle_stiffness", 0) == 0);
  CHECK(message(p).empty());
}

}  // namespace
}  // namespace nfrc
