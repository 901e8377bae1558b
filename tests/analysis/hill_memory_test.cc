// The memory of a hysteretic law in Hill's pencil (analysis/hill_memory.h) against the closed
// form of what it discretises: the force correction −k·w_n∫_piece ψ_n (e^{−sφ/ω} − 1) dφ·q(0),
// integrated analytically here, and nothing at all at s = 0.
#include "analysis/hill_memory.h"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <array>
#include <complex>
#include <numbers>
#include <vector>

namespace nfrc {
namespace {

using Complex = std::complex<double>;

// Chebyshev interpolation of e^{−σφ} at MemoryDegree for |σ| ≤ 1.8 (below) errs by ≲1e-10; the
// collocation solve and the Gauss–Legendre weights add round-off of the entries' size. 1e-9
// relative to the correction's largest coefficient leaves margin.
constexpr double kMemoryTolerance = 1e-9;

// ∫_a^b e^{−σ(θ−θ_a)} e^{iκθ} dθ in closed form (σ ≠ iκ here).
Complex Moment(double anchor, double begin, double end, double kappa, Complex sigma) {
  const Complex z(-sigma.real(), kappa - sigma.imag());
  auto primitive = [&](double phi) { return (std::exp(z * phi) - 1.0) / z; };
  return std::polar(1.0, kappa * anchor) * (primitive(end - anchor) - primitive(begin - anchor));
}

// w_n ∫_piece ψ_n (e^{−sφ/ω} − 1) dθ for an odd-only set (no constant).
Eigen::VectorXcd ClosedForm(const HarmonicSet& set, const MemoryPiece& piece, double omega,
                            Complex s) {
  Eigen::VectorXcd result(set.NumCoefficients());
  const Complex i(0.0, 1.0);
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const double k = set.harmonics()[static_cast<size_t>(p)];
    const Complex plus = Moment(piece.anchor, piece.begin, piece.end, k, s / omega) -
                         Moment(piece.anchor, piece.begin, piece.end, k, 0.0);
    const Complex minus = Moment(piece.anchor, piece.begin, piece.end, -k, s / omega) -
                          Moment(piece.anchor, piece.begin, piece.end, -k, 0.0);
    result(set.CosIndex(p)) = (plus + minus) / (2.0 * std::numbers::pi);
    result(set.SinIndex(p)) = (plus - minus) / (2.0 * i * std::numbers::pi);
  }
  return result;
}

// The memory of one piece on unknowns [p (nc) | q]: rows 0..nc−1 take the force, b = φ(θ_a).
// Eliminates q at exponent s: force correction = −W_pq (W_qq(s))⁻¹ W_qp.
Eigen::MatrixXcd Correction(const HarmonicSet& set, const MemoryPiece& piece, double omega,
                            double stiffness, Complex s) {
  const int nc = set.NumCoefficients();
  HillMemory memory;
  memory.piece = piece;
  memory.stiffness = stiffness;
  memory.rows = {{0, 1.0}};
  const Eigen::VectorXd basis = set.Basis(piece.anchor);
  for (int c = 0; c < nc; ++c) memory.anchor[0].emplace_back(c, basis(c));
  std::array<std::vector<Eigen::Triplet<double>>, 3> d;
  const int m = AddMemoryUnknowns(memory, set, omega, nc, &d);
  const std::vector<Eigen::Triplet<double>>&d0 = d[0], &d1 = d[1];
  REQUIRE(d[2].empty());
  REQUIRE(m == MemoryDegree(piece.end - piece.anchor) + 1);
  Eigen::SparseMatrix<double> a0(nc + m, nc + m), a1(nc + m, nc + m);
  a0.setFromTriplets(d0.begin(), d0.end());
  a1.setFromTriplets(d1.begin(), d1.end());
  const Eigen::MatrixXcd t =
      Eigen::MatrixXd(a0).cast<Complex>() + s * Eigen::MatrixXd(a1).cast<Complex>();
  const Eigen::MatrixXcd qq = t.bottomRightCorner(m, m), qp = t.bottomLeftCorner(m, nc);
  const Eigen::MatrixXcd pq = t.topRightCorner(nc, m);
  return -pq * qq.partialPivLu().solve(qp);
}

TEST_CASE("Hill memory: the collocated Floquet factor gives the closed-form force correction") {
  const double omega = 0.7, stiffness = 3.0;
  // A stick piece starting at its anchor, one starting later (a phase crossing θ = 2π is
  // unwrapped: end beyond 2π), one over almost the whole period and a short one (degree 10); H = 15
  // and the Fig. 7 cases' 59, whose quadrature needs the most points.
  for (const int h : {15, 59}) {
    const HarmonicSet set(h, true, 4 * (h + 1));
    for (const MemoryPiece piece : {MemoryPiece{0.4, 0.4, 4.9}, MemoryPiece{5.0, 5.6, 7.9},
                                    MemoryPiece{1.0, 1.0, 7.2}, MemoryPiece{2.0, 2.0, 2.6}}) {
      for (const Complex s : {Complex(-0.05, 0.3), Complex(0.02, -0.61), Complex(-0.3, 1.2)}) {
        CAPTURE(h);
        CAPTURE(piece.anchor);
        CAPTURE(s);
        const Eigen::MatrixXcd discretised = Correction(set, piece, omega, stiffness, s);
        // Exact: −k·g_n(s)·φ(θ_a)ᵀp.
        const Eigen::MatrixXcd exact = -stiffness * ClosedForm(set, piece, omega, s) *
                                       set.Basis(piece.anchor).transpose().cast<Complex>();
        const double error =
            (discretised - exact).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
        MESSAGE("piece [" << piece.begin << ", " << piece.end << "] from " << piece.anchor
                          << ", s = " << s << ": relative error " << error);
        CHECK(error < kMemoryTolerance);
      }
    }
  }
}

TEST_CASE("Hill memory: nothing at s = 0, where the law's Jacobian is exact (folds)") {
  const HarmonicSet set(15, true, 256);
  const Eigen::MatrixXcd correction = Correction(set, MemoryPiece{1.0, 1.0, 5.5}, 0.7, 3.0, 0.0);
  CHECK(correction.cwiseAbs().maxCoeff() < 1e-12 * 3.0);
}

}  // namespace
}  // namespace nfrc
