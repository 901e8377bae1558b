#include "analysis/hill.h"

#include <Spectra/GenEigsRealShiftSolver.h>

#include <Eigen/SparseLU>
#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "analysis/hill_memory.h"
#include "analysis/hill_product.h"
#include "analysis/hill_solver.h"

namespace nfrc {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;
using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
using Complex = std::complex<double>;

// The real shift of shift-invert, as a fraction of ω: off the imaginary axis so that the
// exponent 0 of a fold does not make the shifted Hill matrix singular.
constexpr double kShiftFraction = 1e-2;
// An exponent with |s − σ| above this many (H + 1)·ω lies beyond the band Hill's truncated
// matrix resolves: it is an infinite exponent of the algebraic rows (massless DOFs, a
// friction law's stick constraint v = 0, which is of index 2) that rounding made finite.
// Seen on the one-DOF Coulomb oscillator in stick-slip at |s| ≈ 1e3–1e6·ω.
constexpr double kBandFactor = 10.0;
// Copies s + ikω of one family share Re s and Im s modulo ω up to the truncation of Hill's
// matrix (1e-4·ω seen on the rod at H = 20); two candidates that agree to this fraction of ω
// are one family (their multipliers agree to 2π·1e-3 ≈ 0.6 %). Distinct physical multipliers
// closer than that, or a complex pair within 3e-3 rad of the real axis, are reported once.
constexpr double kSameExponent = 1e-3;
// With a law's memory the force perturbation jumps where a stick piece ends, its harmonics
// decay as 1/k, and copies agree less: 1.4e-3·ω between the central copy of a real multiplier
// and its neighbours on the Fig. 7 Jenkins oscillator at ω = 0.2 (H = 59). Multipliers closer
// than 2π·5e-3 ≈ 3 % are then reported once.
constexpr double kSameExponentMemory = 5e-3;
// A copy whose eigenvector has more than this share of its weight in the top quarter of the
// harmonics is shaped by the truncation, not by the dynamics: it is not used.
constexpr double kEdgeLimit = 0.25;
// With a few harmonics every one is "top quarter": harmonics up to this one never count as
// the edge (H = 1 would otherwise drop every copy).
constexpr int kSmallestEdgeHarmonic = 2;

// Adds scale·(A ⊗ B) in the DOF-major layout: entry (i·nc + r, j·nc + c) = scale·A_ij·B_rc.
void AddKronecker(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b,
                  double scale, Triplets* triplets) {
  const int nc = static_cast<int>(b.rows());
  for (int k = 0; k < a.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it) {
      for (int c = 0; c < b.outerSize(); ++c) {
        for (Eigen::SparseMatrix<double>::InnerIterator jt(b, c); jt; ++jt) {
          triplets->emplace_back(static_cast<int>(it.row()) * nc + static_cast<int>(jt.row()),
                                 static_cast<int>(it.col()) * nc + static_cast<int>(jt.col()),
                                 scale * it.value() * jt.value());
        }
      }
    }
  }
}

// Where an index of the condensed unknowns y lands in the full Hill unknowns: a relative
// displacement x − u at a DOF with an obstacle is two entries (x: +1, u: −1).
struct Target {
  int index;
  double sign;
};

struct Targets {
  std::array<Target, 2> entries;
  int count;
};

// Adds a condensed-layout law matrix to a full-layout one (rows and columns mapped alike:
// the obstacle row takes the reaction −f_nl).
void AddMapped(const Eigen::MatrixXd& law, const std::vector<Targets>& map, Triplets* triplets) {
  for (int j = 0; j < law.cols(); ++j) {
    const Targets& columns = map[static_cast<size_t>(j)];
    for (int i = 0; i < law.rows(); ++i) {
      const double value = law(i, j);
      if (value == 0.0) continue;
      const Targets& rows = map[static_cast<size_t>(i)];
      for (int r = 0; r < rows.count; ++r) {
        for (int c = 0; c < columns.count; ++c) {
          const Target& row = rows.entries[static_cast<size_t>(r)];
          const Target& column = columns.entries[static_cast<size_t>(c)];
          triplets->emplace_back(row.index, column.index, row.sign * column.sign * value);
        }
      }
    }
  }
}

// A law's memory in the full unknowns: one HillMemory per stick piece, its rows at the mapped
// coefficient-0 row of each force DOF (a DOF block maps to contiguous full indices) and its
// anchor row δu(θ_a) = Σ c_i φ(θ_a)·x_i over the mapped columns.
// `linear_rows`: the full model's rows of Δ0, Δ1, Δ2 (row-major), for residual_terms.
void AddMemory(const LinearizationMemory& law_memory, const NonlinearityContext& ctx,
               const std::vector<int>& dofs, const HarmonicSet& set,
               const std::vector<Targets>& map, const std::array<RowMatrix, 3>* linear_rows,
               std::vector<HillMemory>* out) {
  const int nc = set.NumCoefficients();
  std::vector<std::pair<int, double>> rows;
  for (const auto& [dof_index, row_sign] : law_memory.rows) {
    const Targets& targets = map[static_cast<size_t>(ctx.DofOffset(dof_index))];
    for (int r = 0; r < targets.count; ++r) {
      const Target& target = targets.entries[static_cast<size_t>(r)];
      rows.emplace_back(target.index, target.sign * row_sign);
    }
  }
  for (const MemoryPiece& piece : law_memory.pieces) {
    HillMemory& memory = out->emplace_back();
    memory.piece = piece;
    memory.stiffness = law_memory.stiffness;
    memory.rows = rows;
    const Eigen::VectorXd basis = set.Basis(piece.anchor);
    for (const auto& [dof_index, coefficient] : law_memory.terms) {
      for (int c = 0; c < nc; ++c) {
        if (basis(c) == 0.0) continue;
        const Targets& targets = map[static_cast<size_t>(ctx.DofOffset(dof_index) + c)];
        for (int r = 0; r < targets.count; ++r) {
          const Target& target = targets.entries[static_cast<size_t>(r)];
          memory.anchor[0].emplace_back(target.index, target.sign * coefficient * basis(c));
        }
      }
    }
    if (law_memory.residual_terms.empty()) continue;
    assert(linear_rows != nullptr && "residual terms need the linear rows");
    for (size_t k = 0; k < 3; ++k) {
      Eigen::VectorXd row = Eigen::VectorXd::Zero((*linear_rows)[k].cols());
      for (const auto& [dof_index, coefficient] : law_memory.residual_terms) {
        const int first = dofs[static_cast<size_t>(dof_index)] * nc;
        for (int c = 0; c < nc; ++c) {
          if (basis(c) == 0.0) continue;
          for (RowMatrix::InnerIterator it((*linear_rows)[k], first + c); it; ++it) {
            row(it.col()) += coefficient * basis(c) * it.value();
          }
        }
      }
      for (Eigen::Index j = 0; j < row.size(); ++j) {
        if (row(j) != 0.0) memory.anchor[k].emplace_back(static_cast<int>(j), row(j));
      }
    }
  }
}

