#include "nonlinearities/return_mapping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace nfrc {

bool SlipHistory::Slips() const {
  for (int a : anchor) {
    if (a == kSlip) return true;
  }
  return false;
}

SlipHistory ReturnMapping(const Eigen::VectorXd& input, double stiffness, double limit) {
  const int nt = static_cast<int>(input.size());
  SlipHistory history;
  history.force.resize(nt);
  history.anchor.assign(static_cast<size_t>(nt), SlipHistory::kOrigin);
  double slider = 0.0;
  int anchor = SlipHistory::kOrigin;
  for (int pass = 0; pass < 2; ++pass) {
    for (int j = 0; j < nt; ++j) {
      const double trial = stiffness * (input(j) - slider);
      double force = trial;
      int state = anchor;
      if (std::abs(trial) > limit) {
        force = std::copysign(limit, trial);
        slider = input(j) - force / stiffness;
        anchor = j;
        state = SlipHistory::kSlip;
      }
      if (pass == 1) {
        history.force(j) = force;
        history.anchor[static_cast<size_t>(j)] = state;
      }
    }
  }
  return history;
}

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Safeguarded Newton iterations locating one switch (each halves the bracket at worst, so 200
// reach rounding from any sample interval).
constexpr int kMaxRefineIterations = 200;

// u(θ) = Σ c_i φ_i(θ) of a signal of a HarmonicSet, and its derivatives, at any θ.
class TrigPolynomial {
 public:
  TrigPolynomial(const HarmonicSet& set, const Eigen::VectorXd& c)
      : cos_(Eigen::VectorXd::Zero(set.max_harmonic() + 1)),
        sin_(Eigen::VectorXd::Zero(set.max_harmonic() + 1)) {
    for (int p = 0; p < set.num_harmonics(); ++p) {
      const int k = set.harmonics()[static_cast<size_t>(p)];
      cos_(k) = c(set.CosIndex(p));
      if (k > 0) sin_(k) = c(set.SinIndex(p));
    }
  }

  // d^order u / dθ^order and the next derivative at θ (order 0 to 2), in one pass: e^{ikθ}
  // by rotation (k·eps of rounding, where a sine and cosine per harmonic cost tenfold).
  std::pair<double, double> Derivatives(double theta, int order) const {
    const double c1 = std::cos(theta);
    const double s1 = std::sin(theta);
    double c = 1.0, s = 0.0;
    double first = order == 0 ? cos_(0) : 0.0;
    double second = 0.0;
    for (Eigen::Index k = 1; k < cos_.size(); ++k) {
      const double rotated = c * c1 - s * s1;
      s = s * c1 + c * s1;
      c = rotated;
      const double a = cos_(k), b = sin_(k);
      if (a == 0.0 && b == 0.0) continue;
      // d^d/dθ^d (a cos kθ + b sin kθ) = k^d Re(i^d (a − ib) e^{ikθ}): k^d times p, −q, −p, q
      // for d mod 4 = 0, 1, 2, 3.
      const double p = a * c + b * s;
      const double q = a * s - b * c;
      const double kd = std::pow(static_cast<double>(k), order);
      first += kd * Part(order, p, q);
      second += kd * static_cast<double>(k) * Part(order + 1, p, q);
    }
    return {first, second};
  }
  double Value(double theta) const { return Derivatives(theta, 0).first; }

  // Σ k^order √(a_k² + b_k²) ≥ max_θ |d^order u / dθ^order| (order ≥ 1).
  double DerivativeBound(int order) const {
    double sum = 0.0;
    for (Eigen::Index k = 1; k < cos_.size(); ++k) {
      sum += std::pow(static_cast<double>(k), order) * std::hypot(cos_(k), sin_(k));
    }
    return sum;
  }

 private:
  static double Part(int d, double p, double q) {
    switch (d % 4) {
      case 0:
        return p;
      case 1:
        return -q;
      case 2:
        return -p;
      default:
        return q;
    }
  }

  Eigen::VectorXd cos_;  // a_k, k = 0..H (zero for harmonics outside the set)
  Eigen::VectorXd sin_;  // b_k
};

// A root of u^(order)(θ) − level in [lo, hi], given g_lo, g_hi = u^(order) − level at the ends
// (the caller knows them: samples, turning points): Newton from the secant's root, safeguarded
// by bisection, to rounding (a few iterations on a sample interval). Where the ends do not
// bracket a root (a switch within rounding of a sample), the end nearer to the level.
double Refine(const TrigPolynomial& u, int order, double level, double lo, double hi, double g_lo,
              double g_hi) {
  if (g_lo == 0.0) return lo;
  if (g_hi == 0.0) return hi;
  if ((g_lo > 0.0) == (g_hi > 0.0)) return std::abs(g_lo) <= std::abs(g_hi) ? lo : hi;
  const bool rising = g_hi > 0.0;
  double theta = lo - g_lo * (hi - lo) / (g_hi - g_lo);
  if (!(theta > lo && theta < hi)) theta = 0.5 * (lo + hi);
  for (int iteration = 0; iteration < kMaxRefineIterations; ++iteration) {
    const auto [value, slope] = u.Derivatives(theta, order);
    const double g = value - level;
    if (g == 0.0) return theta;
    ((g > 0.0) == rising ? hi : lo) = theta;
    double next = slope != 0.0 ? theta - g / slope : lo;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double tolerance = 4.0 * std::numeric_limits<double>::epsilon() * kTwoPi;
    if (std::abs(next - theta) <= tolerance || hi - lo <= tolerance) return next;
    theta = next;
  }
  return theta;
}

// The turning points of u over [0, 2π), in order: the roots of u', bracketed on the samples of
// u' (a sign change: one root) and u'' (u' turning back towards zero inside an interval and
// crossing it: two), so that u is monotone between consecutive ones and a pair of turning
// points is found from its birth on (missed inside an interval, it would appear with a finite
// stick or slip phase: a jump of the force). With N_t ≥ 4H + 1 (the default sampling) an
// interval is at most a quarter of the top harmonic's period, where u'' changes sign once.
std::vector<double> TurningPoints(const TrigPolynomial& u, const Eigen::VectorXd& slopes,
                                  const Eigen::VectorXd& curvatures) {
  const int nt = static_cast<int>(slopes.size());
  const double third_bound = u.DerivativeBound(3);
  const double h = kTwoPi / nt;
  std::vector<double> roots;
  for (int j = 0; j < nt; ++j) {
    const double t0 = j * h;
    const double t1 = (j + 1) * h;
    // Zero counts as negative, so a root on a sample belongs to one interval.
    const bool up0 = slopes(j) > 0.0;
    const bool up1 = slopes((j + 1) % nt) > 0.0;
    if (up0 != up1) {
      roots.push_back(Refine(u, 1, 0.0, t0, t1, slopes(j), slopes((j + 1) % nt)));
      continue;
    }
    // u' keeps its sign at both ends: does it turn back and cross zero in between? Not if
    // Taylor's bound from either end, |u'(θ) − u'(t) − u''(t)(θ − t)| ≤ ½ M₃ (θ − t)², keeps it
    // off zero over the interval (most intervals: this spares the search for u'' = 0).
    const double s0 = slopes(j);
    const double s1 = slopes((j + 1) % nt);
    const double c0 = curvatures(j);
    const double c1 = curvatures((j + 1) % nt);
    const bool turns = up0 ? (c0 < 0.0 && c1 > 0.0) : (c0 > 0.0 && c1 < 0.0);
    if (!turns) continue;
    const double slack = 0.5 * third_bound * h * h;
    const double off_zero = std::max(std::min(std::abs(s0), std::abs(s0 + c0 * h)),
                                     std::min(std::abs(s1), std::abs(s1 - c1 * h))) -
                            slack;
    const bool same_sign =
        up0 ? (s0 + c0 * h > 0.0 && s1 - c1 * h > 0.0) : (s0 + c0 * h <= 0.0 && s1 - c1 * h <= 0.0);
    if (off_zero > 0.0 && same_sign) continue;
    const double middle = Refine(u, 2, 0.0, t0, t1, c0, c1);
    const double slope = u.Derivatives(middle, 1).first;
    if (up0 ? slope <= 0.0 : slope > 0.0) {
      roots.push_back(Refine(u, 1, 0.0, t0, middle, s0, slope));
      roots.push_back(Refine(u, 1, 0.0, middle, t1, slope, s1));
    }
  }
  return roots;
}

// Where each harmonic of a set sits in its coefficient layout, read once per evaluation.
struct Layout {
  explicit Layout(const HarmonicSet& set) : num_coefficients(set.NumCoefficients()) {
    for (int p = 0; p < set.num_harmonics(); ++p) {
      harmonic.push_back(set.harmonics()[static_cast<size_t>(p)]);
      cos_index.push_back(set.CosIndex(p));
      sin_index.push_back(set.SinIndex(p));  // = cos_index for harmonic 0 (unused there)
    }
  }
  int num_coefficients;
  std::vector<int> harmonic, cos_index, sin_index;
};

// Exact integrals over [begin, end] of the products of the set's basis functions, with the
// projection's weights (1/2π on the constant, 1/π on cos and sin).
class PieceIntegrals {
 public:
  PieceIntegrals(const Layout& layout, int max_harmonic, double begin, double end)
      : layout_(layout), cos_(2 * max_harmonic + 1), sin_(2 * max_harmonic + 1) {
    // ∫cos pθ and ∫sin pθ from the midpoint and half-length: no cancellation on short pieces.
    const double middle = 0.5 * (begin + end);
    const double half = 0.5 * (end - begin);
    cos_(0) = 2.0 * half;
    sin_(0) = 0.0;
    for (Eigen::Index p = 1; p < cos_.size(); ++p) {
      const double pd = static_cast<double>(p);
      const double factor = 2.0 * std::sin(pd * half) / pd;
      cos_(p) = factor * std::cos(pd * middle);
      sin_(p) = factor * std::sin(pd * middle);
    }
  }

  // w_n ∫ψ_n: the projection of the constant 1 onto the set.
  Eigen::VectorXd Ones() const {
    Eigen::VectorXd result(layout_.num_coefficients);
    for (size_t p = 0; p < layout_.harmonic.size(); ++p) {
      const int k = layout_.harmonic[p];
      if (k == 0) {
        result(layout_.cos_index[p]) = cos_(0) / kTwoPi;
      } else {
        result(layout_.cos_index[p]) = cos_(k) / std::numbers::pi;
        result(layout_.sin_index[p]) = sin_(k) / std::numbers::pi;
      }
    }
    return result;
  }

  // G_nm = w_n ∫φ_m ψ_n: the projection of a piece of the set's signals onto the set.
  Eigen::MatrixXd Products() const {
    const int nc = layout_.num_coefficients;
    const size_t count = layout_.harmonic.size();
    Eigen::MatrixXd result(nc, nc);
    for (size_t p = 0; p < count; ++p) {    // basis function φ_m, harmonic m (a column pair)
      for (size_t q = 0; q < count; ++q) {  // test function ψ_n, harmonic n
        const int n = layout_.harmonic[q];
        const int m = layout_.harmonic[p];
        const double weight = n == 0 ? 1.0 / kTwoPi : 1.0 / std::numbers::pi;
        const int nc_row = layout_.cos_index[q], ns_row = layout_.sin_index[q];
        const int mc_col = layout_.cos_index[p], ms_col = layout_.sin_index[p];
        // cos m·cos n, sin m·sin n, sin m·cos n, cos m·sin n by product-to-sum.
        const double cc = 0.5 * (Cos(m - n) + Cos(m + n));
        const double ss = 0.5 * (Cos(m - n) - Cos(m + n));
        const double sc = 0.5 * (Sin(m + n) + Sin(m - n));
        const double cs = 0.5 * (Sin(m + n) - Sin(m - n));
        if (m == 0 && n == 0) {
          result(nc_row, mc_col) = weight * Cos(0);
        } else if (m == 0) {
          result(nc_row, mc_col) = weight * Cos(n);
          result(ns_row, mc_col) = weight * Sin(n);
        } else if (n == 0) {
          result(nc_row, mc_col) = weight * Cos(m);
          result(nc_row, ms_col) = weight * Sin(m);
        } else {
          result(nc_row, mc_col) = weight * cc;
          result(nc_row, ms_col) = weight * sc;
          result(ns_row, mc_col) = weight * cs;
          result(ns_row, ms_col) = weight * ss;
        }
      }
    }
    return result;
  }

 private:
  double Cos(int p) const { return cos_(std::abs(p)); }
  double Sin(int p) const { return p >= 0 ? sin_(p) : -sin_(-p); }

  const Layout& layout_;
  Eigen::VectorXd cos_;  // ∫cos pθ, p = 0..2H
  Eigen::VectorXd sin_;  // ∫sin pθ
};

}  // namespace

