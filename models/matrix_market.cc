#include "models/matrix_market.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <sstream>
#include <string_view>
#include <system_error>
#include <vector>

#include "core/errors.h"

namespace nfrc {
namespace {

// Longest line accepted, in bytes. The Matrix Market format limits lines to 1024
// characters; 64 times that lets long comment lines of other writers through while a file
// without line breaks cannot grow the line buffer without bound.
constexpr size_t kMaxLineBytes = size_t{64} << 10;

// Bytes requested per read() (64 KiB).
constexpr size_t kReadChunkBytes = size_t{64} << 10;

// Peak bytes per stored entry while building the matrix: the triplet list (two int indices
// and a double, 16 bytes), then Eigen's setFromTriplets holds a transposed copy and the
// result (a double and an int index each, 2 x 12 bytes).
constexpr double kBytesPerStoredEntry = 16.0 + 2 * 12.0;

// Bytes per row and per column: the two compressed matrices' outer index arrays and Eigen's
// per-column count vector (ints), rounded up.
constexpr double kBytesPerRowOrColumn = 8.0;

// Under the memory limit, every count fits Eigen's int indices (rows, columns, entries).
static_assert(kMaxMatrixMarketBytes / kBytesPerStoredEntry < INT_MAX);
static_assert(kMaxMatrixMarketBytes / kBytesPerRowOrColumn < INT_MAX);

// Shortest text of one entry, in bytes, used to bound the entries the rest of the file can
// hold: "i j v\n" in coordinate format, "v\n" in array format.
constexpr long long kMinCoordinateEntryBytes = 6;
constexpr long long kMinArrayEntryBytes = 2;

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string ErrorText(int error_number) { return std::generic_category().message(error_number); }

// "24 GB", "1.5 MB": a byte count in decimal units with three significant digits.
std::string FormatBytes(double bytes) {
  static const char* const kUnits[] = {"bytes", "kB", "MB", "GB", "TB", "PB", "EB"};
  size_t unit = 0;
  while (bytes >= 1000.0 && unit + 1 < std::size(kUnits)) {
    bytes /= 1000.0;
    ++unit;
  }
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g %s", bytes, kUnits[unit]);
  return text;
}

// "1 entry", "3 entries".
std::string Entries(long long count) {
  return std::to_string(count) + (count == 1 ? " entry" : " entries");
}

// Whitespace-separated fields of a line.
std::vector<std::string_view> Fields(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    start = line.find_first_not_of(" \t\r", start);
    if (start == std::string_view::npos) return fields;
    const size_t end = std::min(line.find_first_of(" \t\r", start), line.size());
    fields.push_back(line.substr(start, end - start));
    start = end;
  }
}

bool IsBlankOrComment(std::string_view line) {
  const size_t first = line.find_first_not_of(" \t\r");
  return first == std::string_view::npos || line[first] == '%';
}

// A leading '+' (allowed by the format, refused by from_chars) is skipped.
std::string_view WithoutPlus(std::string_view text) {
  return text.size() > 1 && text[0] == '+' && text[1] != '-' ? text.substr(1) : text;
}

// The whole field as an integer; false if it is not one or does not fit.
bool ParseInteger(std::string_view text, long long& value) {
  text = WithoutPlus(text);
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

enum class RealStatus { kOk, kNotANumber, kOutOfRange, kNotFinite };

// The whole field as a finite double; a value too small for a double reads as 0 or a
// subnormal, as strtod gives it.
RealStatus ParseReal(std::string_view text, double& value) {
  text = WithoutPlus(text);
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (end != text.data() + text.size()) return RealStatus::kNotANumber;
  if (error == std::errc::result_out_of_range) {
    value = std::strtod(std::string(text).c_str(), nullptr);
    if (std::isinf(value)) return RealStatus::kOutOfRange;
  } else if (error != std::errc()) {
    return RealStatus::kNotANumber;
  }
  return std::isfinite(value) ? RealStatus::kOk : RealStatus::kNotFinite;
}

// Closes a file descriptor on every way out.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() { ::close(fd_); }
  int get() const { return fd_; }

 private:
  int fd_;
};

// Lines of a file read through a fixed buffer, each at most kMaxLineBytes long.
class LineReader {
 public:
  LineReader(int fd, const std::string& path) : fd_(fd), path_(path), chunk_(kReadChunkBytes) {}

  // The next line without its line break; false at the end of the file.
  bool Next(std::string& line) {
    line.clear();
    while (true) {
      if (position_ == filled_ && !Fill()) {
        if (line.empty()) return false;
        break;
      }
      const char* begin = chunk_.data() + position_;
      const char* end = chunk_.data() + filled_;
      const char* newline = std::find(begin, end, '\n');
      line.append(begin, newline);
      position_ += static_cast<size_t>(newline - begin);
      consumed_ += newline - begin;
      if (line.size() > kMaxLineBytes) {
        throw InputError(path_ + ":" + std::to_string(number_ + 1) + ": line longer than " +
                         std::to_string(kMaxLineBytes) + " bytes");
      }
      if (newline != end) {
        ++position_;
        ++consumed_;
        break;
      }
    }
    ++number_;
    return true;
  }