Eigen::SparseMatrix<double> FromTriplets(const Triplets& triplets, int size) {
  Eigen::SparseMatrix<double> matrix(size, size);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  return matrix;
}

// Where a dense law matrix's non-zeros lie, column by column (each column read from its ends
// to its first non-zeros): the merges and the block test below read only these rows.
struct ColumnSpans {
  std::vector<int> first, last;  // per column, its first and last non-zero row (last < first: none)
  Eigen::Index bound = 0;        // the spans' lengths summed: at least the non-zeros
};

ColumnSpans SpansOf(const Eigen::MatrixXd& law) {
  const int m = static_cast<int>(law.rows());
  ColumnSpans spans;
  spans.first.assign(static_cast<size_t>(law.cols()), 0);
  spans.last.assign(static_cast<size_t>(law.cols()), -1);
  for (Eigen::Index j = 0; j < law.cols(); ++j) {
    const double* column = law.col(j).data();
    int first = 0, last = m - 1;
    while (first < m && column[first] == 0.0) ++first;
    if (first == m) continue;
    while (column[last] == 0.0) --last;
    spans.first[static_cast<size_t>(j)] = first;
    spans.last[static_cast<size_t>(j)] = last;
    spans.bound += last - first + 1;
  }
  return spans;
}

// linear + the condensed-layout `law` placed at rows and columns `targets` (one full index
// per condensed unknown, increasing; `condensed` is its inverse, −1 off the map), merged
// column by column: the same sums as adding the mapped triplets' matrix, without building and
// sorting them (a 640 × 640 law's 400 000 entries per matrix and point at N_φ = 160).
// law_entries (optional): the law's non-zeros, counted in the same pass.
Eigen::SparseMatrix<double> PlusMapped(const Eigen::SparseMatrix<double>& linear,
                                       const Eigen::MatrixXd& law, const ColumnSpans& spans,
                                       const std::vector<int>& targets,
                                       const std::vector<int>& condensed,
                                       Eigen::Index* law_entries = nullptr) {
  assert(linear.isCompressed());
  const int size = static_cast<int>(linear.rows());
  const int* linear_outer = linear.outerIndexPtr();
  const int* linear_inner = linear.innerIndexPtr();
  const double* linear_values = linear.valuePtr();
  // Filled through the raw arrays, sized for both parts and trimmed at the end: insertBack's
  // per-entry bookkeeping made this merge 7 % of point E's curve.
  Eigen::SparseMatrix<double> result(size, size);
  result.resizeNonZeros(linear.nonZeros() + spans.bound);
  int* outer = result.outerIndexPtr();
  int* inner = result.innerIndexPtr();
  double* values = result.valuePtr();
  int k = 0;
  Eigen::Index count = 0;
  for (int col = 0; col < size; ++col) {
    outer[col] = k;
    int p = linear_outer[col];
    const int end = linear_outer[col + 1];
    const int j = condensed[static_cast<size_t>(col)];
    if (j >= 0) {
      const double* column = law.col(j).data();
      const int last = spans.last[static_cast<size_t>(j)];
      for (int i = spans.first[static_cast<size_t>(j)]; i <= last; ++i) {
        if (column[i] == 0.0) continue;
        const int row = targets[static_cast<size_t>(i)];
        for (; p < end && linear_inner[p] < row; ++p, ++k) {
          inner[k] = linear_inner[p];
          values[k] = linear_values[p];
        }
        inner[k] = row;
        values[k] = p < end && linear_inner[p] == row ? linear_values[p++] + column[i] : column[i];
        ++k;
        ++count;
      }
    }
    for (; p < end; ++p, ++k) {
      inner[k] = linear_inner[p];
      values[k] = linear_values[p];
    }
  }
  outer[size] = k;
  result.data().resize(k);
  if (law_entries != nullptr) *law_entries = count;
  return result;
}

// Below this share of non-zeros a block's dense product does more work than the sparse one.
constexpr double kFullBlockShare = 0.5;

