#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "analysis/harmonic_system.h"
#include "analysis/stability.h"
#include "core/harmonic_set.h"
#include "core/nonlinearity.h"

namespace nfrc {

// Δ1 and Δ2 factored for Arnoldi's products with them (30–100 per point): Δ1 = C⊗I + 2ω M⊗D +
// dependences + laws_d1 and Δ2 = M⊗I + dependences + laws_d2, the Kronecker products over the
// first n·nc unknowns (n DOFs, nc coefficients each, DOF-major). A product then makes two
// dense (nc × n)·(n × n) passes instead of one sparse pass over C⊗I's entries (n²·nc of them
// with the rod's modal damping).
// A law that predicts its force from the linear rows (DLFT, LinearResidualDependence) adds
// sign·W·Σ c·(the linear rows of a term's DOF) to Δ1's and Δ2's rows of a target block: nc rows
// per target, each as dense as the linear rows. Its product is taken from the linear one.
struct HillFactors {
  struct RowDependence {
    Eigen::MatrixXd weights;                    // W (nc × nc)
    std::vector<std::pair<int, double>> terms;  // (DOF, c)
    std::vector<std::pair<int, double>> rows;   // (first unknown of the target block, sign)
  };
  Eigen::SparseMatrix<double> damping_t, mass_t;  // Cᵀ and Mᵀ (n × n)
  Eigen::SparseMatrix<double> derivative;         // D (nc × nc)
  // A block of the laws' Δ1 rest that is nearly full (a friction force's velocity Jacobian over
  // its DOF's harmonics), kept dense at rows and columns from (row, col) instead of in laws_d1.
  struct DenseBlock {
    int row = 0, col = 0;
    Eigen::MatrixXd values;
  };
  std::vector<RowDependence> dependences;
  Eigen::SparseMatrix<double> laws_d1, laws_d2;  // the rest, of the pencil's size
  std::optional<DenseBlock> laws_d1_block;
};

// Hill's quadratic eigenproblem (Δ0 + sΔ1 + s²Δ2) q = 0 of a periodic solution: the
// perturbation e^{st} p(θ), p in the solution's harmonic basis (and, for a law with memory,
// its stick pieces' Floquet factor sampled on Chebyshev nodes, analysis/hill_memory.h). It is posed
// on the full, uncondensed model (every DOF, each flexible obstacle as a massless DOF, and the
// laws' own unknowns), where it is linear in s: condensing the linear DOFs would make Δ depend on s
// through Z_red(s + ikω). Rows without mass (own unknowns, massless DOFs) are algebraic.
struct HillPencil {
  Eigen::SparseMatrix<double> d0, d1, d2;
  // Set by HillAssembler where the laws' rest of Δ1 and Δ2 has fewer entries than their
  // linear parts, or is one nearly full block (HillProduct uses them); a pencil without them
  // is applied through d1 and d2.
  std::optional<HillFactors> factors;
  HarmonicSet set{1, false};
  double omega = 1.0;
  // Unknowns whose columns of Δ2 are non-zero (coefficients of DOFs with mass), ascending.
  std::vector<int> dynamic;
  // First index of each displacement signal (NumCoefficients entries) whose harmonic content
  // tells the physical exponents from their copies s + ikω (the DOFs with mass).
  std::vector<int> signal_offsets;
  // Dimension of the physical state (2 per DOF with mass): how many exponents to expect.
  int state_dimension = 0;
  // The laws' own unknowns (then the memory's, if any) run from here to the end (-1: there are
  // no own unknowns).
  int own_offset = -1;
  // Unknowns of the laws' memory (analysis/hill_memory.h), the last ones, after the own
  // unknowns (own_offset does not count them: it stays -1 without own unknowns).
  int memory_unknowns = 0;
};

// A linear model for Hill's pencil other than the system's own: a reduction of it that keeps
// every DOF the system retains as a DOF of its own (HillReduction, analysis/hill_reduction.h).
struct HillModel {
  LinearModel model;
  // The reduced DOF of each DOF of the system's model; −1 for one the reduction dropped.
  std::vector<int> dof_of;
};

// Assembles the pencils of one HarmonicSystem at many points (a trace analyses every one):
// the Kronecker products of the linear part, which depend on neither y nor ω, and the map
// from the system's unknowns to the full ones are built once, at construction. The system
// must outlive the assembler and keep its model and laws.
class HillAssembler {
 public:
  // With `reduced`, the pencil's linear part is that model's (its DOFs are the pencil's) while
  // the laws are still linearised by the system at its own solution: their active samples and
  // weights are the exact ones, and only the structure's dynamics away from them is reduced.
  explicit HillAssembler(HarmonicSystem& system,
                         std::shared_ptr<const HillModel> reduced = nullptr);
  ~HillAssembler();
  HillAssembler(const HillAssembler&) = delete;
  HillAssembler& operator=(const HillAssembler&) = delete;

