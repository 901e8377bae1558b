#include "tools/json_input.h"

#include <doctest/doctest.h>
#include <unistd.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/errors.h"

namespace nfrc {
namespace {

std::string TempDir() {
  // One directory per process: ctest runs test cases of this file in parallel.
  const auto dir = std::filesystem::temp_directory_path() /
                   ("nfrc_json_input_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string ParseError(const std::string& text, const std::string& name = "case.json") {
  try {
    ParseJsonText(text, name);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

std::string ReadError(const std::string& path) {
  try {
    ReadJsonFile(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_CASE("JSON input: every case in cases/ reads as nlohmann::json::parse reads it") {
  int count = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(std::string(NFRC_SOURCE_DIR) + "/cases")) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    CHECK_MESSAGE(ReadJsonFile(entry.path().string()) == nlohmann::json::parse(in),
                  entry.path().string());
    ++count;
  }
  CHECK(count > 10);
  const nlohmann::json value = ParseJsonText(
      R"({"a": [1, -2, 3.5, true, null, "x", {}, []], "b": {"c": 18446744073709551615}})", "t");
  CHECK(value["a"][1].get<int>() == -2);
  CHECK(value["a"][6].is_object());
  CHECK(value["b"]["c"].is_number_unsigned());
}

TEST_CASE("JSON input: nesting beyond kMaxJsonDepth is refused while parsing") {
  const int kDeep = 100000;  // far beyond any stack the recursive code could survive
  const std::string arrays = std::string(kDeep, '[') + std::string(kDeep, ']');
  const std::string error = ParseError(arrays);
  CHECK(Contains(error, "case.json: [0][0]"));
  CHECK(Contains(error, "nested deeper than 64 levels"));
  std::string objects;
  for (int i = 0; i < kDeep; ++i) objects += "{\"a\":";
  objects += "1" + std::string(kDeep, '}');
  CHECK(Contains(ParseError(objects), "case.json: a.a.a"));
  CHECK(Contains(ParseError(objects), "nested deeper than 64 levels"));

  const std::string at_limit = std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']');
  CHECK(ParseError(at_limit) == "no error");
  const std::string over = "[" + at_limit + "]";
  CHECK(ParseError(over) == "case.json: " + [] {
    std::string path;
    for (int i = 0; i < kMaxJsonDepth; ++i) path += "[0]";
    return path;
  }() + ": nested deeper than 64 levels of arrays and objects");
}

TEST_CASE("JSON input: a repeated key is an error naming its path") {
  CHECK(ParseError(R"({"continuation": {"step": 0.01, "max_step": 1, "step": 0.02}})") ==
        "case.json: continuation.step: duplicate key (it appears more than once in the same "
        "object)");
  CHECK(Contains(ParseError(R"({"nonlinearities": [{"dof": 0}, {"dof": 0, "dof": 1}]})"),
                 "case.json: nonlinearities[1].dof: duplicate key"));
  CHECK(Contains(ParseError(R"({"a": 1, "a": 1})"), "case.json: a: duplicate key"));
  CHECK(ParseError(R"({"a": {"x": 1}, "b": {"x": 1}})") == "no error");
  // Keys are shown as UTF-8, with control characters escaped.
  CHECK(Contains(ParseError(R"({"ω": 1, "ω": 2})"), "case.json: ω: duplicate key"));
  CHECK(
      Contains(ParseError(R"({"a\u0001": 1, "a\u0001": 2})"), "case.json: a\\x01: duplicate key"));
}

TEST_CASE("JSON input: a number beyond double range names the file and the field") {
  CHECK(ParseError(R"({"continuation": {"omega_start": 0.5, "step": 1e400}})") ==
        "case.json: continuation.step: number 1e400 is out of range");
  CHECK(ParseError(R"({"model": {"M": [[1, 0], [0, -1e400]]}})") ==
        "case.json: model.M[1][1]: number -1e400 is out of range");
  CHECK(ParseError("1e400") == "case.json: number 1e400 is out of range");
  // Underflow is not an error: the value is 0 (or subnormal), as strtod gives it.
  CHECK(ParseJsonText(R"({"a": 1e-400})", "t")["a"].get<double>() == 0.0);
  // Integers beyond 64 bits become doubles, as with nlohmann::json::parse.
  CHECK(ParseJsonText(R"({"a": 123456789012345678901234567890})", "t")["a"].is_number_float());
}

TEST_CASE("JSON input: invalid JSON gives the file, line and column") {
  CHECK(ParseError("{\n  \"a\": 1,\n  \"b\": }", "x.json") ==
        "x.json: not valid JSON at line 3, column 8, in b: syntax error while parsing value - "
        "unexpected '}'; expected '[', '{', or a literal");
  CHECK(Contains(ParseError("{\"a\": 1} x"), "case.json: not valid JSON at line 1, column 10"));
  CHECK(Contains(ParseError("{\"a\": 1} x"), "expected end of input"));
  CHECK(Contains(ParseError("{\"a\": [1, 2,\n\n   tru]}"),
                 "not valid JSON at line 3, column 7, in a[2]: "));
  CHECK(ParseError("") == "case.json: empty file (expected a JSON object)");
  CHECK(ParseError(" \n\t ") == "case.json: empty file (expected a JSON object)");
  // Control characters and broken UTF-8 echoed from the input are escaped.
  CHECK_FALSE(Contains(ParseError("{\"a\": \"\x01\"}"), "\x01"));
  const std::string broken = ParseError("[\"\xff\"]");
  CHECK(Contains(broken, "ill-formed UTF-8"));
  CHECK(Contains(broken, "\\xff"));
  CHECK_FALSE(Contains(broken, "\xff"));
  // A huge bad token is not echoed whole.
  const std::string long_token = "[\"" + std::string(1 << 20, 'x') + "\x01\"]";
  CHECK(ParseError(long_token).size() < 400);
}

TEST_CASE("JSON input: files that are not regular or too large are refused before reading") {
  const std::string dir = TempDir() + "/a_directory.json";
  std::filesystem::create_directories(dir);
  CHECK(ReadError(dir) == dir + ": is a directory, not a case file");
  CHECK(ReadError("/dev/zero") == "/dev/zero: not a regular file (a character device)");
  const std::string fifo = TempDir() + "/fifo.json";
  std::filesystem::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK(ReadError(fifo) == fifo + ": not a regular file (a FIFO)");
  std::filesystem::remove(fifo);

  const std::string big = WriteFile("big.json", "{}");
  std::filesystem::resize_file(big, kMaxCaseBytes + 1);  // sparse: no disk space used
  CHECK(ReadError(big) == big +
                              ": file is 16777217 bytes, more than the 16 MiB accepted for a "
                              "case file");
  std::filesystem::remove(big);

  CHECK(ReadError(TempDir() + "/missing.json") ==
        TempDir() + "/missing.json: cannot open case file");
  const std::string bad = WriteFile("bad.json", "{\"a\": [1,\n 2,]}");
  CHECK(Contains(ReadError(bad), bad + ": not valid JSON at line 2, column 4, in a[2]"));
  const std::string good = WriteFile("good.json", "{\"a\": [1, 2]}");
  CHECK(ReadJsonFile(good)["a"][1].get<int>() == 2);
}

}  // namespace
}  // namespace nfrc