// The non-zeros of a condensed-layout law matrix (`count` of them) as one dense block of the
// full layout (rows and columns at `targets`, increasing), where their bounding box maps to
// contiguous full rows and columns and is at least kFullBlockShare non-zero.
std::optional<HillFactors::DenseBlock> NearlyFullBlock(const Eigen::MatrixXd& law,
                                                       const ColumnSpans& spans, Eigen::Index count,
                                                       const std::vector<int>& targets) {
  if (count == 0) return std::nullopt;
  Eigen::Index r0 = law.rows(), r1 = -1, c0 = law.cols(), c1 = -1;
  for (Eigen::Index j = 0; j < law.cols(); ++j) {
    if (spans.last[static_cast<size_t>(j)] < spans.first[static_cast<size_t>(j)]) continue;
    c0 = std::min(c0, j);
    c1 = j;
    r0 = std::min<Eigen::Index>(r0, spans.first[static_cast<size_t>(j)]);
    r1 = std::max<Eigen::Index>(r1, spans.last[static_cast<size_t>(j)]);
  }
  const auto at = [&](Eigen::Index i) { return targets[static_cast<size_t>(i)]; };
  if (at(r1) - at(r0) != r1 - r0 || at(c1) - at(c0) != c1 - c0) return std::nullopt;
  const Eigen::Index rows = r1 - r0 + 1, cols = c1 - c0 + 1;
  if (static_cast<double>(count) < kFullBlockShare * static_cast<double>(rows * cols)) {
    return std::nullopt;
  }
  return HillFactors::DenseBlock{at(r0), at(c0), law.block(r0, c0, rows, cols)};
}

// The rows of a dependence's force (nc × size) placed at each target block (its first
// unknown, ascending and disjoint, and its sign), as one matrix of the pencil's size.
Eigen::SparseMatrix<double> PlacedRows(const Eigen::MatrixXd& force,
                                       const std::vector<std::pair<int, double>>& targets,
                                       int size) {
  const int nc = static_cast<int>(force.rows());
  Eigen::SparseMatrix<double> result(size, size);
  result.reserve(static_cast<Eigen::Index>(targets.size()) * (force.array() != 0.0).count());
  for (int j = 0; j < size; ++j) {
    result.startVec(j);
    for (const auto& [first, sign] : targets) {
      for (int c = 0; c < nc; ++c) {
        const double value = force(c, j);
        if (value != 0.0) result.insertBack(first + c, j) = sign * value;
      }
    }
  }
  result.finalize();
  return result;
}

}  // namespace

// The parts of the pencil that depend on neither y nor ω, each of the full size.
struct HillAssembler::Cache {
  int size = 0;
  Eigen::SparseMatrix<double> stiffness;  // K⊗I plus the obstacles' springs
  Eigen::SparseMatrix<double> damping_d;  // C⊗D
  Eigen::SparseMatrix<double> mass_dd;    // M⊗D²
  Eigen::SparseMatrix<double> damping;    // C⊗I
  Eigen::SparseMatrix<double> mass_d;     // M⊗D
  Eigen::SparseMatrix<double> mass;       // M⊗I
  std::vector<Targets> map;               // per unknown of the system
  // map's single targets where each unknown has one and they increase (else empty): the
  // laws' matrices are then merged into the linear ones directly (PlusMapped), and the
  // inverse: each full unknown's condensed index, −1 for the others.
  std::vector<int> increasing_targets;
  std::vector<int> condensed_of;
  HillPencil shape;     // set, dynamic, signal offsets, state dimension
  HillFactors factors;  // Cᵀ, Mᵀ and D (the laws' parts are the point's)
};

HillAssembler::HillAssembler(HarmonicSystem& system, std::shared_ptr<const HillModel> reduced)
    : system_(system), reduced_(std::move(reduced)), cache_(std::make_unique<Cache>()) {
  const LinearModel& model = reduced_ ? reduced_->model : system.model();
  const HarmonicSet& set = system.harmonic_set();
  const int nc = set.NumCoefficients();
  const int n = static_cast<int>(model.mass.rows());
  // Sparse: D is 2 × 2 per harmonic, and a dense D·D was 4 Gflop at N_φ = 640.
  Eigen::SparseMatrix<double> identity(nc, nc);
  identity.setIdentity();
  const Eigen::SparseMatrix<double> d = system.fourier().DerivativeMatrix().sparseView();

  // Flexible obstacles: one massless block per retained DOF backed by one, after the DOFs.
  const int num_retained = system.num_displacement_unknowns() / nc;
  std::vector<int> obstacle_offset(static_cast<size_t>(num_retained), -1);
  Triplets obstacles;
  int next = n * nc;
  for (size_t i = 0; i < system.laws().size(); ++i) {
    const std::vector<double> compliance = system.laws()[i]->ObstacleCompliance();
    for (size_t j = 0; j < compliance.size(); ++j) {
      if (compliance[j] <= 0.0) continue;
      const int local = system.context(static_cast<int>(i)).local_dofs[j];
      obstacle_offset[static_cast<size_t>(local)] = next;
      for (int c = 0; c < nc; ++c) obstacles.emplace_back(next + c, next + c, 1.0 / compliance[j]);
      next += nc;
    }
  }
  const int own_offset = next;
  Cache& cache = *cache_;
  cache.size = own_offset + system.NumUnknowns() - system.num_displacement_unknowns();
  const int size = cache.size;

  Triplets triplets = obstacles;
  AddKronecker(model.stiffness, identity, 1.0, &triplets);
  cache.stiffness = FromTriplets(triplets, size);
  const auto kronecker = [&](const Eigen::SparseMatrix<double>& a,
                             const Eigen::SparseMatrix<double>& b) {
    Triplets t;
    AddKronecker(a, b, 1.0, &t);
    return FromTriplets(t, size);
  };
  cache.damping_d = kronecker(model.damping, d);
  cache.mass_dd = kronecker(model.mass, Eigen::SparseMatrix<double>(d * d));
  cache.damping = kronecker(model.damping, identity);
  cache.mass_d = kronecker(model.mass, d);
  cache.mass = kronecker(model.mass, identity);
  cache.factors.damping_t = model.damping.transpose();
  cache.factors.mass_t = model.mass.transpose();
  cache.factors.derivative = d;

  const int nx = system.num_displacement_unknowns();
  cache.map.resize(static_cast<size_t>(system.NumUnknowns()));
  for (int j = 0; j < system.NumUnknowns(); ++j) {
    Targets& targets = cache.map[static_cast<size_t>(j)];
    if (j >= nx) {
      targets = {{Target{own_offset + j - nx, 1.0}, Target{0, 0.0}}, 1};
      continue;
    }
    const int local = j / nc, c = j % nc;
    const int dof = PencilDof(system.retained()[static_cast<size_t>(local)]);
    targets = {{Target{dof * nc + c, 1.0}, Target{0, 0.0}}, 1};
    if (obstacle_offset[static_cast<size_t>(local)] >= 0) {
      targets.entries[1] = Target{obstacle_offset[static_cast<size_t>(local)] + c, -1.0};
      targets.count = 2;
    }
  }

  for (const Targets& targets : cache.map) {
    const int index = targets.entries[0].index;
    if (targets.count != 1 || targets.entries[0].sign != 1.0 ||
        (!cache.increasing_targets.empty() && index <= cache.increasing_targets.back())) {
      cache.increasing_targets.clear();
      break;
    }
    cache.increasing_targets.push_back(index);
  }
  if (!cache.increasing_targets.empty()) {
    cache.condensed_of.assign(static_cast<size_t>(size), -1);
    for (size_t j = 0; j < cache.increasing_targets.size(); ++j) {
      cache.condensed_of[static_cast<size_t>(cache.increasing_targets[j])] = static_cast<int>(j);
    }
  }

  HillPencil& shape = cache.shape;
  shape.set = set;
  shape.own_offset = own_offset;
  for (int dof = 0; dof < n; ++dof) {
    if (model.mass.coeff(dof, dof) > 0.0) {
      shape.signal_offsets.push_back(dof * nc);
      for (int c = 0; c < nc; ++c) shape.dynamic.push_back(dof * nc + c);
      shape.state_dimension += 2;
    } else if (model.damping.coeff(dof, dof) > 0.0) {
      shape.state_dimension += 1;  // a massless damped DOF is a first-order state
    }
  }
}