  // The pencil of the solution y at ω (a solution: the laws are linearised, not checked
  // against their residual). Δ0 is the Jacobian of the uncondensed harmonic equations;
  // Δ1 = C⊗I + 2ωM⊗D plus the laws' velocity Jacobians; Δ2 = M⊗I
  // (Nonlinearity::LinearizeForStability). Throws std::runtime_error where y is not finite or
  // the linear part cannot be formed at ω.
  HillPencil Assemble(const Eigen::VectorXd& y, double omega);

 private:
  struct Cache;
  // The pencil's DOF of a retained model DOF, and of a law's DOFs.
  int PencilDof(int dof) const;
  std::vector<int> PencilDofs(std::vector<int> dofs) const;

  HarmonicSystem& system_;
  std::shared_ptr<const HillModel> reduced_;
  std::unique_ptr<Cache> cache_;
};

// One pencil, through a HillAssembler made for it.
HillPencil AssembleHillPencil(HarmonicSystem& system, const Eigen::VectorXd& y, double omega);

// The end of the pencil's displacement unknowns (the DOFs' and obstacles' coefficients, nc
// each, then any memory unknowns of a pencil without own unknowns): own_offset, or the size.
int DisplacementEnd(const HillPencil& pencil);
// The harmonic (position in pencil.set) of each of those unknowns, for HillLinearSolver.
std::vector<int> DisplacementHarmonics(const HillPencil& pencil);
// Hill's matrix H(σ) = Δ0 + σΔ1 + σ²Δ2, compressed, rounded as Eigen's sparse sums round
// (Δ0 + σΔ1) + σ²Δ2 (a term missing from one side is a zero added). d0, d1 and d2 must be
// compressed.
Eigen::SparseMatrix<double> HillMatrix(const HillPencil& pencil, double sigma);

struct HillOptions {
  // |μ| > 1 + unstable_tolerance counts as unstable (StabilityOptions).
  double unstable_tolerance = 1e-6;
  // Linearised pencils up to this size are solved whole (dense); larger ones by shift-invert
  // Arnoldi (Spectra) for the exponents nearest the imaginary axis.
  int dense_limit = 60;
};

// The Floquet exponents and multipliers of a pencil. The pencil is linearised on
// z = (q, s q_dynamic) and shift-inverted at a small real σ. Each physical exponent appears
// in Hill's spectrum as a family of copies s + ikω (k in steps of 2 for odd-only sets) that
// share μ = exp(sT), T = 2π/ω. Candidates are taken in the order of their eigenvector's
// harmonic centroid |k̄| (k̄ = Σk|c_k|²/Σ|c_k|² over the complex amplitudes c_k of the DOF
// signals): the first of each multiplier is the family's representative, later ones with the
// same μ are its copies. So at a multiplier −1, whose copies ±iω/2 tie at |k̄| = ½ (the
// failure mode of sorting by centroid alone), one is kept; and a family whose central copy is
// far from σ (a stiff mode, Im s ≈ ω_m) is still represented by a copy near the axis.
// Copies with most of their weight in the top quarter of the harmonics are truncation
// artefacts and are not used, and at most state_dimension families are kept (the most
// central ones: beyond them come the copies that truncation has shifted off their family). Dense
// solve up to dense_limit, else Arnoldi (Spectra) for the state + 6 eigenvalues nearest σ.
//
// krylov_start (optional, Arnoldi only): in, Arnoldi's first vector if it has the operator's
// size (else a random one); out, the sum of this solve's Ritz vectors, the start for the next
// point of a trace, whose wanted eigenvectors differ little (38 → 32 operator applications per
// point on Fig. 7, N = 10). The exponents are the same to Arnoldi's 1e-8 either way.
FloquetResult SolveHill(const HillPencil& pencil, const HillOptions& options,
                        Eigen::VectorXd* krylov_start = nullptr);

}  // namespace nfrc
