#pragma once

#include <Eigen/Sparse>
#include <string>

namespace nfrc {

// Reads a real Matrix Market file ("matrix coordinate|array real|integer general|symmetric").
// Throws InputError naming the file (and line) if it cannot be read or is malformed.
Eigen::SparseMatrix<double> ReadMatrixMarket(const std::string& path);

}  // namespace nfrc
