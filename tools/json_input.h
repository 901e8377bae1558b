#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace nfrc {

// Deepest nesting of arrays and objects accepted (the top-level object is depth 1). Real
// cases nest fewer than 10 levels (case > nonlinearities > [i] > gap > harmonics > [k] is 6);
// 64 leaves ample room while keeping the recursive code that walks, copies and destroys the
// document far from stack exhaustion (a copy at 5 000 levels already overflows under ASan).
inline constexpr int kMaxJsonDepth = 64;

// Largest JSON file read, in bytes (16 MiB). The biggest case in cases/ is about 1 KiB and
// large matrices belong in Matrix Market files; the parsed document takes several times its
// text in memory, so the cap keeps a wrong path (a log, an image, a disk dump) from being
// loaded whole.
inline constexpr std::uintmax_t kMaxCaseBytes = std::uintmax_t{16} << 20;

// What a JSON file read is, for messages ("cannot open case file"), and its size cap.
struct JsonFileKind {
  const char* name;
  std::uintmax_t max_bytes;
};
inline constexpr JsonFileKind kCaseFileKind{"case file", kMaxCaseBytes};
// A sweep's record: ~300 bytes a run, 31 MB at nfrc sweep's 100 000 runs.
inline constexpr JsonFileKind kSweepRecordKind{"sweep record", std::uintmax_t{256} << 20};

// Reads one JSON document from a regular file of at most kind.max_bytes. Throws InputError
// naming the file: "is a directory", "not a regular file" (FIFO, device, socket: checked
// before any read, so /dev/zero fails at once), too large (with its size), or any problem
// of ParseJsonText.
nlohmann::json ReadJsonFile(const std::string& path, const JsonFileKind& kind = kCaseFileKind);

// Parses `text` as one JSON document; `name` (usually the file's path) starts every message.
// Stricter than nlohmann::json::parse: nesting deeper than kMaxJsonDepth is refused while
// parsing (the deep document is never built), and a key repeated in one object is an error
// instead of the last one winning. Messages have the form "<name>: <field>: <problem>", e.g.
// "case.json: continuation.step: number 1e400 is out of range" or, for syntax errors,
// "case.json:3:8: not valid JSON: ...", with the line and column (from 1). Throws InputError.
nlohmann::json ParseJsonText(std::string_view text, const std::string& name);

}  // namespace nfrc