HillAssembler::~HillAssembler() = default;

int HillAssembler::PencilDof(int dof) const {
  if (!reduced_) return dof;
  const int kept = reduced_->dof_of[static_cast<size_t>(dof)];
  assert(kept >= 0 && "a reduction for Hill keeps every retained DOF");
  return kept;
}

std::vector<int> HillAssembler::PencilDofs(std::vector<int> dofs) const {
  for (int& dof : dofs) dof = PencilDof(dof);
  return dofs;
}

HillPencil HillAssembler::Assemble(const Eigen::VectorXd& y, double omega) {
  // The linear part and the laws' binding only: each law evaluates itself as it linearises.
  // The points analysed are solutions, whose residual and Jacobian the corrector found finite
  // (the whole residual evaluated here as a check was 1.4–2.6 % of a worker's samples).
  const auto refuse = [omega](const std::string& why) {
    return std::runtime_error(
        "Hill: the system cannot be evaluated at omega = " + std::to_string(omega) + ": " + why);
  };
  if (!y.allFinite()) throw refuse("y is not finite");
  if (!system_.Prepare(omega)) throw refuse(system_.last_error());
  const Cache& cache = *cache_;
  const int size = cache.size;
  const int nc = system_.harmonic_set().NumCoefficients();
  // The linear part of each matrix (Δ2's is the cached M⊗I itself).
  const Eigen::SparseMatrix<double> d0_linear =
      cache.stiffness + omega * cache.damping_d + (omega * omega) * cache.mass_dd;
  const Eigen::SparseMatrix<double> d1_linear = cache.damping + (2.0 * omega) * cache.mass_d;
  const std::array<const Eigen::SparseMatrix<double>*, 3> linear = {&d0_linear, &d1_linear,
                                                                    &cache.mass};
  // Its rows in row-major order, for laws whose force is predicted from them (DLFT).
  std::optional<std::array<RowMatrix, 3>> linear_rows;
  std::array<Triplets, 3> laws;
  // The dependences' entries of Δ0, Δ1 and Δ2 (in the pencil's matrices, not in laws_d1 and
  // laws_d2: HillProduct takes them from the linear product).
  std::array<Eigen::SparseMatrix<double>, 3> dependent;
  HillPencil pencil = cache.shape;
  pencil.omega = omega;
  HillFactors& factors = pencil.factors.emplace(cache.factors);
  std::vector<HillMemory> memory;
  const int m = system_.NumUnknowns();
  // The laws' Jacobians, summed over the laws (each adds its own).
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(m, m);
  Eigen::MatrixXd velocity = Eigen::MatrixXd::Zero(m, m);
  for (size_t i = 0; i < system_.laws().size(); ++i) {
    const Nonlinearity& law = *system_.laws()[i];
    const NonlinearityContext& ctx = system_.context(static_cast<int>(i));
    law.LinearizeForStability(ctx, y, omega, &jacobian, &velocity);
    if (const auto law_memory = law.Memory(ctx, y, omega)) {
      if (!law_memory->residual_terms.empty() && !linear_rows) {
        linear_rows.emplace(std::array<RowMatrix, 3>{*linear[0], *linear[1], *linear[2]});
      }
      AddMemory(*law_memory, ctx, PencilDofs(law.Dofs()), system_.harmonic_set(), cache.map,
                linear_rows ? &*linear_rows : nullptr, &memory);
    }
    const auto dependence = law.LinearResidualPart(ctx, y, omega);
    if (!dependence) continue;
    if (!linear_rows)
      linear_rows.emplace(std::array<RowMatrix, 3>{*linear[0], *linear[1], *linear[2]});
    const std::vector<int> dofs = PencilDofs(law.Dofs());
    HillFactors::RowDependence& structured = factors.dependences.emplace_back();
    structured.weights = dependence->weights;
    for (const auto& [dof_index, coefficient] : dependence->terms) {
      structured.terms.emplace_back(dofs[static_cast<size_t>(dof_index)], coefficient);
    }
    for (const auto& [dof_index, row_sign] : dependence->rows) {
      const Targets& rows = cache.map[static_cast<size_t>(ctx.DofOffset(dof_index))];
      for (int r = 0; r < rows.count; ++r) {
        const Target& row = rows.entries[static_cast<size_t>(r)];
        structured.rows.emplace_back(row.index, row.sign * row_sign);
      }
    }
    std::sort(structured.rows.begin(), structured.rows.end());
    for (size_t k = 0; k < 3; ++k) {
      // The linear rows are sparse (a DOF's neighbours): W times them costs nc·nnz.
      Eigen::MatrixXd force = Eigen::MatrixXd::Zero(nc, size);
      for (const auto& [dof, coefficient] : structured.terms) {
        force.noalias() +=
            coefficient * (structured.weights * (*linear_rows)[k].middleRows(dof * nc, nc));
      }
      const Eigen::SparseMatrix<double> placed = PlacedRows(force, structured.rows, size);
      dependent[k] =
          dependent[k].size() == 0 ? placed : Eigen::SparseMatrix<double>(dependent[k] + placed);
    }
  }

  const bool only_jacobians =
      memory.empty() && factors.dependences.empty() && !cache.increasing_targets.empty();
  // The entries the factored product replaces by Kronecker products (Δ1's and Δ2's linear
  // parts): the factors are kept only where the laws' rest of Δ1 and Δ2 has fewer.
  const Eigen::Index linear_entries = d1_linear.nonZeros() + cache.mass.nonZeros();
  if (only_jacobians) {
    const ColumnSpans velocity_spans = SpansOf(velocity);
    pencil.d0 = PlusMapped(d0_linear, jacobian, SpansOf(jacobian), cache.increasing_targets,
                           cache.condensed_of);
    Eigen::Index velocity_entries = 0;
    pencil.d1 = PlusMapped(d1_linear, velocity, velocity_spans, cache.increasing_targets,
                           cache.condensed_of, &velocity_entries);
    pencil.d2 = cache.mass;
    factors.laws_d2.resize(size, size);
    // A friction force's velocity block: one dense product instead of a scatter per entry.
    if (auto block =
            NearlyFullBlock(velocity, velocity_spans, velocity_entries, cache.increasing_targets)) {
      factors.laws_d1.resize(size, size);
      factors.laws_d1_block = std::move(block);
      return pencil;
    }
    // The law's entries outside the linear pattern, at least: where they dominate (a velocity
    // Jacobian spread over several blocks) the factors would save nothing and double them.
    if (pencil.d1.nonZeros() - d1_linear.nonZeros() >= linear_entries) {
      pencil.factors.reset();
      return pencil;
    }
    factors.laws_d1 = PlusMapped(Eigen::SparseMatrix<double>(size, size), velocity, velocity_spans,
                                 cache.increasing_targets, cache.condensed_of);
    return pencil;
  }
  // The Jacobians' triplets first, then the memory's (AddMemoryUnknowns, below).
  for (size_t k = 0; k < 2; ++k) AddMapped(k == 0 ? jacobian : velocity, cache.map, &laws[k]);
  // Each matrix: its linear part, the laws' mapped Jacobians and memory terms, and the
  // dependences' rows.
  const auto with = [&](const Eigen::SparseMatrix<double>& sum, size_t k, int total) {
    if (dependent[k].size() == 0) return sum;
    if (dependent[k].rows() != total) dependent[k].conservativeResize(total, total);
    return Eigen::SparseMatrix<double>(sum + dependent[k]);
  };
  if (memory.empty()) {
    factors.laws_d1 = FromTriplets(laws[1], size);
    assert(laws[2].empty() && "only the memory's terms reach the laws' part of Δ2");
    factors.laws_d2.resize(size, size);
    pencil.d0 = with(d0_linear + FromTriplets(laws[0], size), 0, size);
    pencil.d1 = with(d1_linear + factors.laws_d1, 1, size);
    pencil.d2 = with(cache.mass, 2, size);
    if (factors.laws_d1.nonZeros() >= linear_entries) pencil.factors.reset();
    return pencil;
  }
  // The memory's unknowns after every other (algebraic: no Δ2). With own unknowns they join
  // them in the linear solver's Schur complement; without, the solver factorises the whole.
  int total = size;
  for (const HillMemory& piece : memory) {
    total += AddMemoryUnknowns(piece, system_.harmonic_set(), omega, total, &laws);
  }
  pencil.memory_unknowns = total - size;
  auto grown = [total](const Eigen::SparseMatrix<double>& matrix) {
    Eigen::SparseMatrix<double> result = matrix;
    result.conservativeResize(total, total);
    return result;
  };
  factors.laws_d1 = FromTriplets(laws[1], total);
  factors.laws_d2 = FromTriplets(laws[2], total);
  pencil.d0 = with(grown(d0_linear) + FromTriplets(laws[0], total), 0, total);
  pencil.d1 = with(grown(d1_linear) + factors.laws_d1, 1, total);
  pencil.d2 = with(grown(cache.mass) + factors.laws_d2, 2, total);
  if (factors.laws_d1.nonZeros() + factors.laws_d2.nonZeros() >= linear_entries) {
    pencil.factors.reset();
  }
  return pencil;
}

