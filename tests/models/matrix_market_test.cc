#include "models/matrix_market.h"

#include <doctest/doctest.h>
#include <unistd.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/errors.h"

namespace nfrc {
namespace {

std::string TempDir() {
  // One directory per process: ctest runs test cases of this file in parallel.
  const auto dir = std::filesystem::temp_directory_path() /
                   ("nfrc_matrix_market_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string Error(const std::string& path) {
  try {
    ReadMatrixMarket(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

// The error of a file holding `text`, with the temporary directory cut from the message.
std::string ErrorOf(const std::string& text) {
  const std::string message = Error(WriteFile("m.mtx", text));
  const std::string prefix = TempDir() + "/";
  return message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
}

const std::string kGeneral = "%%MatrixMarket matrix coordinate real general\n";
const std::string kSymmetric = "%%MatrixMarket matrix coordinate real symmetric\n";

TEST_CASE("Matrix Market: a directory, a FIFO or a device fails at once") {
  const auto start = std::chrono::steady_clock::now();
  const std::string dir = TempDir() + "/dir.mtx";
  std::filesystem::create_directories(dir);
  CHECK(Error(dir) == dir + ": is a directory, not a Matrix Market file");
  CHECK(Error("/dev/zero") == "/dev/zero: not a regular file (a character device)");
  const std::string fifo = TempDir() + "/fifo.mtx";
  std::filesystem::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK(Error(fifo) == fifo + ": not a regular file (a FIFO)");
  std::filesystem::remove(fifo);
  CHECK(Error(TempDir() + "/missing.mtx") ==
        TempDir() + "/missing.mtx: cannot open Matrix Market file (No such file or directory)");
  // Reading /dev/zero used to take 36 s; every check above is a stat.
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(1));
}

TEST_CASE("Matrix Market: content after the announced entries names its line") {
  CHECK(ErrorOf(kGeneral + "2 2 1\n1 1 4\njunk\n") ==
        "m.mtx:4: unexpected content after the last entry (the header announces 1 entry)");
  CHECK(ErrorOf(kGeneral + "2 2 1\n1 1 4\n2 2 5\n") ==
        "m.mtx:4: unexpected content after the last entry (the header announces 1 entry)");
  CHECK(ErrorOf("%%MatrixMarket matrix array real general\n1 1\n4\n5\n") ==
        "m.mtx:4: unexpected content after the last entry (the header announces 1 entry)");
  // Comments and blank lines may follow.
  CHECK(ErrorOf(kGeneral + "2 2 1\n1 1 4\n% end\n\n  \n") == "no error");
  // Extra fields on a line are not ignored either (a complex entry has four).
  CHECK(ErrorOf(kGeneral + "2 2 1\n1 1 4 0\n") == "m.mtx:3: expected 'row col value'");
  CHECK(ErrorOf(kGeneral + "2 2 1 7\n1 1 4\n") == "m.mtx:2: expected 'rows cols entries'");
  CHECK(ErrorOf("%%MatrixMarket matrix array real general\n1 1\n4 5\n") ==
        "m.mtx:3: expected one value per line");
  CHECK(ErrorOf(kGeneral + "2 2 1\n1.5 1 4\n") == "m.mtx:3: expected 'row col value'");
}

TEST_CASE("Matrix Market: a header needing too much memory is refused with the estimate") {
  CHECK(ErrorOf(kGeneral + "100000000 100000000 100000000\n1 1 1\n") ==
        "m.mtx:2: a 100000000 x 100000000 matrix with 100000000 entries needs about 5.6 GB, "
        "more than the 4 GB limit");
  CHECK(ErrorOf("%%MatrixMarket matrix array real general\n100000000 100000000\n1\n") ==
        "m.mtx:2: a 100000000 x 100000000 array needs about 400 PB, more than the 4 GB limit");
  // Sizes beyond 64 bits do not parse; sizes beyond Eigen's int indices exceed the limit.
  CHECK(ErrorOf(kGeneral + "99999999999999999999 1 1\n1 1 1\n") ==
        "m.mtx:2: expected 'rows cols entries'");
  CHECK(ErrorOf(kGeneral + "3000000000 1 1\n1 1 1\n") ==
        "m.mtx:2: a 3000000000 x 1 matrix with 1 entry needs about 24 GB, more than the 4 GB "
        "limit");
}

TEST_CASE("Matrix Market: an entry count inconsistent with the header or the file") {
  CHECK(ErrorOf(kGeneral + "2 2 5\n1 1 1\n") ==
        "m.mtx:2: the header announces 5 entries, more than a 2 x 2 matrix holds");
  CHECK(ErrorOf(kSymmetric + "2 2 4\n1 1 1\n") ==
        "m.mtx:2: the header announces 4 entries, more than a symmetric 2 x 2 matrix holds");
  // More entries announced than the file holds: nothing large is allocated before the end.
  CHECK(ErrorOf(kGeneral + "10000 10000 1000000\n1 1 1\n") ==
        "m.mtx:3: file ends after 1 of 1000000 entries");
  CHECK(ErrorOf(kGeneral + "2 2 3\n1 1 4\n") == "m.mtx:3: file ends after 1 of 3 entries");
  CHECK(ErrorOf(kGeneral + "0 2 0\n") == "m.mtx:2: sizes must be positive");
  CHECK(ErrorOf(kGeneral + "% only comments\n") == "m.mtx:3: expected 'rows cols entries'");
}

TEST_CASE("Matrix Market: values must be finite numbers and indices in range") {
  CHECK(ErrorOf(kGeneral + "1 1 1\n1 1 nan\n") == "m.mtx:3: value is not finite");
  CHECK(ErrorOf(kGeneral + "1 1 1\n1 1 -inf\n") == "m.mtx:3: value is not finite");
  CHECK(ErrorOf(kGeneral + "1 1 1\n1 1 1e400\n") == "m.mtx:3: value 1e400 is out of range");
  CHECK(ErrorOf(kGeneral + "1 1 1\n1 1 1,5\n") == "m.mtx:3: expected a number, got \"1,5\"");
  CHECK(ErrorOf(kGeneral + "2 3 1\n3 1 4\n") ==
        "m.mtx:3: index out of range: (3, 1) in a 2 x 3 matrix");
  CHECK(ErrorOf(kGeneral + "2 3 1\n1 0 4\n") ==
        "m.mtx:3: index out of range: (1, 0) in a 2 x 3 matrix");
  CHECK(ErrorOf(kGeneral + "2 3 1\n1 -1 4\n") ==
        "m.mtx:3: index out of range: (1, -1) in a 2 x 3 matrix");
}

TEST_CASE("Matrix Market: an entry given twice is refused instead of summed") {
  CHECK(ErrorOf(kGeneral + "2 2 2\n1 2 4\n1 2 5\n") ==
        "m.mtx: entry (1, 2) is given more than once");
  CHECK(ErrorOf(kSymmetric + "2 2 2\n2 1 -1\n1 2 -1\n") ==
        "m.mtx: entry (2, 1) is given more than once (a symmetric file stores one triangle: "
        "(i, j) and (j, i) are the same entry)");
}

TEST_CASE("Matrix Market: a line without an end is refused at the line limit") {
  CHECK(ErrorOf(kGeneral + "% " + std::string(1 << 20, 'x')) ==
        "m.mtx:2: line longer than 65536 bytes");
}

TEST_CASE("Matrix Market: what the format allows still reads") {
  const auto matrix = ReadMatrixMarket(
      WriteFile("ok.mtx",
                "%%MatrixMarket matrix coordinate integer symmetric\r\n%\r\n\r\n 3 3  4 \r\n"
                "1 1 +2\r\n2 1\t-1\r\n3 3 1e-400\r\n3 2 -1.5e0"));
  CHECK(matrix.rows() == 3);
  CHECK(matrix.coeff(0, 0) == 2.0);
  CHECK(matrix.coeff(0, 1) == -1.0);
  CHECK(matrix.coeff(1, 0) == -1.0);
  CHECK(matrix.coeff(2, 1) == -1.5);
  CHECK(matrix.coeff(1, 2) == -1.5);
  CHECK(matrix.coeff(2, 2) == 0.0);  // 1e-400 underflows to zero, as strtod reads it
  const auto rod = ReadMatrixMarket(std::string(NFRC_SOURCE_DIR) + "/cases/two_rods/K.mtx");
  CHECK(rod.rows() == 18);
  CHECK(rod.nonZeros() == 50);
  CHECK(rod.coeff(0, 0) == doctest::Approx(5.04e10));
  const auto empty = ReadMatrixMarket(WriteFile("zero.mtx", kGeneral + "2 3 0\n"));
  CHECK(empty.cols() == 3);
  CHECK(empty.nonZeros() == 0);
}

}  // namespace
}  // namespace nfrc
