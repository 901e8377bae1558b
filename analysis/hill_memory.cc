#include "analysis/hill_memory.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <numbers>

namespace nfrc {
namespace {

// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n from Chebyshev guesses).
struct GaussRule {
  Eigen::VectorXd nodes, weights;
};

GaussRule ComputeGaussLegendre(int n) {
  GaussRule rule;
  Eigen::VectorXd* nodes = &rule.nodes;
  Eigen::VectorXd* weights = &rule.weights;
  nodes->resize(n);
  weights->resize(n);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-15) break;
    }
    (*nodes)(i) = x;
    (*weights)(i) = 2.0 / ((1.0 - x * x) * derivative * derivative);
  }
  return rule;
}

// The rule of n points, computed once per thread (a trace asks for a few sizes at every point).
const GaussRule& GaussLegendre(int n) {
  thread_local std::map<int, GaussRule> rules;
  auto found = rules.find(n);
  if (found == rules.end()) found = rules.emplace(n, ComputeGaussLegendre(n)).first;
  return found->second;
}

// Chebyshev–Lobatto nodes on [0, length] from φ = 0 (x = 1) and the derivative matrix d/dφ.
void Chebyshev(int degree, double length, Eigen::VectorXd* nodes, Eigen::MatrixXd* derivative) {
  const int m = degree + 1;
  Eigen::VectorXd x(m);
  for (int i = 0; i < m; ++i) x(i) = std::cos(std::numbers::pi * i / degree);
  *nodes = 0.5 * length * (1.0 - x.array());
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(m, m);
  for (int i = 0; i < m; ++i) {
    const double ci = (i == 0 || i == degree) ? 2.0 : 1.0;
    for (int j = 0; j < m; ++j) {
      if (i == j) continue;
      const double cj = (j == 0 || j == degree) ? 2.0 : 1.0;
      d(i, j) = (ci / cj) * (((i + j) % 2 == 0) ? 1.0 : -1.0) / (x(i) - x(j));
    }
    d(i, i) = -d.row(i).sum();
  }
  *derivative = (-2.0 / length) * d;  // dφ = −(length/2) dx
}

// ℓ_j(φ) of the nodes (barycentric form with the Chebyshev–Lobatto weights).
Eigen::VectorXd Lagrange(const Eigen::VectorXd& nodes, double phi) {
  const int m = static_cast<int>(nodes.size());
  Eigen::VectorXd values(m);
  double sum = 0.0;
  for (int j = 0; j < m; ++j) {
    const double difference = phi - nodes(j);
    if (difference == 0.0) {
      values.setZero();
      values(j) = 1.0;
      return values;
    }
    const double w = ((j % 2 == 0) ? 1.0 : -1.0) * ((j == 0 || j == m - 1) ? 0.5 : 1.0);
    values(j) = w / difference;
    sum += values(j);
  }
  return values / sum;
}

}  // namespace

int MemoryDegree(double phi_end) {
  return std::min(24, 6 + static_cast<int>(std::ceil(6.0 * phi_end)));
}

int AddMemoryUnknowns(const HillMemory& memory, const HarmonicSet& set, double omega, int first,
                      std::array<std::vector<Eigen::Triplet<double>>, 3>* d) {
  std::vector<Eigen::Triplet<double>>* d0 = &(*d)[0];
  std::vector<Eigen::Triplet<double>>* d1 = &(*d)[1];
  const MemoryPiece& piece = memory.piece;
  const double begin = piece.begin - piece.anchor, end = piece.end - piece.anchor;
  assert(begin >= 0.0 && end > begin && "a stick piece follows its anchor");
  const int degree = MemoryDegree(end);
  const int m = degree + 1;
  Eigen::VectorXd nodes;
  Eigen::MatrixXd derivative;
  Chebyshev(degree, end, &nodes, &derivative);

  // q(0) = (b_0 + s b_1 + s² b_2)ᵀp.
  d0->emplace_back(first, first, 1.0);
  for (size_t k = 0; k < 3; ++k) {
    for (const auto& [column, value] : memory.anchor[k])
      (*d)[k].emplace_back(first, column, -value);
  }
  // (s/ω) q + dq/dφ = 0 at the other nodes.
  for (int i = 1; i < m; ++i) {
    for (int j = 0; j < m; ++j) d0->emplace_back(first + i, first + j, derivative(i, j));
    d1->emplace_back(first + i, first + i, 1.0 / omega);
  }

  // W_nj = w_n ∫_piece ψ_n(θ_a + φ) ℓ_j(φ) dφ by Gauss–Legendre of G points, exact to degree
  // 2G − 1: ℓ_j's degree plus that of a polynomial resolving harmonic H over the piece
  // (≤ e·H·length/4, length ≤ 2π), rounded up to a multiple of 8 so that a trace reuses a few
  // rules.
  const int nc = set.NumCoefficients();
  const double length = end - begin;
  const int points =
      8 * ((degree + static_cast<int>(0.7 * set.max_harmonic() * length) + 16 + 7) / 8);
  const GaussRule& rule = GaussLegendre(points);
  Eigen::MatrixXd samples(nc, points), lagrange(points, m);
  Eigen::VectorXd basis(nc);
  const double half = 0.5 * length, middle = 0.5 * (end + begin);
  for (int g = 0; g < points; ++g) {
    const double phi = middle + half * rule.nodes(g);
    set.Basis(piece.anchor + phi, basis);
    samples.col(g) = (half * rule.weights(g)) * basis;
    lagrange.row(g) = Lagrange(nodes, phi).transpose();
  }
  Eigen::MatrixXd weights = samples * lagrange;
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const double projection = set.harmonics()[static_cast<size_t>(p)] == 0
                                  ? 1.0 / (2.0 * std::numbers::pi)
                                  : 1.0 / std::numbers::pi;
    weights.row(set.CosIndex(p)) *= projection;
    if (set.SinIndex(p) != set.CosIndex(p)) weights.row(set.SinIndex(p)) *= projection;
  }
  // −k(q(φ) − q(0)) on the piece: Σ_j ℓ_j = 1, so q(0)'s column takes −Σ_j W_nj besides W_n0.
  const Eigen::VectorXd ones = weights.rowwise().sum();
  for (const auto& [base, sign] : memory.rows) {
    const double factor = -memory.stiffness * sign;
    for (int n = 0; n < nc; ++n) {
      for (int j = 0; j < m; ++j) {
        const double value = factor * (weights(n, j) - (j == 0 ? ones(n) : 0.0));
        if (value != 0.0) d0->emplace_back(base + n, first + j, value);
      }
    }
  }
  return m;
}

}  // namespace nfrc