HillPencil AssembleHillPencil(HarmonicSystem& system, const Eigen::VectorXd& y, double omega) {
  return HillAssembler(system).Assemble(y, omega);
}

int DisplacementEnd(const HillPencil& pencil) {
  return pencil.own_offset < 0 ? static_cast<int>(pencil.d0.rows()) : pencil.own_offset;
}

std::vector<int> DisplacementHarmonics(const HillPencil& pencil) {
  const HarmonicSet& set = pencil.set;
  std::vector<int> of_coefficient(static_cast<size_t>(set.NumCoefficients()));
  for (int p = 0; p < set.num_harmonics(); ++p) {
    of_coefficient[static_cast<size_t>(set.CosIndex(p))] = p;
    of_coefficient[static_cast<size_t>(set.SinIndex(p))] = p;
  }
  // Memory unknowns without own unknowns end the displacement range: a group of their own.
  const int end = DisplacementEnd(pencil) - (pencil.own_offset < 0 ? pencil.memory_unknowns : 0);
  std::vector<int> harmonics(static_cast<size_t>(DisplacementEnd(pencil)), set.num_harmonics());
  for (int i = 0; i < end; ++i) {
    harmonics[static_cast<size_t>(i)] =
        of_coefficient[static_cast<size_t>(i % set.NumCoefficients())];
  }
  return harmonics;
}

