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
// pile up on long paths; a rebuild, O(k³ + n·k²), costs about as much as k O(n·k) pivots.
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
// I·w̃ − M̃·z̃ − d̃·z0 = q̃ with basis B and x_B = B⁻¹q̃.
//
// B⁻¹ is kept in O(n·k) storage, k the number of basic z's and z0: with R the rows whose w is
// not basic, column j ∉ R of B⁻¹ is the unit vector at w_j's position (B e_p = e_j there), so
// only the k columns j ∈ R are stored (y_). Every row of B⁻¹ is supported on R plus at most
// one unit entry, so a pivot's rank-one update, an entering column B⁻¹a and the row norms of
// the pivot tolerance all cost O(n·k) instead of O(n²). On the low-rank Delassus operators of
// LCP-HBM k stays below rank(M) + 2 while n = N_t is ten times larger.
class LemkeSolver {
 public:
  LemkeSolver(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const LemkeOptions& options)
      : n_(static_cast<int>(q.size())), options_(options), m_(m), original_q_(q) {
    q_scale_ = q.lpNorm<Eigen::Infinity>();
    m_scale_ = m.lpNorm<Eigen::Infinity>();
    if (!(q_scale_ > 0.0)) q_scale_ = 1.0;
    if (!(m_scale_ > 0.0)) m_scale_ = 1.0;
    q_ = q / q_scale_;
    max_pivots_ = options.max_pivots > 0 ? options.max_pivots : 50 * n_ + 1000;
    w_position_.assign(n_, -1);
    free_index_.assign(n_, -1);
    y_.resize(n_, 0);  // n rows from the start; empty until a column is stored
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
      std::vector<int> basic(n_);
      for (int i = 0; i < n_; ++i) basic[i] = i;
      for (int i : options_.warm_basis) basic[i] = n_ + i;
      SetBasis(basic);
      const Factorization basis = Factorize();
      if (basis.rcond >= kSingularRcond) {
        result_.warm_started = true;
        LoadInverse(basis);
        x_ = Solve(basis, q_);
        if (x_.minCoeff() >= -options_.feasibility_tolerance) {
          return Finish(LemkeStatus::kSolution, "the warm basis is the solution");
        }
        covering = Eigen::VectorXd::Ones(n_);
        covering_ = covering;  // d̃ = B·1
        for (int i : options_.warm_basis) {
          covering_ -= m_.col(i) / m_scale_;
          covering_(i) -= 1.0;
        }
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

    Eigen::VectorXd column(n_);
    Eigen::VectorXd threshold(n_);
    for (;;) {
      if (leaving == ArtificialVariable()) {
        return Finish(LemkeStatus::kSolution, prefix + "solution: z0 left the basis");
      }
      const int entering = leaving < n_ ? leaving + n_ : leaving - n_;
      if (options_.stop != nullptr && options_.stop->load()) {
        return Finish(LemkeStatus::kInterrupted, prefix + "interrupted");
      }
      if (result_.pivots >= max_pivots_) {
        return Finish(LemkeStatus::kPivotLimit,
                      prefix + "pivot limit " + std::to_string(max_pivots_) + " reached");
      }
      EnteringColumn(entering, &column);
      RowNorms(&threshold);
      threshold *= options_.pivot_tolerance;
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
  int NumFree() const { return static_cast<int>(free_.size()); }

  std::string Name(int variable) const {
    if (variable == ArtificialVariable()) return "z0";
    return (variable < n_ ? "w_" : "z_") + std::to_string(variable % n_);
  }

  // Sets the basic variables and the positions of the basic w's; the stored columns of B⁻¹
  // are then stale until SetColdBasis or LoadInverse.
  void SetBasis(std::vector<int> basic) {
    basic_ = std::move(basic);
    std::fill(w_position_.begin(), w_position_.end(), -1);
    for (int p = 0; p < n_; ++p) {
      if (basic_[p] < n_) w_position_[basic_[p]] = p;
    }
  }

  void SetColdBasis() {
    std::vector<int> basic(n_);
    for (int i = 0; i < n_; ++i) basic[i] = i;
    SetBasis(std::move(basic));
    free_.clear();
    std::fill(free_index_.begin(), free_index_.end(), -1);
    x_ = q_;
  }

  // Column of `variable` in I·w̃ − M̃·z̃ − d̃·z0 = q̃.
  Eigen::VectorXd TableauColumn(int variable) const {
    if (variable == ArtificialVariable()) return -covering_;
    if (variable >= n_) return -m_.col(variable - n_) / m_scale_;
    return Eigen::VectorXd::Unit(n_, variable);
  }

  // (B⁻¹)_{row, col} from the stored columns and the unit ones.
  double InverseEntry(int row, int col) const {
    const int c = free_index_[col];
    if (c >= 0) return y_(row, c);
    return w_position_[col] == row ? 1.0 : 0.0;
  }

  // 1-norms of the rows of B⁻¹ (the size rounding errors in B⁻¹a scale with), in O(n·k).
  void RowNorms(Eigen::VectorXd* norms) const {
    if (free_.empty()) {
      norms->setZero();
    } else {
      *norms = y_.leftCols(NumFree()).cwiseAbs().rowwise().sum();
    }
    for (int i = 0; i < n_; ++i) {
      if (w_position_[i] >= 0) (*norms)(w_position_[i]) += 1.0;
    }
  }

  // LU of the basis through its structure: the basic w's are unit columns, so with C the k
  // other basic columns and R the k rows that no basic w covers, B is singular iff C_R is, and
  // B⁻¹ follows from an LU of C_R in O(k³ + n·k²) instead of O(n³).
  struct Factorization {
    std::vector<int> other_positions;         // basis positions holding a z or z0
    std::vector<int> free_rows;               // rows i whose w_i is not basic (ascending)
    Eigen::MatrixXd c;                        // n × k tableau columns of the others
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // of C_R
    double rcond = 1.0;
  };

  Factorization Factorize() const {
    Factorization f;
    for (int p = 0; p < n_; ++p) {
      if (basic_[p] >= n_) f.other_positions.push_back(p);
    }
    for (int i = 0; i < n_; ++i) {
      if (w_position_[i] < 0) f.free_rows.push_back(i);
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
      const int p = w_position_[i];
      if (p >= 0) x(p) = f.other_positions.empty() ? rhs(i) : rhs(i) - f.c.row(i).dot(x_c);
    }
    return x;
  }

  // Stores the columns j ∈ R of B⁻¹ from the factorisation: C_R⁻¹ in the rows of the others,
  // −(C·C_R⁻¹)_i in the row of each basic w_i.
  void LoadInverse(const Factorization& f) {
    free_ = f.free_rows;
    std::fill(free_index_.begin(), free_index_.end(), -1);
    const int k = NumFree();
    for (int b = 0; b < k; ++b) free_index_[free_[b]] = b;
    if (y_.cols() < k) y_.resize(n_, std::max(k, std::min(n_, 2 * k)));
    if (k == 0) return;
    const Eigen::MatrixXd g = f.lu.inverse();  // C_R⁻¹
    const Eigen::MatrixXd h = f.c * g;         // C·C_R⁻¹
    for (int a = 0; a < k; ++a) y_.row(f.other_positions[a]).head(k) = g.row(a);
    for (int i = 0; i < n_; ++i) {
      const int p = w_position_[i];
      if (p >= 0) y_.row(p).head(k) = -h.row(i);
    }
  }

  // B⁻¹a for the column a of `variable`, in O(n·k): the stored columns times a_R, plus a_i
  // at w_i's position for every basic w_i.
  void EnteringColumn(int variable, Eigen::VectorXd* column) const {
    const int k = NumFree();
    if (variable < n_) {
      *column = y_.col(free_index_[variable]);  // w_j enters only while j ∈ R
      return;
    }
    const double* a = nullptr;
    double sign = -1.0;  // the tableau columns of z and z0 are −M̃_j and −d̃
    if (variable == ArtificialVariable()) {
      a = covering_.data();
    } else {
      a = m_.col(variable - n_).data();
      sign = -1.0 / m_scale_;
    }
    if (k > 0) {
      Eigen::VectorXd a_free(k);
      for (int c = 0; c < k; ++c) a_free(c) = sign * a[free_[c]];
      column->noalias() = y_.leftCols(k) * a_free;
    } else {
      column->setZero();
    }
    for (int i = 0; i < n_; ++i) {
      if (w_position_[i] >= 0) (*column)(w_position_[i]) += sign * a[i];
    }
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
    if (ties.size() == 1) return ties.front();
    // The natural size of the ratio entries, for a relative tie width in B⁻¹'s components.
    double scale = 0.0;
    for (int i : ties) {
      double norm = basic_[i] < n_ ? 1.0 : 0.0;
      for (int c = 0; c < NumFree(); ++c) norm += std::abs(y_(i, c));
      scale = std::max(scale, norm / column(i));
    }
    const double width = options_.pivot_tolerance * scale;
    for (int k = 0; k < n_ && ties.size() > 1; ++k) {
      best = std::numeric_limits<double>::infinity();
      for (int i : ties) best = std::min(best, InverseEntry(i, k) / column(i));
      rows.clear();
      for (int i : ties) {
        if (InverseEntry(i, k) / column(i) - best <= width) rows.push_back(i);
      }
      ties.swap(rows);
    }
    return ties.front();
  }

  // Exchanges the basic variable of `row` for `entering` (whose B⁻¹a is `column`) with the
  // rank-one update B⁻¹ −= (column − e_row)·(B⁻¹)_row / pivot on the stored columns, and of
  // x_B; returns the leaving variable. A leaving w_i adds column i (its unit column updated),
  // an entering w_j drops column j (now the unit vector at `row`). Sets overflow_ if the pivot
  // was so small (pivot_tolerance 0) that the update is not finite.
  int Pivot(int row, int entering, const Eigen::VectorXd& column) {
    const double pivot = column(row);
    const int leaving = basic_[row];
    int k = NumFree();
    // No stored column yet: a row view of the empty y_ would offset its null data pointer.
    const Eigen::RowVectorXd pivot_row =
        k > 0 ? Eigen::RowVectorXd(y_.row(row).head(k) / pivot) : Eigen::RowVectorXd();
    overflow_ =
        !(pivot_row.allFinite() && std::isfinite(x_(row) / pivot) && std::isfinite(1.0 / pivot));
    Eigen::VectorXd eta = column;
    eta(row) -= 1.0;
    if (k > 0) y_.leftCols(k).noalias() -= eta * pivot_row;
    if (leaving < n_) {
      // Column `leaving` of B⁻¹ was e_row; its update is e_row − eta/pivot.
      if (y_.cols() <= k) {
        y_.conservativeResize(n_, std::min(n_, std::max(2 * k, 8)));
      }
      y_.col(k) = -eta / pivot;
      y_(row, k) += 1.0;
      free_.push_back(leaving);
      free_index_[leaving] = k;
      w_position_[leaving] = -1;
      ++k;
    }
    if (entering < n_) {
      const int c = free_index_[entering];
      if (c != k - 1) {
        y_.col(c) = y_.col(k - 1);
        free_[c] = free_[k - 1];
        free_index_[free_[c]] = c;
      }
      free_.pop_back();
      free_index_[entering] = -1;
      w_position_[entering] = row;
    }
    const double step = x_(row) / pivot;
    x_ -= step * eta;
    basic_[row] = entering;
    ++result_.pivots;
    return leaving;
  }

  // Rebuilds B⁻¹ and x_B from scratch; keeps the updated ones if B is numerically singular
  // (the final refactorisation reports that).
  void Refactor() {
    const Factorization basis = Factorize();
    if (!(basis.rcond >= kSingularRcond)) return;
    LoadInverse(basis);
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
    r.equation_residual = (r.w - m_ * r.z - original_q_).lpNorm<Eigen::Infinity>();
    r.message = std::move(message) + " (" + std::to_string(r.pivots) + " pivots)";
    return r;
  }

  int n_;
  const LemkeOptions& options_;
  const Eigen::MatrixXd& m_;  // unscaled: M̃ = m_/m_scale_ is formed column by column
  const Eigen::VectorXd& original_q_;
  double q_scale_ = 1.0;
  double m_scale_ = 1.0;
  int max_pivots_ = 0;
  Eigen::VectorXd q_;
  Eigen::VectorXd covering_;     // d̃, the scaled covering vector (B·1 after a warm start)
  std::vector<int> basic_;       // basic variable of each tableau row
  std::vector<int> w_position_;  // w_position_[i]: row of w_i if basic, −1 if i ∈ R
  std::vector<int> free_;        // R: rows whose w is not basic, in the order of y_'s columns
  std::vector<int> free_index_;  // free_index_[i]: column of y_ for i ∈ R, −1 otherwise
  Eigen::MatrixXd y_;            // n × capacity; the first |R| columns are B⁻¹'s columns R
  Eigen::VectorXd x_;
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
    case LemkeStatus::kInterrupted:
      return "interrupted";
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
