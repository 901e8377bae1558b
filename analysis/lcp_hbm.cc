#include "analysis/lcp_hbm.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/errors.h"

namespace nfrc {

LcpHbm::LcpHbm(HarmonicSystem& system, const std::vector<LawSpec>& laws)
    : system_(system), omega_(std::numeric_limits<double>::quiet_NaN()) {
  if (laws.size() != system.laws().size()) {
    throw std::logic_error("LcpHbm: the specifications are not the system's laws");
  }
  for (size_t i = 0; i < laws.size(); ++i) {
    const auto* law = std::get_if<LcpContactSpec>(&laws[i]);
    if (law == nullptr) {
      throw InputError("nonlinearities[" + std::to_string(i) +
                       "]: LCP-HBM needs every law to be "
                       "lcp_contact, got " +
                       std::string(LawType(laws[i])));
    }
    Contact c;
    c.law = static_cast<int>(i);
    c.n = law->contact.geometry.direction;
    c.pair = law->contact.geometry.other >= 0;
    c.gap0 = law->contact.geometry.GapCoefficients(system.harmonic_set());
    c.contact = law->contact;
    contacts_.push_back(c);
    num_samples_ += system.harmonic_set().num_samples();
  }
  if (contacts_.empty()) throw InputError("nonlinearities: LCP-HBM needs an lcp_contact law");
}

Eigen::VectorXd LcpHbm::Relative(const Contact& c, const Eigen::VectorXd& x) const {
  const NonlinearityContext& ctx = system_.context(c.law);
  const int nc = ctx.num_coefficients();
  Eigen::VectorXd relative = x.segment(ctx.DofOffset(0), nc);
  if (c.pair) relative -= x.segment(ctx.DofOffset(1), nc);
  return relative;
}

const LcpHbm::Problem& LcpHbm::Assemble(double omega) {
  if (omega == omega_) return problem_;
  const Eigen::MatrixXd& a = system_.LinearOperator(omega);
  const Eigen::VectorXd& b = system_.LinearForcing(omega);
  const FourierTransform& fourier = system_.fourier();
  const Eigen::MatrixXd& e = fourier.SampleMatrix();
  const Eigen::MatrixXd& p = fourier.ProjectionMatrix();
  const int nt = system_.harmonic_set().num_samples();
  const int nc = system_.harmonic_set().NumCoefficients();
  const Eigen::Index nx = a.rows();

  Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (!lu.isInvertible()) {
    std::ostringstream message;
    message.precision(8);
    message << "LCP-HBM: the condensed dynamic stiffness is singular at omega = " << omega
            << " (an undamped resonance there, or a frequency so far from the model's that its "
               "matrices no longer resolve it)";
    throw InputError(message.str());
  }
  x_linear_ = lu.solve(b);
  // Right-hand sides n_d S_dᵀ P, one block of N_t columns per contact.
  Eigen::MatrixXd injection = Eigen::MatrixXd::Zero(nx, num_samples_);
  for (size_t d = 0; d < contacts_.size(); ++d) {
    const NonlinearityContext& ctx = system_.context(contacts_[d].law);
    auto block = injection.middleCols(static_cast<Eigen::Index>(d) * nt, nt);
    block.middleRows(ctx.DofOffset(0), nc) += contacts_[d].n * p;
    if (contacts_[d].pair) block.middleRows(ctx.DofOffset(1), nc) -= contacts_[d].n * p;
  }
  force_response_ = lu.solve(injection);

  problem_.w.resize(num_samples_, num_samples_);
  problem_.p.resize(num_samples_);
  for (size_t c = 0; c < contacts_.size(); ++c) {
    const Contact& contact = contacts_[c];
    const NonlinearityContext& ctx = system_.context(contact.law);
    Eigen::MatrixXd relative = force_response_.middleRows(ctx.DofOffset(0), nc);
    if (contact.pair) relative -= force_response_.middleRows(ctx.DofOffset(1), nc);
    const Eigen::Index row = static_cast<Eigen::Index>(c) * nt;
    problem_.w.middleRows(row, nt) = contact.n * (e * relative);
    problem_.p.segment(row, nt) = e * (contact.gap0 - contact.n * Relative(contact, x_linear_));
  }
  omega_ = omega;
  return problem_;
}

Eigen::VectorXd LcpHbm::Unknowns(const Eigen::VectorXd& lambda, double omega) {
  Assemble(omega);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(system_.NumUnknowns());
  y.head(x_linear_.size()) = x_linear_ - force_response_ * lambda;
  const int nt = system_.harmonic_set().num_samples();
  for (size_t c = 0; c < contacts_.size(); ++c) {
    const int law = contacts_[c].law;
    const double epsilon = contacts_[c].contact.EpsilonFor(system_.context(law));
    y.segment(system_.context(law).own_offset, nt) =
        lambda.segment(static_cast<Eigen::Index>(c) * nt, nt) / epsilon;
  }
  return y;
}

LcpHbm::Solution LcpHbm::Solve(double omega, const LemkeOptions& options) {
  const Problem& problem = Assemble(omega);
  // Scaled problem: z = λ·‖W‖∞/‖p‖∞ solves (W/‖W‖∞) z + p/‖p‖∞ ⊥ z.
  const double w_scale = problem.w.cwiseAbs().maxCoeff();
  const double p_scale = problem.p.cwiseAbs().maxCoeff();
  Solution solution;
  if (!(w_scale > 0.0) || !(p_scale > 0.0)) {
    throw std::runtime_error("LCP-HBM: W or p vanishes at omega = " + std::to_string(omega));
  }
  solution.lemke = SolveLcp(problem.w / w_scale, problem.p / p_scale, options);
  solution.lambda = solution.lemke.z * (p_scale / w_scale);
  solution.gap = problem.w * solution.lambda + problem.p;
  solution.y = Unknowns(solution.lambda, omega);
  solution.complementarity_gap =
      solution.gap.cwiseMin(solution.lambda / w_scale).cwiseAbs().maxCoeff();
  return solution;
}

}  // namespace nfrc
