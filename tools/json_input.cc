#include "tools/json_input.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <system_error>
#include <utility>
#include <vector>

#include "core/errors.h"

namespace nfrc {
namespace {

using Json = nlohmann::json;

// Characters of nlohmann's own explanation kept in a syntax-error message: its "last read"
// echo can repeat a whole multi-megabyte string token.
constexpr size_t kMaxDetailChars = 160;

// Bytes requested per read() of a case file (64 KiB: a few calls for any real case).
constexpr size_t kReadChunkBytes = size_t{64} << 10;

// nlohmann's exception id for "number overflow parsing '...'" (out_of_range.406).
constexpr int kNumberOverflowId = 406;

// How Printable treats bytes 0x80-0xff.
enum class NonAscii { kEscape, kKeep };

// `text` with control characters (and, with NonAscii::kEscape, all bytes >= 0x80) written as
// \xNN, cut to about `max_chars` with "...". The echo of a bad token may hold control
// characters or broken UTF-8, which must not reach a terminal or a JSON report; keys are
// valid UTF-8 (the lexer checks strings), so their non-ASCII characters are kept, and a cut
// never splits one.
std::string Printable(std::string_view text, size_t max_chars, NonAscii non_ascii) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    const bool continuation = (byte & 0xc0) == 0x80;
    if (out.size() >= max_chars && !(non_ascii == NonAscii::kKeep && continuation)) {
      out += "...";
      break;
    }
    if ((byte >= 0x20 && byte < 0x7f) || (byte >= 0x80 && non_ascii == NonAscii::kKeep)) {
      out += text[i];
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\x%02x", byte);
      out += escaped;
    }
  }
  return out;
}

// nlohmann's explanation without its "[json.exception...] parse error at line L, column C: "
// prefix (the position is reported separately); the whole text if the format differs.
std::string ParseErrorDetail(const std::string& what) {
  const size_t column = what.find("column ");
  const size_t colon = column == std::string::npos ? column : what.find(": ", column);
  const std::string detail = colon == std::string::npos ? what : what.substr(colon + 2);
  return Printable(detail, kMaxDetailChars, NonAscii::kEscape);
}

// Builds the document from nlohmann's SAX events without recursion, tracking the field path
// of the value being parsed so that every error can name it, and rejecting what
// nlohmann::json::parse accepts silently: duplicate keys and unbounded nesting.
class DomBuilder {
 public:
  DomBuilder(std::string_view text, const std::string& name) : text_(text), name_(name) {}

  bool null() { return AddScalar(Json(nullptr)); }
  bool boolean(bool value) { return AddScalar(Json(value)); }
  bool number_integer(Json::number_integer_t value) { return AddScalar(Json(value)); }
  bool number_unsigned(Json::number_unsigned_t value) { return AddScalar(Json(value)); }
  bool number_float(Json::number_float_t value, const Json::string_t& /*text*/) {
    return AddScalar(Json(value));
  }
  bool string(Json::string_t& value) { return AddScalar(Json(std::move(value))); }
  // Only binary formats (CBOR, MessagePack, ...) produce these; kept for the SAX interface.
  bool binary(Json::binary_t& value) { return AddScalar(Json(std::move(value))); }

  bool start_object(std::size_t /*elements*/) { return Open(Json::object()); }
  bool start_array(std::size_t /*elements*/) { return Open(Json::array()); }
  bool end_object() { return Close(); }
  bool end_array() { return Close(); }