  long long number() const { return number_; }
  long long consumed() const { return consumed_; }

 private:
  bool Fill() {
    while (true) {
      const ssize_t count = ::read(fd_, chunk_.data(), chunk_.size());
      if (count < 0 && errno == EINTR) continue;
      if (count < 0) throw InputError(path_ + ": cannot read (" + ErrorText(errno) + ")");
      position_ = 0;
      filled_ = static_cast<size_t>(count);
      return count > 0;
    }
  }

  int fd_;
  const std::string& path_;
  std::vector<char> chunk_;
  size_t position_ = 0;
  size_t filled_ = 0;
  long long number_ = 0;    // lines returned so far (the last one's number, from 1)
  long long consumed_ = 0;  // bytes of the file returned so far, line breaks included
};

[[noreturn]] void FailAt(const std::string& path, long long line, const std::string& problem) {
  throw InputError(path + ":" + std::to_string(line) + ": " + problem);
}

// Throws unless `info` describes a regular file.
void CheckRegularFile(const std::string& path, const struct stat& info) {
  if (S_ISDIR(info.st_mode)) {
    throw InputError(path + ": is a directory, not a Matrix Market file");
  }
  if (!S_ISREG(info.st_mode)) {
    const char* kind = S_ISFIFO(info.st_mode)   ? "a FIFO"
                       : S_ISCHR(info.st_mode)  ? "a character device"
                       : S_ISBLK(info.st_mode)  ? "a block device"
                       : S_ISSOCK(info.st_mode) ? "a socket"
                                                : "not a file";
    throw InputError(path + ": not a regular file (" + kind + ")");
  }
}

}  // namespace

