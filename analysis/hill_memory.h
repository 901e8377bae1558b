#pragma once

#include <Eigen/Sparse>
#include <array>
#include <utility>
#include <vector>

#include "core/harmonic_set.h"
#include "core/nonlinearity.h"

namespace nfrc {

// Hill's method for a law with memory (Nonlinearity::Memory). On a stick piece anchored at
// θ_a the exact force perturbation is k(δu(t) − δu(t_a)): for e^{st}p(θ) the anchor's term is
// −k q(φ), φ = θ − θ_a, with q(φ) = e^{−sφ/ω} δu(θ_a), where the law's Jacobian (exact at
// s = 0) holds −k δu(θ_a). Not polynomial in s, but q solves the linear problem
//   q(0) = δu(θ_a) = bᵀp,   (s/ω) q + dq/dφ = 0 on [0, φ_end],
// which Chebyshev collocation at MemoryDegree + 1 nodes keeps linear in s, so the pencil stays
// a quadratic one with these nodal values as extra unknowns. A truncated Fourier series of q
// (a slider state in the harmonic basis) cannot do this: q jumps where the stick piece ends,
// and on the Fig. 7 Jenkins oscillator that version's multipliers were off by up to 60 %.
// The collocation's own exponents (q alone, b = 0) have Re s ≲ −ω·degree/φ_end: far
// inside the unit circle, and with no displacement they are not candidates.

// One stick piece in Hill's full unknowns.
struct HillMemory {
  MemoryPiece piece;
  double stiffness = 0.0;  // k (N/m)
  std::vector<std::pair<int, double>>
      rows;  // (full index of a force row block's coefficient 0, sign)
  // b_k: (full index, value) with (b_0 + s b_1 + s² b_2)ᵀp = δu(θ_a); b_1, b_2 only for a law
  // driven by the linear rows (LinearizationMemory::residual_terms).
  std::array<std::vector<std::pair<int, double>>, 3> anchor;
};

// Chebyshev degree of q on a piece ending φ_end after its anchor: e^{−σφ} for the central
// copies' |σ| = |s|/ω ≲ 2 is resolved to ~1e-10 by 6 + 6φ_end (the interpolation error of
// e^{zx} on [−1, 1], |z| = |σ|φ_end/2, is ~|z|^{d+1}/(d+1)!/2^d), capped at 24 (φ_end = 2π).
int MemoryDegree(double phi_end);

// Appends the piece's MemoryDegree + 1 unknowns from index `first`: their rows (the boundary
// and collocation rows) and the correction of the force rows, −k·sign·w_n∫_piece ψ_n (q(φ) −
// q(0)) dφ, to Δ0, Δ1 and Δ2 (`d`). Returns the number of unknowns added.
int AddMemoryUnknowns(const HillMemory& memory, const HarmonicSet& set, double omega, int first,
                      std::array<std::vector<Eigen::Triplet<double>>, 3>* d);

}  // namespace nfrc