  bool key(Json::string_t& key) {
    Frame& frame = frames_.back();
    frame.key = std::move(key);
    frame.has_key = true;
    if (frame.value->contains(frame.key)) {
      Fail(Path(), "duplicate key (it appears more than once in the same object)");
    }
    return true;
  }

  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& error) {
    if (error.id == kNumberOverflowId) {
      Fail(Path(), "number " + Printable(last_token, kMaxDetailChars, NonAscii::kEscape) +
                       " is out of range");
    }
    const std::string field = Path();
    throw InputError(name_ + ": not valid JSON at " + Position(position) +
                     (field.empty() ? "" : ", in " + field) + ": " +
                     ParseErrorDetail(error.what()));
  }

  Json TakeResult() { return std::move(root_); }

 private:
  // One open array or object: where its next value goes and how messages name that place.
  struct Frame {
    Json* value;
    std::string key;       // objects: the key of the value being parsed
    bool has_key = false;  // objects: a key was read and its value is not complete yet
    size_t index = 0;      // arrays: index of the element being parsed
  };

  [[noreturn]] void Fail(const std::string& field, const std::string& problem) const {
    throw InputError(name_ + ": " + (field.empty() ? "" : field + ": ") + problem);
  }

  // "continuation.step", "nonlinearities[1].gap.harmonics[0]": the value being parsed.
  std::string Path() const {
    std::string path;
    for (const Frame& frame : frames_) {
      // Appended piece by piece: GCC 12 misreports "x" + string temporaries (-Wrestrict).
      if (frame.value->is_array()) {
        path += '[';
        path += std::to_string(frame.index);
        path += ']';
      } else if (frame.has_key) {
        if (!path.empty()) path += '.';
        path += Printable(frame.key, kMaxDetailChars, NonAscii::kKeep);
      }
    }
    return path;
  }

  // "line L, column C" (from 1) of byte `position` (from 1, as nlohmann counts).
  std::string Position(size_t position) const {
    const size_t offset = std::min(position == 0 ? 0 : position - 1, text_.size());
    const std::string_view before = text_.substr(0, offset);
    const size_t line = 1 + static_cast<size_t>(std::count(before.begin(), before.end(), '\n'));
    const size_t line_start = before.rfind('\n');
    const size_t column = line_start == std::string_view::npos ? offset + 1 : offset - line_start;
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
  }

  // Stores a value at the current place; returns where it went.
  Json* Insert(Json&& value) {
    if (frames_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Frame& frame = frames_.back();
    if (frame.value->is_array()) {
      frame.value->push_back(std::move(value));
      return &frame.value->back();
    }
    return &((*frame.value)[frame.key] = std::move(value));
  }

  // The value at the top frame's current place is complete: move that place on.
  void Advance() {
    if (frames_.empty()) return;
    Frame& frame = frames_.back();
    if (frame.value->is_array()) {
      ++frame.index;
    } else {
      frame.has_key = false;
    }
  }

  bool AddScalar(Json&& value) {
    Insert(std::move(value));
    Advance();
    return true;
  }

  bool Open(Json&& empty) {
    // Refused before the container is created: a deep document is never built.
    if (frames_.size() >= static_cast<size_t>(kMaxJsonDepth)) {
      Fail(Path(),
           "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels of arrays and objects");
    }
    Json* value = Insert(std::move(empty));
    frames_.push_back(Frame{value, std::string(), false, 0});
    return true;
  }

  bool Close() {
    frames_.pop_back();
    Advance();
    return true;
  }

  std::string_view text_;
  const std::string& name_;
  Json root_;
  std::vector<Frame> frames_;
};

std::string ErrorText(int error_number) { return std::generic_category().message(error_number); }

std::string FileKind(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a file";
}

// Throws unless `info` describes a regular file of at most kind.max_bytes.
void CheckFile(const std::string& path, const struct stat& info, const JsonFileKind& kind) {
  if (S_ISDIR(info.st_mode)) {
    throw InputError(path + ": is a directory, not a " + std::string(kind.name));
  }
  if (!S_ISREG(info.st_mode)) {
    throw InputError(path + ": not a regular file (" + FileKind(info.st_mode) + ")");
  }
  const auto size = static_cast<std::uintmax_t>(info.st_size);
  if (size > kind.max_bytes) {
    throw InputError(path + ": file is " + std::to_string(size) + " bytes, more than the " +
                     std::to_string(kind.max_bytes >> 20) + " MiB accepted for a " + kind.name);
  }
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

}  // namespace

nlohmann::json ParseJsonText(std::string_view text, const std::string& name) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    throw InputError(name + ": empty file (expected a JSON object)");
  }
  DomBuilder builder(text, name);
  // strict: anything after the document is an error. The handler throws on every error, so
  // a false return (parse stopped without a report) cannot happen; it is checked anyway.
  if (!Json::sax_parse(text.data(), text.data() + text.size(), &builder, Json::input_format_t::json,
                       /*strict=*/true)) {
    throw InputError(name + ": not valid JSON");
  }
  return builder.TakeResult();
}

nlohmann::json ReadJsonFile(const std::string& path, const JsonFileKind& kind) {
  // The type is checked by name first so that a FIFO or device is refused without opening
  // it (opening a FIFO can block, a socket cannot be opened), then again on the open
  // descriptor, in case the path changed in between.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    const int error = errno;
    throw InputError(path + ": cannot open " + kind.name +
                     (error == ENOENT ? std::string() : " (" + ErrorText(error) + ")"));
  }
  CheckFile(path, info, kind);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    throw InputError(path + ": cannot open " + kind.name + " (" + ErrorText(errno) + ")");
  }
  const FileDescriptor file(fd);
  if (::fstat(file.get(), &info) != 0) {
    throw InputError(path + ": cannot read (" + ErrorText(errno) + ")");
  }
  CheckFile(path, info, kind);

  std::string text;
  text.reserve(static_cast<size_t>(info.st_size));
  std::vector<char> chunk(kReadChunkBytes);
  while (true) {
    const ssize_t count = ::read(file.get(), chunk.data(), chunk.size());
    if (count < 0) {
      if (errno == EINTR) continue;
      throw InputError(path + ": cannot read (" + ErrorText(errno) + ")");
    }
    if (count == 0) break;
    text.append(chunk.data(), static_cast<size_t>(count));
    // The file may grow after fstat: the size limit holds for what is actually read.
    if (text.size() > kind.max_bytes) {
      throw InputError(path + ": file grew past the " + std::to_string(kind.max_bytes >> 20) +
                       " MiB accepted for a " + kind.name + " while being read");
    }
  }
  return ParseJsonText(text, path);
}

}  // namespace nfrc
