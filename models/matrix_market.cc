#include "models/matrix_market.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/errors.h"

namespace nfrc {
namespace {

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

}  // namespace

Eigen::SparseMatrix<double> ReadMatrixMarket(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open Matrix Market file");
  auto fail = [&](int line, const std::string& problem) {
    throw InputError(path + ":" + std::to_string(line) + ": " + problem);
  };

  std::string line;
  int line_number = 1;
  if (!std::getline(in, line)) fail(1, "empty file");
  std::istringstream banner(Lower(line));
  std::string tag, object, format, field, symmetry;
  banner >> tag >> object >> format >> field >> symmetry;
  if (tag != "%%matrixmarket" || object != "matrix") fail(1, "not a Matrix Market matrix header");
  if (format != "coordinate" && format != "array") fail(1, "format must be coordinate or array");
  if (field != "real" && field != "integer" && field != "double") {
    fail(1, "field must be real or integer, got \"" + field + "\"");
  }
  if (symmetry != "general" && symmetry != "symmetric") {
    fail(1, "symmetry must be general or symmetric, got \"" + symmetry + "\"");
  }
  const bool symmetric = symmetry == "symmetric";

  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line[0] != '%' &&
        line.find_first_not_of(" \t\r") != std::string::npos) {
      break;
    }
  }
  std::istringstream size_line(line);
  long long rows = 0, cols = 0, entries = 0;
  if (format == "coordinate") {
    if (!(size_line >> rows >> cols >> entries)) fail(line_number, "expected 'rows cols entries'");
  } else {
    if (!(size_line >> rows >> cols)) fail(line_number, "expected 'rows cols'");
    entries = symmetric ? rows * (rows + 1) / 2 : rows * cols;
  }
  if (rows <= 0 || cols <= 0 || entries < 0) fail(line_number, "sizes must be positive");
  if (symmetric && rows != cols) fail(line_number, "a symmetric matrix must be square");

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(symmetric ? 2 * entries : entries));
  long long read = 0;
  long long array_row = 0, array_col = 0;
  while (read < entries && std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '%' || line.find_first_not_of(" \t\r") == std::string::npos) {
      continue;
    }
    std::istringstream entry(line);
    long long i = 0, j = 0;
    double value = 0.0;
    if (format == "coordinate") {
      if (!(entry >> i >> j >> value)) fail(line_number, "expected 'row col value'");
      if (i < 1 || i > rows || j < 1 || j > cols) fail(line_number, "index out of range");
      --i;
      --j;
    } else {
      if (!(entry >> value)) fail(line_number, "expected a value");
      i = array_row;
      j = array_col;
      ++array_row;
      if (array_row >= rows) {
        ++array_col;
        array_row = symmetric ? array_col : 0;
      }
    }
    if (!std::isfinite(value)) fail(line_number, "value is not finite");
    triplets.emplace_back(static_cast<int>(i), static_cast<int>(j), value);
    if (symmetric && i != j) triplets.emplace_back(static_cast<int>(j), static_cast<int>(i), value);
    ++read;
  }
  if (read < entries) {
    fail(line_number, "file ends after " + std::to_string(read) + " of " +
                          std::to_string(entries) + " entries");
  }
  Eigen::SparseMatrix<double> matrix(static_cast<Eigen::Index>(rows),
                                     static_cast<Eigen::Index>(cols));
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  return matrix;
}

}  // namespace nfrc
