#include "core/modal_receptance.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace nfrc::internal {
namespace {

using Complex = std::complex<double>;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// K must be positive definite to this condition: a rigid-body mode computes as λ ~ ±eps·λ_max.
constexpr double kMinStiffnessRatio = 1e-12;

// Off-diagonal entries of ΦᵀCΦ up to this fraction of its largest diagonal one are rounding
// (Rayleigh and modal damping leave ~n·eps of it there): dropping them moves Z_red by less
// than the 1e-10 within which the modal form must agree with the direct one.
constexpr double kDiagonalTolerance = 1e-11;

// Roundings per term of a modal sum (a product of mode entries, a division, an accumulation,
// the complex parts): δ(Σ t_m) ≤ kRoundingsPerTerm·n·eps·Σ|t_m|.
constexpr double kRoundingsPerTerm = 4.0;

bool ExactlySymmetric(const Eigen::MatrixXd& a) { return a == a.transpose(); }

}  // namespace

std::unique_ptr<ModalReceptance> ModalReceptance::Make(const LinearModel& model,
                                                       const std::vector<int>& retained,
                                                       std::string* reason) {
  const auto refuse = [&](std::string why) {
    if (reason != nullptr) *reason = std::move(why);
    return std::unique_ptr<ModalReceptance>();
  };
  const int n = model.num_dofs();
  if (n > kMaxDofs) return refuse("more than " + std::to_string(kMaxDofs) + " DOFs");
  const Eigen::MatrixXd k(model.stiffness), m(model.mass), c(model.damping);
  // C need not be exactly symmetric (modal damping assembled in floating point is not): its
  // asymmetry shows in ΦᵀCΦ's off-diagonal entries, checked below.
  if (!ExactlySymmetric(k) || !ExactlySymmetric(m)) return refuse("M and K must be symmetric");
  if (Eigen::LLT<Eigen::MatrixXd>(m).info() != Eigen::Success) {
    return refuse("M is not positive definite");
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eigen(k, m);
  if (eigen.info() != Eigen::Success) return refuse("the eigensolver of (K, M) failed");
  const Eigen::VectorXd& lambda = eigen.eigenvalues();  // ascending
  if (!(lambda(0) > kMinStiffnessRatio * lambda(n - 1))) {
    return refuse("K is not positive definite");
  }
  auto modal = std::unique_ptr<ModalReceptance>(new ModalReceptance());
  modal->modes_ = eigen.eigenvectors();
  const Eigen::MatrixXd modal_damping = modal->modes_.transpose() * c * modal->modes_;
  modal->damping_ = modal_damping.diagonal();
  const double largest = modal->damping_.cwiseAbs().maxCoeff();
  const Eigen::MatrixXd off_diagonal =
      modal_damping - Eigen::MatrixXd(modal->damping_.asDiagonal());
  if (off_diagonal.cwiseAbs().maxCoeff() > kDiagonalTolerance * largest) {
    return refuse("C is not diagonal in the modes of (K, M)");
  }
  modal->stiffness_ = lambda;
  modal->retained_modes_ = modal->modes_(retained, Eigen::all);
  modal->retained_modes_t_ = modal->retained_modes_.transpose().cast<Complex>();
  modal->largest_retained_square_ = modal->retained_modes_.cwiseAbs2().maxCoeff();
  return modal;
}

Eigen::VectorXcd ModalReceptance::Project(const Eigen::VectorXcd& forcing) const {
  return modes_.transpose().cast<Complex>() * forcing;
}

bool ModalReceptance::Inverses(int k, double omega, Eigen::VectorXcd* inverse) const {
  const double big_omega = k * omega;
  const double squared = big_omega * big_omega;
  inverse->resize(stiffness_.size());
  for (Eigen::Index m = 0; m < stiffness_.size(); ++m) {
    const Complex d(stiffness_(m) - squared, big_omega * damping_(m));
    if (!(std::abs(d) > kRoundingsPerTerm * kEps * (stiffness_(m) + squared))) return false;
    (*inverse)(m) = 1.0 / d;
  }
  return true;
}

void ModalReceptance::Sum(const Eigen::VectorXcd& weights, Eigen::MatrixXcd* h) const {
  const int n_r = static_cast<int>(retained_modes_.rows());
  h->resize(n_r, n_r);
  for (int j = 0; j < n_r; ++j) {
    for (int i = j; i < n_r; ++i) {
      Complex sum = 0.0;
      for (int m = 0; m < num_dofs(); ++m) {
        sum += (retained_modes_(i, m) * retained_modes_(j, m)) * weights(m);
      }
      (*h)(i, j) = (*h)(j, i) = sum;
    }
  }
}

void ModalReceptance::Respond(const Eigen::VectorXcd& weights,
                              const Eigen::VectorXcd& modal_forcing, Eigen::VectorXcd* u) const {
  const int n_r = static_cast<int>(retained_modes_.rows());
  u->resize(n_r);
  for (int i = 0; i < n_r; ++i) {
    Complex sum = 0.0;
    for (int m = 0; m < num_dofs(); ++m)
      sum += retained_modes_(i, m) * (weights(m) * modal_forcing(m));
    (*u)(i) = sum;
  }
}

bool ModalReceptance::Condense(int k, double omega, const Eigen::VectorXcd& modal_forcing,
                               Eigen::VectorXcd* inverse, Eigen::MatrixXcd* z, Eigen::MatrixXcd* dz,
                               Eigen::VectorXcd* f, Eigen::VectorXcd* df) const {
  if (!Inverses(k, omega, inverse)) return false;
  const int n_r = static_cast<int>(retained_modes_.rows());
  const int n = num_dofs();
  Sum(*inverse, &h_);
  // A pivot of H_rr at the rounding level of its terms is zero: Z_ll is singular there.
  double largest_term = 0.0;
  for (int m = 0; m < n; ++m) largest_term = std::max(largest_term, std::abs((*inverse)(m)));
  const double pivot_floor = kRoundingsPerTerm * n * kEps * largest_term * largest_retained_square_;
  if (n_r == 1) {
    if (!(std::abs(h_(0, 0)) > pivot_floor)) return false;
    z->resize(1, 1);
    (*z)(0, 0) = 1.0 / h_(0, 0);
  } else {
    const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(h_);
    if (!(lu.matrixLU().diagonal().cwiseAbs().minCoeff() > pivot_floor) || !(lu.rcond() >= kEps)) {
      return false;
    }
    *z = lu.inverse();
  }
  // (HF)_r and F_red = Z_red (HF)_r.
  Respond(*inverse, modal_forcing, &response_);
  f->noalias() = *z * response_;
  if (k == 0) {  // Z_0 = K does not depend on ω
    dz->setZero(n_r, n_r);
    df->setZero(n_r);
    return true;
  }
  // d/dω of 1/d_m is −d_m'/d_m² with d_m' = −2k²ω + ikc_m.
  rate_.resize(n);
  for (int m = 0; m < n; ++m) {
    rate_(m) = -Complex(-2.0 * k * k * omega, k * damping_(m)) * ((*inverse)(m) * (*inverse)(m));
  }
  Sum(rate_, &h_);
  dz->noalias() = -(*z) * h_ * (*z);
  Respond(rate_, modal_forcing, &d_response_);
  df->noalias() = *dz * response_;
  df->noalias() += *z * d_response_;
  return true;
}

void ModalReceptance::Recover(const Eigen::VectorXcd& inverse,
                              const Eigen::VectorXcd& modal_forcing, const Eigen::MatrixXcd& z,
                              const Eigen::VectorXcd& f, const Eigen::VectorXcd& x_r,
                              Eigen::VectorXcd* x) const {
  // The products into the work arrays, then the differences: the operations (and roundings)
  // of f − z x_r and (F − Φ_rᵀ g) ⊙ (1/d), without a temporary per harmonic.
  interface_.noalias() = z * x_r;
  interface_ = f - interface_;
  modal_.noalias() = retained_modes_t_ * interface_;
  modal_ = (modal_forcing - modal_).cwiseProduct(inverse);
  // Φ is real: two real sums per row instead of a complex copy of the n × n modes. Each runs
  // from zero over the modes in order, as Eigen's product sums a row below 128 columns (the
  // same bits), without the product's temporaries for the strided real and imaginary parts
  // (1.3 % of the N_φ = 160 friction curve's trace, through its plotted energy).
  const int n = num_dofs();
  x->resize(n);
  for (int i = 0; i < n; ++i) {
    double real = 0.0;
    double imag = 0.0;
    for (int m = 0; m < n; ++m) {
      real += modes_(i, m) * modal_(m).real();
      imag += modes_(i, m) * modal_(m).imag();
    }
    (*x)(i) = Complex(real, imag);
  }
}

void ModalReceptance::Rounding(const Eigen::VectorXcd& inverse,
                               const Eigen::VectorXcd& modal_forcing, const Eigen::MatrixXcd& z,
                               Eigen::MatrixXd* z_rounding, Eigen::VectorXd* f_rounding) const {
  const Eigen::MatrixXd phi = retained_modes_.cwiseAbs();
  const double unit = kRoundingsPerTerm * num_dofs() * kEps;
  const Eigen::MatrixXd h_rounding = unit * phi * inverse.cwiseAbs().asDiagonal() * phi.transpose();
  const Eigen::VectorXd response_rounding =
      unit * phi * inverse.cwiseAbs().cwiseProduct(modal_forcing.cwiseAbs());
  Eigen::VectorXcd response;
  Respond(inverse, modal_forcing, &response);
  const Eigen::MatrixXd z_abs = z.cwiseAbs();
  *z_rounding = z_abs * h_rounding * z_abs;
  *f_rounding = *z_rounding * response.cwiseAbs() + z_abs * response_rounding;
}

}  // namespace nfrc::internal
