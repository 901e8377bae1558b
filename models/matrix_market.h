#pragma once

#include <Eigen/Sparse>
#include <cstdint>
#include <string>

namespace nfrc {

// Most memory, in bytes (4 GB), that reading one matrix may take, as estimated from its
// header before anything is allocated. The harmonic system is (2H+1) times the model, so a
// model whose matrices alone need more than this cannot be continued on the workstations
// nfrc targets; refusing at the header beats a std::bad_alloc (or swapping) halfway.
inline constexpr std::uint64_t kMaxMatrixMarketBytes = 4'000'000'000;

// Reads a real Matrix Market file ("matrix coordinate|array real|integer general|symmetric").
// Throws InputError naming the file (and line) if it cannot be read or is malformed:
// - not a regular file (directory, FIFO, device): refused before any read;
// - a header whose matrix would need more than kMaxMatrixMarketBytes (the message gives the
//   estimate; this also keeps sizes within Eigen's int indices) or that announces more
//   entries than the matrix holds;
// - an entry with extra fields, an index out of range, a value that is not finite, the same
//   entry twice (in a symmetric file (i, j) and (j, i) are the same entry), fewer entries
//   than announced, or anything but comments and blank lines after the last entry.
Eigen::SparseMatrix<double> ReadMatrixMarket(const std::string& path);

}  // namespace nfrc