ResolvedSlip ResolveReturnMapping(const FourierTransform& fourier, const Eigen::VectorXd& input,
                                  double stiffness, double limit, bool with_jacobian) {
  const HarmonicSet& set = fourier.harmonic_set();
  const Layout layout(set);
  const int nc = set.NumCoefficients();
  ResolvedSlip result;
  result.force = Eigen::VectorXd::Zero(nc);
  if (with_jacobian) result.jacobian = Eigen::MatrixXd::Zero(nc, nc);
  if (limit == 0.0) return result;  // the slider follows u: no force at all

  const TrigPolynomial u(set, input);
  const Eigen::MatrixXd& derivative = fourier.DerivativeMatrix();
  const Eigen::VectorXd slope_coefficients = derivative * input;
  const Eigen::VectorXd slopes = fourier.ToTime(slope_coefficients).col(0);
  const Eigen::VectorXd curvatures = fourier.ToTime(derivative * slope_coefficients).col(0);
  const std::vector<double> turning = TurningPoints(u, slopes, curvatures);
  std::vector<double> turning_values(turning.size());
  for (size_t i = 0; i < turning.size(); ++i) turning_values[i] = u.Value(turning[i]);
  const auto highest = std::max_element(turning_values.begin(), turning_values.end());
  const auto lowest = std::min_element(turning_values.begin(), turning_values.end());
  const double r = limit / stiffness;  // m: the slider's play either side of u

  if (turning.size() < 2 || *highest - *lowest <= 2.0 * r) {
    // No slip: f = k(u − w) with the slider at rest where the passes from w = 0 leave it,
    // clamp(0, u_max − r, u_min + r) (a constant u has no turning point: w = clamp(0, u ∓ r)).
    result.force = stiffness * input;
    if (with_jacobian) result.jacobian = stiffness * Eigen::MatrixXd::Identity(nc, nc);
    if (set.has_constant()) {
      const double theta_max = turning.empty() ? 0.0 : turning[highest - turning_values.begin()];
      const double theta_min = turning.empty() ? 0.0 : turning[lowest - turning_values.begin()];
      const double u_max = u.Value(theta_max);
      const double u_min = u.Value(theta_min);
      const int c0 = set.CosIndex(0);
      if (u_max - r > 0.0) {
        result.force(c0) -= stiffness * (u_max - r);
        if (with_jacobian) result.jacobian.row(c0) -= stiffness * set.Basis(theta_max).transpose();
      } else if (u_min + r < 0.0) {
        result.force(c0) -= stiffness * (u_min + r);
        if (with_jacobian) result.jacobian.row(c0) -= stiffness * set.Basis(theta_min).transpose();
      }
    }
    return result;
  }

  // The play operator on the monotone pieces between turning points, for one period from the
  // global maximum, where the force is +F_s (a stick phase starts there). The force of a stick
  // phase is f_a + k(u − u_a), anchored at the turning point where the last slip ended; on a
  // piece away from the anchor's side it reaches the other limit at a unique level crossing,
  // and the slip that follows ends at the piece's turning point.
  const int count = static_cast<int>(turning.size());
  const int start = static_cast<int>(highest - turning_values.begin());
  double anchor = turning[static_cast<size_t>(start)];
  double anchor_value = *highest;
  double anchor_force = limit;
  double phase_begin = anchor;
  auto add_phase = [&](double end, bool stick, double slip_force) {
    if (!(end > phase_begin)) return;
    const PieceIntegrals integrals(layout, set.max_harmonic(), phase_begin, end);
    const Eigen::VectorXd ones = integrals.Ones();
    if (stick) {
      result.stick_pieces.push_back({anchor, phase_begin, end});
      // f = f_a + k(u − u_a): ∂f/∂ũ = k(φ − φ(θ_a)).
      const Eigen::MatrixXd products = integrals.Products();
      result.force +=
          (anchor_force - stiffness * anchor_value) * ones + stiffness * products * input;
      if (with_jacobian)
        result.jacobian += stiffness * (products - ones * set.Basis(anchor).transpose());
    } else {
      result.force += slip_force * ones;
    }
    phase_begin = end;
  };
  double previous_theta = anchor;
  double previous_value = anchor_value;
  for (int i = 1; i <= count; ++i) {
    const int index = (start + i) % count;
    // Unwrapped to the period [θ_max, θ_max + 2π].
    double theta =
        turning[static_cast<size_t>(index)] + (index < start || i == count ? kTwoPi : 0.0);
    theta = std::max(theta, previous_theta);  // coincident roots: an empty piece
    const double value = turning_values[static_cast<size_t>(index)];
    const bool falling = value < previous_value;
    // The level at which the stick force reaches the limit on the side u moves towards.
    const double level = falling ? anchor_value - (limit + anchor_force) / stiffness
                                 : anchor_value + (limit - anchor_force) / stiffness;
    if (falling ? value < level : value > level) {
      const double crossing =
          Refine(u, 0, level, previous_theta, theta, previous_value - level, value - level);
      add_phase(crossing, true, 0.0);
      add_phase(theta, false, falling ? -limit : limit);
      result.switches += 2;
      anchor = theta;
      anchor_value = value;
      anchor_force = falling ? -limit : limit;
    }
    previous_theta = theta;
    previous_value = value;
  }
  add_phase(turning[static_cast<size_t>(start)] + kTwoPi, true, 0.0);
  return result;
}

std::optional<LinearizationMemory> SliderMemory(ResolvedSlip slip, double stiffness, bool pair) {
  if (slip.stick_pieces.empty()) return std::nullopt;
  LinearizationMemory memory;
  memory.pieces = std::move(slip.stick_pieces);
  memory.stiffness = stiffness;
  memory.terms = {{0, 1.0}};
  memory.rows = {{0, 1.0}};
  if (pair) {
    memory.terms.emplace_back(1, -1.0);
    memory.rows.emplace_back(1, -1.0);
  }
  return memory;
}

PhaseCount StickPhases(const HarmonicSet& set, const SlipHistory& history) {
  std::vector<bool> stuck(history.anchor.size());
  for (size_t j = 0; j < stuck.size(); ++j) stuck[j] = history.Sticks(static_cast<int>(j));
  return CountPhases(stuck, 1.0 / set.max_harmonic());
}

}  // namespace nfrc