// One merge through the raw arrays (Eigen's expression took 3 % of point E's curve). Two
// merges of two took 4 % of its Hill analysis, this one about as much: fewer passes, more
// comparisons per entry.
Eigen::SparseMatrix<double> HillMatrix(const HillPencil& pencil, double sigma) {
  const Eigen::SparseMatrix<double>&d0 = pencil.d0, &d1 = pencil.d1, &d2 = pencil.d2;
  assert(d0.isCompressed() && d1.isCompressed() && d2.isCompressed());
  assert(d0.rows() == d1.rows() && d0.rows() == d2.rows() && d0.cols() == d1.cols() &&
         d0.cols() == d2.cols());
  const double sigma2 = sigma * sigma;
  const int cols = static_cast<int>(d0.cols());
  Eigen::SparseMatrix<double> result(d0.rows(), d0.cols());
  result.resizeNonZeros(d0.nonZeros() + d1.nonZeros() + d2.nonZeros());
  int* outer = result.outerIndexPtr();
  int* inner = result.innerIndexPtr();
  double* values = result.valuePtr();
  const int *x_inner = d0.innerIndexPtr(), *y_inner = d1.innerIndexPtr(),
            *z_inner = d2.innerIndexPtr();
  const double *x_values = d0.valuePtr(), *y_values = d1.valuePtr(), *z_values = d2.valuePtr();
  constexpr int kDone = std::numeric_limits<int>::max();  // the row of an exhausted column
  int k = 0;
  for (int col = 0; col < cols; ++col) {
    outer[col] = k;
    int p = d0.outerIndexPtr()[col], q = d1.outerIndexPtr()[col], r = d2.outerIndexPtr()[col];
    const int p_end = d0.outerIndexPtr()[col + 1], q_end = d1.outerIndexPtr()[col + 1],
              r_end = d2.outerIndexPtr()[col + 1];
    for (;; ++k) {
      const int x_row = p < p_end ? x_inner[p] : kDone, y_row = q < q_end ? y_inner[q] : kDone,
                z_row = r < r_end ? z_inner[r] : kDone;
      const int row = std::min({x_row, y_row, z_row});
      if (row == kDone) break;
      inner[k] = row;
      const bool x = x_row == row, y = y_row == row;
      const double z = z_row == row ? sigma2 * z_values[r++] : 0.0;
      if (x || y) {
        const double first = (x ? x_values[p++] : 0.0) + (y ? sigma * y_values[q++] : 0.0);
        values[k] = first + z;
      } else {
        values[k] = 0.0 + z;
      }
    }
  }
  outer[cols] = k;
  result.data().resize(k);
  return result;
}

namespace {

// Applies the shift-inverted linearised pencil (A − σB)⁻¹B on z = (q, w = s q_dynamic):
//   A = [[−Δ0, 0], [0, I]], B = [[Δ1, Δ2 S_dᵀ], [S_d, 0]],
// so that (A − σB)⁻¹B z = ν z exactly when A z = (σ + 1/ν) B z. One factorisation of the
// Hill matrix H(σ) = Δ0 + σΔ1 + σ²Δ2 (HillLinearSolver) serves every product.
class ShiftInvertOperator {
 public:
  using Scalar = double;

  ShiftInvertOperator(const HillPencil& pencil, double sigma)
      : pencil_(pencil),
        n_(static_cast<int>(pencil.d0.rows())),
        sigma_(sigma),
        solver_(HillMatrix(pencil, sigma), DisplacementEnd(pencil), DisplacementHarmonics(pencil)),
        product_(pencil) {}
  bool ok() const { return solver_.ok(); }
  Eigen::Index rows() const { return n_ + static_cast<Eigen::Index>(pencil_.dynamic.size()); }
  Eigen::Index cols() const { return rows(); }
  void set_shift(double /*sigma*/) {}  // fixed at construction (the LU is of H(σ))

