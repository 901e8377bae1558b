#include "core/lemke.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace nfrc {
namespace {

// Below this reciprocal condition estimate or pivot ratio a basis keeps no correct digit.
constexpr double kSingularRcond = std::numeric_limits<double>::epsilon();

// The basis inverse is rebuilt from scratch every this many pivots, so update errors cannot
// pile up on long paths; a rebuild costs about as much as a few O(n²) pivots (see Factorize).
constexpr int kRefactorInterval = 50;

std::string Format(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

[[noreturn]] void ThrowInvalid(const std::string& field, const std::string& problem) {
  throw std::invalid_argument("SolveLcp: " + field + " " + problem);
}

// Reciprocal condition estimate of an LU, 0 if a pivot vanishes (Eigen's estimate misses
// exactly zero pivots).
double Rcond(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu) {
  const Eigen::VectorXd pivots = lu.matrixLU().diagonal().cwiseAbs();
  if (!(pivots.minCoeff() >= kSingularRcond * pivots.maxCoeff())) return 0.0;
  return lu.rcond();
}

// Lemke's method on the scaled problem w̃ = M̃ z̃ + q̃ with M̃ = M/‖M‖max, q̃ = q/‖q‖∞
// (z̃ = z·‖M‖max/‖q‖∞, w̃ = w/‖q‖∞), which keeps the lexicographic path and makes every
// tolerance relative. Variables are numbered w_i = i, z_i = n + i, z0 = 2n; the tableau is
// I·w̃ − M̃·z̃ − d̃·z0 = q̃ with basis B, kept as B⁻¹ and x_B = B⁻¹q̃.
class LemkeSolver {
 public:
  LemkeSolver(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const LemkeOptions& options)
      : n_(static_cast<int>(q.size())), options_(options), original_m_(m), original_q_(q) {
    q_scale_ = q.lpNorm<Eigen::Infinity>();
    m_scale_ = m.lpNorm<Eigen::Infinity>();
    if (!(q_scale_ > 0.0)) q_scale_ = 1.0;
    if (!(m_scale_ > 0.0)) m_scale_ = 1.0;
    m_ = m / m_scale_;
    q_ = q / q_scale_;
    max_pivots_ = options.max_pivots > 0 ? options.max_pivots : 50 * n_ + 1000;
  }

  LemkeResult Solve() {
    // A warm basis is tried even when q ≥ 0: it may lead to a non-trivial solution that
    // coexists with the trivial one (a contact branch past a turning point).
    const bool trivial = q_.minCoeff() >= -options_.feasibility_tolerance;
    if (trivial && options_.warm_basis.empty()) {
      SetColdBasis();
      result_.trivial = true;
      return Finish(LemkeStatus::kSolution, "trivial solution z = 0: q >= 0");
    }
    std::string prefix;
    Eigen::VectorXd covering;  // d̄ = B⁻¹d̃ of the starting basis
    if (!options_.warm_basis.empty()) {
      basic_.assign(n_, 0);
      for (int i = 0; i < n_; ++i) basic_[i] = i;
      for (int i : options_.warm_basis) basic_[i] = n_ + i;
      const Factorization basis = Factorize();
      if (basis.rcond >= kSingularRcond) {
        result_.warm_started = true;
        binv_ = Inverse(basis);
        x_ = Solve(basis, q_);
        if (x_.minCoeff() >= -options_.feasibility_tolerance) {
          return Finish(LemkeStatus::kSolution, "the warm basis is the solution");
        }
        covering = Eigen::VectorXd::Ones(n_);
        covering_ = covering;  // d̃ = B·1
        for (int i : options_.warm_basis) covering_ += -m_.col(i) - Eigen::VectorXd::Unit(n_, i);
      } else {
        prefix = "warm basis is singular (rcond " + Format(basis.rcond) + "), cold start; ";
      }
    }
    if (!result_.warm_started) {
      SetColdBasis();
      if (trivial) {
        result_.trivial = true;
        return Finish(LemkeStatus::kSolution, prefix + "trivial solution z = 0: q >= 0");
      }
      covering_ = options_.covering.size() == 0 ? Eigen::VectorXd::Ones(n_)
                                                : Eigen::VectorXd(options_.covering);
      covering_ /= covering_.maxCoeff();
      covering = covering_;
    }

    // z0 enters at the most negative x_i/d̄_i, after which every x_B ≥ 0; the lexicographic
    // choice among ties leaves the rows of [x_B, B⁻¹] lexicographically positive.
    std::vector<int> rows(n_);
    for (int i = 0; i < n_; ++i) rows[i] = i;
    const int first_row = LexicographicMinimum(rows, x_, covering);
    int leaving = Pivot(first_row, ArtificialVariable(), -covering);

    for (;;) {
      if (leaving == ArtificialVariable()) {
        return Finish(LemkeStatus::kSolution, prefix + "solution: z0 left the basis");
      }
      const int entering = leaving < n_ ? leaving + n_ : leaving - n_;
      if (result_.pivots >= max_pivots_) {
        return Finish(LemkeStatus::kPivotLimit,
                      prefix + "pivot limit " + std::to_string(max_pivots_) + " reached");
      }
      const Eigen::VectorXd column = EnteringColumn(entering);
      const Eigen::VectorXd threshold = options_.pivot_tolerance * binv_.cwiseAbs().rowwise().sum();
      rows.clear();
      for (int i = 0; i < n_; ++i) {
        if (column(i) > threshold(i)) rows.push_back(i);
      }
      if (rows.empty()) {
        return Finish(LemkeStatus::kRayTermination, prefix + "secondary ray: entering " +
                                                        Name(entering) + " has no positive pivot");
      }
      const Eigen::VectorXd clamped = x_.cwiseMax(0.0);
      const int row = LexicographicMinimum(rows, clamped, column);
      leaving = Pivot(row, entering, column);
      if (overflow_) {
        return Finish(LemkeStatus::kSingularBasis, prefix + "pivot " + Format(column(row)) +
                                                       " on " + Name(entering) +
                                                       " overflowed the basis inverse");
      }
      if (result_.pivots % kRefactorInterval == 0) Refactor();
    }
  }

 private:
  int ArtificialVariable() const { return 2 * n_; }

  std::string Name(int variable) const {
    if (variable == ArtificialVariable()) return "z0";
    return (variable < n_ ? "w_" : "z_") + std::to_string(variable % n_);
  }

  void SetColdBasis() {
    basic_.assign(n_, 0);
    for (int i = 0; i < n_; ++i) basic_[i] = i;
    binv_ = Eigen::MatrixXd::Identity(n_, n_);
    x_ = q_;
  }

  // Column of `variable` in I·w̃ − M̃·z̃ − d̃·z0 = q̃.
  Eigen::VectorXd TableauColumn(int variable) const {
    if (variable == ArtificialVariable()) return -covering_;
    if (variable >= n_) return -m_.col(variable - n_);
    return Eigen::VectorXd::Unit(n_, variable);
  }

  // LU of the basis through its structure: the basic w's are unit columns, so with C the k
  // other basic columns and R the k rows that no basic w covers, B is singular iff C_R is, and
  // B⁻¹ follows from an LU of C_R in O(k³ + n·k² + n²) instead of O(n³). k is at most the rank
  // of M plus one, so for the low-rank Delassus operators this is about a pivot's cost.
  struct Factorization {
    std::vector<int> other_positions;         // basis positions holding a z or z0
    std::vector<int> free_rows;               // rows i whose w_i is not basic
    std::vector<int> w_positions;             // w_positions[i]: position of w_i, −1 if nonbasic
    Eigen::MatrixXd c;                        // n × k tableau columns of the others
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // of C_R
    double rcond = 1.0;
  };

  Factorization Factorize() const {
    Factorization f;
    f.w_positions.assign(n_, -1);
    for (int p = 0; p < n_; ++p) {
      if (basic_[p] < n_) {
        f.w_positions[basic_[p]] = p;
      } else {
        f.other_positions.push_back(p);
      }
    }
    for (int i = 0; i < n_; ++i) {
      if (f.w_positions[i] < 0) f.free_rows.push_back(i);
    }
    const int k = static_cast<int>(f.other_positions.size());
    f.c.resize(n_, k);
    for (int a = 0; a < k; ++a) f.c.col(a) = TableauColumn(basic_[f.other_positions[a]]);
    if (k > 0) {
      f.lu.compute(f.c(f.free_rows, Eigen::all));
      f.rcond = Rcond(f.lu);
    }
    return f;
  }

  // B⁻¹·rhs: the others from C_R, then each basic w_i = rhs_i − C_i·x_C.
  Eigen::VectorXd Solve(const Factorization& f, const Eigen::VectorXd& rhs) const {
    Eigen::VectorXd x(n_);
    Eigen::VectorXd x_c;
    if (!f.other_positions.empty()) x_c = f.lu.solve(Eigen::VectorXd(rhs(f.free_rows)));
    for (size_t a = 0; a < f.other_positions.size(); ++a) x(f.other_positions[a]) = x_c(a);
    for (int i = 0; i < n_; ++i) {
      const int p = f.w_positions[i];
      if (p >= 0) x(p) = f.other_positions.empty() ? rhs(i) : rhs(i) - f.c.row(i).dot(x_c);
    }
    return x;
  }

  Eigen::MatrixXd Inverse(const Factorization& f) const {
    Eigen::MatrixXd inverse = Eigen::MatrixXd::Zero(n_, n_);
    const int k = static_cast<int>(f.other_positions.size());
    Eigen::MatrixXd g;  // C_R⁻¹
    Eigen::MatrixXd h;  // C·C_R⁻¹
    if (k > 0) {
      g = f.lu.inverse();
      h = f.c * g;
    }
    for (int a = 0; a < k; ++a) {
      for (int b = 0; b < k; ++b) inverse(f.other_positions[a], f.free_rows[b]) = g(a, b);
    }
    for (int i = 0; i < n_; ++i) {
      const int p = f.w_positions[i];
      if (p < 0) continue;
      inverse(p, i) = 1.0;
      for (int b = 0; b < k; ++b) inverse(p, f.free_rows[b]) = -h(i, b);
    }
    return inverse;
  }

  // B⁻¹a for the column a of `variable`, in O(n²) (O(n) for a w).
  Eigen::VectorXd EnteringColumn(int variable) const {
    if (variable < n_) return binv_.col(variable);
    if (variable == ArtificialVariable()) return -(binv_ * covering_);
    return -(binv_ * m_.col(variable - n_));
  }

  // Among `rows` (all with column > 0), the one minimising [x_i, (B⁻¹)_i] / column_i
  // lexicographically, where x_i = numerators(i). Entries closer than the tolerances tie and
  // the next component decides; z0 wins a tie in the first component, since its leaving ends
  // the path. Rows of B⁻¹ are independent, so exact ties cannot survive every component; any
  // that do numerically go to the lowest row, keeping the choice deterministic.
  int LexicographicMinimum(std::vector<int> rows, const Eigen::VectorXd& numerators,
                           const Eigen::VectorXd& column) const {
    double best = std::numeric_limits<double>::infinity();
    int best_row = rows.front();
    for (int i : rows) {
      if (numerators(i) / column(i) < best) {
        best = numerators(i) / column(i);
        best_row = i;
      }
    }
    std::vector<int> ties;
    for (int i : rows) {
      if (numerators(i) - best * column(i) <= options_.feasibility_tolerance) ties.push_back(i);
    }
    if (ties.empty()) ties.push_back(best_row);  // only with overflowing ratios
    for (int i : ties) {
      if (basic_[i] == ArtificialVariable()) return i;
    }
    // The natural size of the ratio entries, for a relative tie width in B⁻¹'s components.
    double scale = 0.0;
    for (int i : ties) scale = std::max(scale, binv_.row(i).lpNorm<1>() / column(i));
    const double width = options_.pivot_tolerance * scale;
    for (int k = 0; k < n_ && ties.size() > 1; ++k) {
      best = std::numeric_limits<double>::infinity();
      for (int i : ties) best = std::min(best, binv_(i, k) / column(i));
      rows.clear();
      for (int i : ties) {
        if (binv_(i, k) / column(i) - best <= width) rows.push_back(i);
      }
      ties.swap(rows);
    }
    return ties.front();
  }

  // Exchanges the basic variable of `row` for `entering` (whose B⁻¹a is `column`) with a
  // rank-one update of B⁻¹ and x_B; returns the leaving variable. Sets overflow_ if the pivot
  // was so small (pivot_tolerance 0) that the update is not finite.
  int Pivot(int row, int entering, const Eigen::VectorXd& column) {
    const double pivot = column(row);
    const Eigen::RowVectorXd pivot_row = binv_.row(row) / pivot;
    overflow_ = !(pivot_row.allFinite() && std::isfinite(x_(row) / pivot));
    Eigen::VectorXd eta = column;
    eta(row) -= 1.0;
    binv_.noalias() -= eta * pivot_row;
    const double step = x_(row) / pivot;
    x_ -= step * eta;
    const int leaving = basic_[row];
    basic_[row] = entering;
    ++result_.pivots;
    return leaving;
  }

  // Rebuilds B⁻¹ and x_B from scratch; keeps the updated ones if B is numerically singular
  // (the final refactorisation reports that).
  void Refactor() {
    const Factorization basis = Factorize();
    if (!(basis.rcond >= kSingularRcond)) return;
    binv_ = Inverse(basis);
    x_ = Solve(basis, q_);
  }

  // Recomputes the basic point from an LU of the final basis, unscales it and fills the result.
  LemkeResult Finish(LemkeStatus status, std::string message) {
    const Factorization basis = Factorize();
    if (basis.rcond >= kSingularRcond) {
      x_ = Solve(basis, q_);
    } else if (status != LemkeStatus::kSingularBasis) {
      message = "final basis is singular (rcond " + Format(basis.rcond) + "); the point is the " +
                "updated tableau's; was: " + message;
      status = LemkeStatus::kSingularBasis;
    }
    LemkeResult& r = result_;
    r.status = status;
    r.z = Eigen::VectorXd::Zero(n_);
    r.w = Eigen::VectorXd::Zero(n_);
    r.z0 = 0.0;
    r.basic_z.clear();
    for (int row = 0; row < n_; ++row) {
      const int variable = basic_[row];
      if (variable == ArtificialVariable()) {
        r.z0 = x_(row) * q_scale_;
      } else if (variable >= n_) {
        r.z(variable - n_) = x_(row) * q_scale_ / m_scale_;
        r.basic_z.push_back(variable - n_);
      } else {
        r.w(variable) = x_(row) * q_scale_;
      }
    }
    std::sort(r.basic_z.begin(), r.basic_z.end());
    r.complementarity = r.w.cwiseProduct(r.z).lpNorm<Eigen::Infinity>();
    r.feasibility = std::max({0.0, -r.w.minCoeff(), -r.z.minCoeff()});
    r.equation_residual = (r.w - original_m_ * r.z - original_q_).lpNorm<Eigen::Infinity>();
    r.message = std::move(message) + " (" + std::to_string(r.pivots) + " pivots)";
    return r;
  }

  int n_;
  const LemkeOptions& options_;
  const Eigen::MatrixXd& original_m_;
  const Eigen::VectorXd& original_q_;
  double q_scale_ = 1.0;
  double m_scale_ = 1.0;
  int max_pivots_ = 0;
  Eigen::MatrixXd m_;
  Eigen::VectorXd q_;
  Eigen::VectorXd covering_;  // d̃, the scaled covering vector (B·1 after a warm start)
  Eigen::MatrixXd binv_;
  Eigen::VectorXd x_;
  std::vector<int> basic_;  // basic variable of each tableau row
  bool overflow_ = false;
  LemkeResult result_;
};

}  // namespace

void LemkeOptions::Validate(int n) const {
  auto fail = [](const std::string& field, const std::string& problem) {
    throw std::invalid_argument("LemkeOptions: " + field + " " + problem);
  };
  if (covering.size() != 0) {
    if (covering.size() != n) {
      fail("covering",
           "has " + std::to_string(covering.size()) + " entries, expected " + std::to_string(n));
    }
    for (int i = 0; i < n; ++i) {
      if (!(std::isfinite(covering(i)) && covering(i) > 0.0)) {
        fail("covering", "entry " + std::to_string(i) + " is " + Format(covering(i)) +
                             ", must be finite and > 0");
      }
    }
  }
  std::vector<bool> seen(std::max(n, 0), false);
  for (int i : warm_basis) {
    if (i < 0 || i >= n) {
      fail("warm_basis",
           "index " + std::to_string(i) + " is out of [0, " + std::to_string(n) + ")");
    }
    if (seen[i]) fail("warm_basis", "index " + std::to_string(i) + " is repeated");
    seen[i] = true;
  }
  if (max_pivots < 0) fail("max_pivots", "is negative (0 = automatic)");
  if (!(pivot_tolerance >= 0.0 && std::isfinite(pivot_tolerance))) {
    fail("pivot_tolerance", "must be finite and >= 0");
  }
  if (!(feasibility_tolerance >= 0.0 && std::isfinite(feasibility_tolerance))) {
    fail("feasibility_tolerance", "must be finite and >= 0");
  }
}

std::string ToString(LemkeStatus status) {
  switch (status) {
    case LemkeStatus::kSolution:
      return "solution";
    case LemkeStatus::kRayTermination:
      return "ray termination";
    case LemkeStatus::kPivotLimit:
      return "pivot limit";
    case LemkeStatus::kSingularBasis:
      return "singular basis";
  }
  return "unknown";
}

LemkeResult SolveLcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                     const LemkeOptions& options) {
  if (M.rows() != M.cols()) {
    ThrowInvalid("M", "is " + std::to_string(M.rows()) + "x" + std::to_string(M.cols()) +
                          ", must be square");
  }
  if (q.size() != M.rows()) {
    ThrowInvalid("q", "has " + std::to_string(q.size()) + " entries, M has " +
                          std::to_string(M.rows()) + " rows");
  }
  if (!M.allFinite()) ThrowInvalid("M", "has non-finite entries");
  if (!q.allFinite()) ThrowInvalid("q", "has non-finite entries");
  const int n = static_cast<int>(q.size());
  options.Validate(n);
  if (n == 0) {
    LemkeResult empty;
    empty.status = LemkeStatus::kSolution;
    empty.message = "empty problem";
    empty.trivial = true;
    return empty;
  }
  return LemkeSolver(M, q, options).Solve();
}

}  // namespace nfrc
