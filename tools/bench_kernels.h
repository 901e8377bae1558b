#pragma once

namespace nfrc::bench {

// The dense LU kernels behind DenseLu (continuation/dense_lu.h): Eigen's PartialPivLU and
// LAPACK's dgetrf from OpenBLAS, each factorising and solving the same random matrices of
// 40 to 2 560 unknowns: fastest of a few runs in ms and in LU(320) units (`lu_unit` s), the
// ratio, and which one DenseLu takes at that size.
void BenchDenseLu(double lu_unit);

}  // namespace nfrc::bench