  // Allocation-free apart from the sparse LU's solve: Arnoldi calls this 30–100 times per point.
  void perform_op(const double* x_in, double* y_out) const {
    const int nd = static_cast<int>(pencil_.dynamic.size());
    Eigen::Map<const Eigen::VectorXd> q(x_in, n_), w(x_in + n_, nd);
    w_full_.setZero();
    for (int i = 0; i < nd; ++i) {
      const int index = pencil_.dynamic[static_cast<size_t>(i)];
      w_full_(index) = w(i) + sigma_ * q(index);
    }
    product_.Apply(q, w_full_, &rhs_);
    solver_.Solve(rhs_, &solution_);
    Eigen::Map<Eigen::VectorXd> out_q(y_out, n_), out_w(y_out + n_, nd);
    out_q = -solution_;
    for (int i = 0; i < nd; ++i) {
      const int index = pencil_.dynamic[static_cast<size_t>(i)];
      out_w(i) = q(index) + sigma_ * out_q(index);
    }
  }

 private:
  const HillPencil& pencil_;
  int n_;
  double sigma_;
  HillLinearSolver solver_;
  HillProduct product_;
  mutable Eigen::VectorXd w_full_ = Eigen::VectorXd(n_), rhs_ = Eigen::VectorXd(n_),
                          solution_ = Eigen::VectorXd(n_);
};

// Spectra's shift-invert Arnoldi, with the Ritz vectors formed by real products of its basis
// and only in the rows that are read: eigenvectors() forms every row by a mixed real × complex
// product (10 % of the rod's analysis).
class HillArnoldi : public Spectra::GenEigsRealShiftSolver<ShiftInvertOperator> {
 public:
  HillArnoldi(ShiftInvertOperator& op, int nev, int ncv, double sigma)
      : GenEigsRealShiftSolver(op, nev, ncv, sigma), nev_(nev) {}

  // After a successful compute (all nev pairs converged, in eigenvalues()' order): the Ritz
  // vectors' first `rows` rows, and the sum of their real and imaginary parts (every row).
  void RitzVectors(Eigen::Index rows, Eigen::MatrixXcd* vectors, Eigen::VectorXd* sum) const {
    const Eigen::MatrixXd& basis = m_fac.matrix_V();
    const Eigen::MatrixXd real = m_ritz_vec.leftCols(nev_).real();
    const Eigen::MatrixXd imaginary = m_ritz_vec.leftCols(nev_).imag();
    const Eigen::MatrixXd top = basis.topRows(rows);
    vectors->resize(rows, nev_);
    vectors->real() = top * real;
    vectors->imag() = top * imaginary;
    if (sum != nullptr) {
      *sum = basis * (real.rowwise().sum() + imaginary.rowwise().sum());
    }
  }

 private:
  int nev_;
};

// The harmonic centroid k̄ of an eigenvector's DOF signals, their share of its norm and the
// share of their weight in harmonics above ¾H.
double Centroid(const Eigen::VectorXcd& q, const HillPencil& pencil, double* weight, double* edge) {
  const HarmonicSet& set = pencil.set;
  const double edge_harmonic = 0.75 * set.max_harmonic();
  double moment = 0.0, total = 0.0, high = 0.0;
  for (int offset : pencil.signal_offsets) {
    for (int p = 0; p < set.num_harmonics(); ++p) {
      const int k = set.harmonics()[static_cast<size_t>(p)];
      const Complex a = q(offset + set.CosIndex(p));
      if (k == 0) {
        total += std::norm(a);
        continue;
      }
      const Complex b = q(offset + set.SinIndex(p));
      const double plus = std::norm(0.5 * (a - Complex(0, 1) * b));
      const double minus = std::norm(0.5 * (a + Complex(0, 1) * b));
      moment += k * (plus - minus);
      total += plus + minus;
      if (k > edge_harmonic && k > kSmallestEdgeHarmonic) high += plus + minus;
    }
  }
  *weight = total / std::max(q.squaredNorm(), 1e-300);
  *edge = total > 0.0 ? high / total : 1.0;
  return total > 0.0 ? moment / total : 0.0;
}

struct Candidate {
  Complex exponent;
  double centroid;
  double edge;
};

// Whether two exponents are one family s + ikω, to `same`·ω.
bool SameFamily(Complex a, Complex b, double omega, double same) {
  const Complex d = a - b;
  return std::abs(d.real()) <= same * omega &&
         std::abs(std::remainder(d.imag(), omega)) <= same * omega;
}

// The exponent s folded into |Im s| ≤ ω/2 (copies share μ).
Complex Folded(Complex s, double omega) { return {s.real(), std::remainder(s.imag(), omega)}; }

// One representative per family (see SolveHill), sorted by decreasing |μ|.
void SelectPhysical(std::vector<Candidate> candidates, const HillPencil& pencil,
                    const HillOptions& options, FloquetResult* result) {
  const double period = 2.0 * std::numbers::pi / pencil.omega;
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::abs(a.centroid) < std::abs(b.centroid);
  });
  const double omega = pencil.omega;
  std::vector<std::pair<Complex, Complex>> accepted;  // (μ, exponent folded into the strip)
  const double same = pencil.memory_unknowns > 0 ? kSameExponentMemory : kSameExponent;
  for (const Candidate& c : candidates) {
    // The state has this many exponents: further families are truncation artefacts (they
    // come after the physical ones in centroid order).
    if (static_cast<int>(accepted.size()) == pencil.state_dimension) break;
    if (c.edge > kEdgeLimit) continue;
    // Copies share μ, so the exponent is reported folded into |Im s| ≤ ω/2.
    const Complex folded = Folded(c.exponent, omega);
    const bool copy = std::any_of(accepted.begin(), accepted.end(), [&](const auto& other) {
      return SameFamily(other.second, folded, omega, same);
    });
    if (copy) continue;
    // The system is real: a complex multiplier comes with its conjugate, so both take their
    // places at once (a pair that does not fit is not physical), and the conjugate's own
    // copies are then skipped. Without this a truncation artefact further down the centroid
    // order could take the conjugate's place.
    const double phase = std::abs(folded.imag());
    const bool real = phase <= same * omega || phase >= (0.5 - same) * omega;
    if (!real) {
      if (static_cast<int>(accepted.size()) + 2 > pencil.state_dimension) continue;
      accepted.emplace_back(std::conj(std::exp(c.exponent * period)), std::conj(folded));
    }
    accepted.emplace_back(std::exp(c.exponent * period), folded);
  }
  std::sort(accepted.begin(), accepted.end(),
            [](const auto& a, const auto& b) { return std::abs(a.first) > std::abs(b.first); });
  for (const auto& [mu, exponent] : accepted) {
    result->multipliers.push_back(mu);
    result->exponents.push_back(exponent);
  }
  result->max_modulus = result->multipliers.empty() ? 0.0 : std::abs(result->multipliers[0]);
  result->num_unstable = static_cast<int>(std::count_if(
      result->multipliers.begin(), result->multipliers.end(),
      [&](const Complex& mu) { return std::abs(mu) > 1.0 + options.unstable_tolerance; }));
  result->computed = true;
  if (static_cast<int>(accepted.size()) != pencil.state_dimension) {
    result->message = "resolved " + std::to_string(accepted.size()) +
                      " multipliers for a state of " + std::to_string(pencil.state_dimension);
  }
}

