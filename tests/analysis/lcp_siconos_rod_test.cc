// nfrc's Lemke against Siconos's lcp_lexicolemke on the LCP-HBM problems of the rod against a
// rigid obstacle (cases/lcp/rigid_stepping_nt400.json, N_h = 20) at N_t = 41 and 400, W and p
// assembled and scaled as LcpHbm::Solve does; the random collection: tests/core/
// lcp_siconos_test.cc. Built only with Siconos (NFRC_HAVE_SICONOS).
#ifdef NFRC_HAVE_SICONOS

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <string>

#include "analysis/lcp_hbm.h"
#include "core/lcp_siconos.h"
#include "core/lemke.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// Residuals of the scaled problem (‖W‖max = ‖p‖∞ = 1): w ≥ 0 and w − Wz − p to this, z ≥ 0 to
// this times max(1, ‖z‖∞), w_i z_i to this times max(1, ‖z‖∞). nfrc's point is an LU solve of
// its final basis, whose condition reaches ~1e6 here (see lcp_test.cc), so ~1e-10 at worst.
constexpr double kResidualTol = 1e-8;
// The two solvers' z (relative to max(1, ‖z‖∞)) and gaps (in units of ‖p‖∞ = 1) against each
// other: the same rounding budget. W is not positive semidefinite (a damped dynamic compliance
// above and below resonance), so several solutions may exist; but both solvers run Lemke's
// method with the covering vector 1 and the lexicographic ratio test from w = p, i.e. the same
// path, so they must end at the same basis (the same number of pivots, z0's entry aside).
constexpr double kAgreementTol = 1e-8;

bool Solves(const Eigen::MatrixXd& w, const Eigen::VectorXd& p, const Eigen::VectorXd& z) {
  const Eigen::VectorXd gap = w * z + p;
  const double z_scale = std::max(1.0, z.lpNorm<Eigen::Infinity>());
  return z.minCoeff() >= -kResidualTol * z_scale && gap.minCoeff() >= -kResidualTol &&
         gap.cwiseProduct(z).lpNorm<Eigen::Infinity>() <= kResidualTol * z_scale;
}

TEST_CASE("Siconos: nfrc's Lemke and lcp_lexicolemke on the LCP-HBM rod at N_t = 41 and 400") {
  const Case base = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/lcp/rigid_stepping_nt400.json");
  constexpr int kFrequencies = 9;   // a sweep through the contact range of the bench
  constexpr double kStart = 6.2e4;  // rad/s
  constexpr double kEnd = 6.6e4;    // rad/s
  for (int nt : {41, 400}) {
    CAPTURE(nt);
    Case the_case = base;
    the_case.harmonics = HarmonicSet(base.harmonics.max_harmonic(), base.harmonics.odd_only(), nt);
    auto system = BuildSystem(the_case);
    LcpHbm lcp(*system, the_case.laws);
    int ours_solved = 0, theirs_solved = 0, theirs_claimed = 0, agree = 0, contact = 0;
    int both = 0, same_z = 0, same_pivots = 0;
    for (int i = 0; i <= kFrequencies; ++i) {
      // The last one is ω0 = 63953.9 rad/s, the bench's first point.
      const double omega =
          i < kFrequencies ? kStart + (kEnd - kStart) * i / (kFrequencies - 1) : 63953.9;
      CAPTURE(omega);
      const LcpHbm::Problem& problem = lcp.Assemble(omega);
      const Eigen::MatrixXd w = problem.w / problem.w.cwiseAbs().maxCoeff();
      const Eigen::VectorXd p = problem.p / problem.p.cwiseAbs().maxCoeff();
      contact += p.minCoeff() < 0.0;
      const LemkeResult ours = SolveLcp(w, p);
      const SiconosLcpResult theirs = SolveLcpSiconos(w, p, SiconosLcpSolver::kLexicoLemke);
      CHECK_MESSAGE(ours.ok(), ours.message);
      CHECK(Solves(w, p, ours.z));
      ours_solved += ours.ok() && Solves(w, p, ours.z);
      theirs_claimed += theirs.ok;
      const bool theirs_ok = theirs.ok && Solves(w, p, theirs.z);
      theirs_solved += theirs_ok;
      if (!theirs_ok) MESSAGE("Siconos failed at omega " << omega << ": " << theirs.message);
      if (ours.ok() && theirs_ok) {
        ++both;
        agree += (w * theirs.z + p - ours.w).lpNorm<Eigen::Infinity>() <= kAgreementTol;
        same_z += (theirs.z - ours.z).lpNorm<Eigen::Infinity>() <=
                  kAgreementTol * std::max(1.0, ours.z.lpNorm<Eigen::Infinity>());
        // Siconos does not count z0's entry: the same path is one pivot shorter there.
        same_pivots += theirs.iterations + (ours.pivots > 0) == ours.pivots;
      }
    }
    MESSAGE("N_t = " << nt << ": " << kFrequencies + 1 << " problems (" << contact
                     << " with contact), nfrc Lemke solved " << ours_solved
                     << ", Siconos lexicolemke solved " << theirs_solved << " (claimed "
                     << theirs_claimed << "), same gap on " << agree << ", same z on " << same_z
                     << ", same path length on " << same_pivots);
    // The sweep must exercise the pivoting: most frequencies are in contact.
    CHECK(contact >= kFrequencies / 2);
    CHECK(ours_solved == kFrequencies + 1);
    CHECK(agree == both);
    CHECK(same_z == both);
    CHECK(same_pivots == both);
  }
}

}  // namespace
}  // namespace nfrc

#endif  // NFRC_HAVE_SICONOS