Eigen::SparseMatrix<double> ReadMatrixMarket(const std::string& path) {
  // The type is checked by name, so that a FIFO or device is refused without opening it,
  // then on the open descriptor in case the path changed in between.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw InputError(path + ": cannot open Matrix Market file (" + ErrorText(errno) + ")");
  }
  CheckRegularFile(path, info);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    throw InputError(path + ": cannot open Matrix Market file (" + ErrorText(errno) + ")");
  }
  const FileDescriptor file(fd);
  if (::fstat(file.get(), &info) != 0) {
    throw InputError(path + ": cannot read (" + ErrorText(errno) + ")");
  }
  CheckRegularFile(path, info);
  const auto file_bytes = static_cast<long long>(info.st_size);

  LineReader reader(file.get(), path);

  std::string line;
  if (!reader.Next(line)) FailAt(path, 1, "empty file");
  std::istringstream banner(Lower(line));
  std::string tag, object, format, field, symmetry;
  banner >> tag >> object >> format >> field >> symmetry;
  if (tag != "%%matrixmarket" || object != "matrix")
    FailAt(path, 1, "not a Matrix Market matrix header");
  if (format != "coordinate" && format != "array")
    FailAt(path, 1, "format must be coordinate or array");
  if (field != "real" && field != "integer" && field != "double") {
    FailAt(path, 1, "field must be real or integer, got \"" + field + "\"");
  }
  if (symmetry != "general" && symmetry != "symmetric") {
    FailAt(path, 1, "symmetry must be general or symmetric, got \"" + symmetry + "\"");
  }
  const bool symmetric = symmetry == "symmetric";
  const bool coordinate = format == "coordinate";

  bool have_size = false;
  while (reader.Next(line)) {
    if (!IsBlankOrComment(line)) {
      have_size = true;
      break;
    }
  }
  const long long size_line = reader.number() + (have_size ? 0 : 1);
  const std::vector<std::string_view> sizes = have_size ? Fields(line) : Fields("");
  long long rows = 0, cols = 0, entries = 0;
  if (coordinate) {
    if (sizes.size() != 3 || !ParseInteger(sizes[0], rows) || !ParseInteger(sizes[1], cols) ||
        !ParseInteger(sizes[2], entries)) {
      FailAt(path, size_line, "expected 'rows cols entries'");
    }
  } else if (sizes.size() != 2 || !ParseInteger(sizes[0], rows) || !ParseInteger(sizes[1], cols)) {
    FailAt(path, size_line, "expected 'rows cols'");
  }
  if (rows <= 0 || cols <= 0 || entries < 0) FailAt(path, size_line, "sizes must be positive");
  if (symmetric && rows != cols) FailAt(path, size_line, "a symmetric matrix must be square");

  // Entries the matrix can hold (every one in array format), in double: the products of
  // unchecked sizes may not fit an integer.
  const double capacity = symmetric
                              ? static_cast<double>(rows) * (static_cast<double>(rows) + 1) / 2
                              : static_cast<double>(rows) * static_cast<double>(cols);
  const double announced = coordinate ? static_cast<double>(entries) : capacity;
  const double stored = symmetric ? 2 * announced : announced;
  const double estimate =
      stored * kBytesPerStoredEntry +
      (static_cast<double>(rows) + static_cast<double>(cols)) * kBytesPerRowOrColumn;
  const std::string shape = std::to_string(rows) + " x " + std::to_string(cols);
  if (estimate > static_cast<double>(kMaxMatrixMarketBytes)) {
    FailAt(path, size_line,
           "a " + shape + (coordinate ? " matrix with " + Entries(entries) : " array") +
               " needs about " + FormatBytes(estimate) + ", more than the " +
               FormatBytes(static_cast<double>(kMaxMatrixMarketBytes)) + " limit");
  }
  // Below the limit every count fits an int (static_asserts above), so products are exact.
  if (!coordinate) entries = symmetric ? rows * (rows + 1) / 2 : rows * cols;
  if (coordinate && static_cast<double>(entries) > capacity) {
    FailAt(path, size_line,
           "the header announces " + Entries(entries) + ", more than a " +
               (symmetric ? "symmetric " : "") + shape + " matrix holds");
  }
  // Room for the announced entries, but no more than the rest of the file can hold: a
  // header announcing more than the file contains ends in "file ends after", not in a large
  // allocation.
  const long long min_entry_bytes = coordinate ? kMinCoordinateEntryBytes : kMinArrayEntryBytes;
  // (At least 0 if the file changed size since fstat.)
  const long long fit = std::max(0LL, (file_bytes - reader.consumed()) / min_entry_bytes + 1);
  const long long expected = std::min(entries, fit);
  std::vector<Eigen::Triplet<double>> triplets;
  try {
    triplets.reserve(static_cast<size_t>(symmetric ? 2 * expected : expected));
  } catch (const std::bad_alloc&) {
    FailAt(path, size_line,
           "a " + shape + " matrix needs about " + FormatBytes(estimate) +
               ", more memory than is available");
  }
  long long read = 0;
  long long array_row = 0, array_col = 0;
  while (read < entries && reader.Next(line)) {
    if (IsBlankOrComment(line)) continue;
    const long long line_number = reader.number();
    const std::vector<std::string_view> values = Fields(line);
    long long i = 0, j = 0;
    std::string_view value_text;
    if (coordinate) {
      if (values.size() != 3 || !ParseInteger(values[0], i) || !ParseInteger(values[1], j)) {
        FailAt(path, line_number, "expected 'row col value'");
      }
      if (i < 1 || i > rows || j < 1 || j > cols) {
        FailAt(path, line_number,
               "index out of range: (" + std::string(values[0]) + ", " + std::string(values[1]) +
                   ") in a " + shape + " matrix");
      }
      --i;
      --j;
      value_text = values[2];
    } else {
      if (values.size() != 1) FailAt(path, line_number, "expected one value per line");
      i = array_row;
      j = array_col;
      ++array_row;
      if (array_row >= rows) {
        ++array_col;
        array_row = symmetric ? array_col : 0;
      }
      value_text = values[0];
    }
    double value = 0.0;
    switch (ParseReal(value_text, value)) {
      case RealStatus::kOk:
        break;
      case RealStatus::kNotANumber:
        FailAt(path, line_number, "expected a number, got \"" + std::string(value_text) + "\"");
      case RealStatus::kOutOfRange:
        FailAt(path, line_number, "value " + std::string(value_text) + " is out of range");
      case RealStatus::kNotFinite:
        FailAt(path, line_number, "value is not finite");
    }
    triplets.emplace_back(static_cast<int>(i), static_cast<int>(j), value);
    if (symmetric && i != j) triplets.emplace_back(static_cast<int>(j), static_cast<int>(i), value);
    ++read;
  }
  if (read < entries) {
    FailAt(
        path, reader.number(),
        "file ends after " + std::to_string(read) + " of " + std::to_string(entries) + " entries");
  }
  while (reader.Next(line)) {
    if (!IsBlankOrComment(line)) {
      FailAt(path, reader.number(),
             "unexpected content after the last entry (the header announces " + Entries(entries) +
                 ")");
    }
  }

  // Eigen would sum repeated entries silently; in a symmetric file a repeat is usually both
  // triangles given, which would double the off-diagonal terms.
  auto by_position = [](const Eigen::Triplet<double>& a, const Eigen::Triplet<double>& b) {
    return a.col() != b.col() ? a.col() < b.col() : a.row() < b.row();
  };
  std::sort(triplets.begin(), triplets.end(), by_position);
  const auto repeat = std::adjacent_find(
      triplets.begin(), triplets.end(),
      [](const auto& a, const auto& b) { return a.row() == b.row() && a.col() == b.col(); });
  if (repeat != triplets.end()) {
    throw InputError(path + ": entry (" + std::to_string(repeat->row() + 1) + ", " +
                     std::to_string(repeat->col() + 1) + ") is given more than once" +
                     (symmetric ? " (a symmetric file stores one triangle: (i, j) and (j, i) "
                                  "are the same entry)"
                                : ""));
  }

  Eigen::SparseMatrix<double> matrix(static_cast<Eigen::Index>(rows),
                                     static_cast<Eigen::Index>(cols));
  try {
    matrix.setFromTriplets(triplets.begin(), triplets.end());
  } catch (const std::bad_alloc&) {
    throw InputError(path + ": a " + shape + " matrix needs about " + FormatBytes(estimate) +
                     ", more memory than is available");
  }
  return matrix;
}

}  // namespace nfrc