// Candidates (finite eigenvalues with their centroids) from eigenpairs ν, z of the operator.
void AddCandidates(const Eigen::VectorXcd& nu, const Eigen::MatrixXcd& vectors, double sigma,
                   const HillPencil& pencil, std::vector<Candidate>* candidates) {
  const double band = kBandFactor * (pencil.set.max_harmonic() + 1) * pencil.omega;
  const int n = static_cast<int>(pencil.d0.rows());
  for (Eigen::Index i = 0; i < nu.size(); ++i) {
    if (std::abs(nu(i)) * band <= 1.0) continue;
    double weight = 0.0, edge = 0.0;
    const double centroid = Centroid(vectors.col(i).head(n), pencil, &weight, &edge);
    if (weight <= 0.0) continue;  // no displacement: an algebraic mode
    candidates->push_back({sigma + 1.0 / nu(i), centroid, edge});
  }
}

}  // namespace

FloquetResult SolveHill(const HillPencil& pencil, const HillOptions& options,
                        Eigen::VectorXd* krylov_start) {
  const auto start = std::chrono::steady_clock::now();
  FloquetResult result;
  result.method = "hill";
  double sigma = kShiftFraction * pencil.omega;
  std::unique_ptr<ShiftInvertOperator> op;
  for (int attempt = 0; attempt < 3; ++attempt, sigma *= 1.7) {
    op = std::make_unique<ShiftInvertOperator>(pencil, sigma);
    if (op->ok()) break;
  }
  if (!op->ok()) {
    result.message = "Hill matrix singular at every shift tried";
    return result;
  }
  const int size = static_cast<int>(op->rows());
  std::vector<Candidate> candidates;
  if (size <= options.dense_limit) {
    Eigen::MatrixXd matrix(size, size);
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(size);
    for (int j = 0; j < size; ++j) {
      unit(j) = 1.0;
      op->perform_op(unit.data(), matrix.col(j).data());
      unit(j) = 0.0;
    }
    result.operator_applications = size;
    Eigen::EigenSolver<Eigen::MatrixXd> solver(matrix, true);
    if (solver.info() != Eigen::Success) {
      result.message = "dense eigensolver failed";
      return result;
    }
    AddCandidates(solver.eigenvalues(), solver.eigenvectors(), sigma, pencil, &candidates);
  } else {
    // Enough exponents nearest σ to hold each family's central copy and its neighbours.
    const int nev = std::min(size - 3, pencil.state_dimension + 6);
    const int ncv = std::min(size, nev + std::max(20, nev / 2));
    HillArnoldi eigs(*op, nev, ncv, sigma);
    const bool warm = krylov_start != nullptr && krylov_start->size() == size &&
                      krylov_start->allFinite() && krylov_start->norm() > 0.0;
    if (warm) {
      eigs.init(krylov_start->data());
    } else {
      eigs.init();
    }
    // Ritz values to 1e-8 relative: exponents two orders below unstable_tolerance's 1e-6.
    eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-8);
    result.operator_applications = static_cast<int>(eigs.num_operations());
    if (warm && eigs.info() != Spectra::CompInfo::Successful) {
      // The warm start is an economy, never a cause of failure: a random start as without it.
      eigs.init();
      eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-8);
      result.operator_applications += static_cast<int>(eigs.num_operations());
    }
    if (eigs.info() != Spectra::CompInfo::Successful) {
      if (krylov_start != nullptr) krylov_start->resize(0);
      result.message = "Arnoldi did not converge";
      return result;
    }
    // The candidates read the pencil's unknowns q (the first rows); the warm start, the sum of
    // the real and imaginary parts (the real operator's invariant subspace of a complex pair).
    Eigen::MatrixXcd ritz;
    eigs.RitzVectors(pencil.d0.rows(), &ritz, krylov_start);
    // Spectra returns the transformed-back λ = σ + 1/ν; AddCandidates wants ν.
    const Eigen::VectorXcd lambda = eigs.eigenvalues();
    const Eigen::VectorXcd nu = (lambda.array() - sigma).inverse();
    AddCandidates(nu, ritz, sigma, pencil, &candidates);
  }
  SelectPhysical(std::move(candidates), pencil, options, &result);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace nfrc
