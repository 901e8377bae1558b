#include "tools/bench_kernels.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "continuation/dense_lu.h"
#include "tools/bench_common.h"

namespace nfrc::bench {
namespace {

// Fastest of `repeats` factorisations and solves of `a` by one back end (s).
double TimeLu(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, bool lapack, int repeats,
              double* residual) {
  double fastest = 1e300;
  Eigen::VectorXd x;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    DenseLu lu;
    lu.Compute(a, lapack);
    x = lu.Solve(b);
    fastest = std::min(fastest, Seconds(start));
  }
  *residual = (a * x - b).norm() / b.norm();
  return fastest;
}

}  // namespace

void BenchDenseLu(double lu_unit) {
  std::printf("dense LU with partial pivoting, factorise and solve (fastest of the runs)\n");
  std::srand(1);
  for (const int n : {40, 80, 120, 160, 200, 320, 640, 1280, 2560}) {
    Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
    a.diagonal().array() += 2.0;
    const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
    const int repeats = n <= 320 ? 20 : (n <= 1280 ? 5 : 3);
    double residual_eigen = 0.0, residual_lapack = 0.0;
    const double eigen = TimeLu(a, b, false, repeats, &residual_eigen);
    const double lapack = TimeLu(a, b, true, repeats, &residual_lapack);
    std::printf(
        "  n = %4d: Eigen %8.2f ms = %7.2f LU(320), LAPACK %8.2f ms = %7.2f LU(320), "
        "Eigen/LAPACK %.2f; DenseLu takes %s (residuals %.1e, %.1e)\n",
        n, 1e3 * eigen, eigen / lu_unit, 1e3 * lapack, lapack / lu_unit, eigen / lapack,
        n >= DenseLu::kLapackMinSize ? "LAPACK" : "Eigen", residual_eigen, residual_lapack);
  }
}

}  // namespace nfrc::bench
