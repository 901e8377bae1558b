#include "tools/output_files.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <numbers>
#include <random>
#include <string_view>
#include <system_error>
#include <utility>

namespace nfrc {
namespace {

// New files get 0666 less the umask, as std::ofstream gives them, so permissions do not
// change with how a file is written.
constexpr mode_t kFileMode = 0666;

std::string SystemReason(int error) {
  return std::error_code(error, std::system_category()).message();
}

// "<path>: cannot <what>: <reason>", with a plainer reason when a symbolic link was refused.
OutputError Failure(const std::string& path, const std::string& what, int error) {
  struct stat info;
  if (error == ELOOP && lstat(path.c_str(), &info) == 0 && S_ISLNK(info.st_mode)) {
    return OutputError(path + ": cannot " + what + ": it is a symbolic link (not followed)");
  }
  return OutputError(path + ": cannot " + what + ": " + SystemReason(error));
}

// Writes all of `data` to `fd`, resuming after partial writes and interrupted calls.
void WriteAll(int fd, std::string_view data, const std::string& path) {
  while (!data.empty()) {
    const ssize_t written = write(fd, data.data(), data.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      throw Failure(path, "write", errno);
    }
    data.remove_prefix(static_cast<size_t>(written));
  }
}

// Closes `fd`; EINTR counts as closed (Linux releases the descriptor before reporting it).
void CloseChecked(int fd, const std::string& path) {
  if (close(fd) != 0 && errno != EINTR) throw Failure(path, "close", errno);
}

// 16 hex digits from the OS's random source: 64 bits nobody can guess ahead.
std::string RandomSuffix() {
  std::random_device device;
  const unsigned long long bits = (static_cast<unsigned long long>(device()) << 32) | device();
  std::ostringstream out;
  out << std::hex << std::setw(16) << std::setfill('0') << bits;
  return out.str();
}

// A temporary file created exclusively next to its target; removed unless committed.
class TemporaryFile {
 public:
  explicit TemporaryFile(const std::string& target) {
    const std::filesystem::path target_path(target);
    const std::filesystem::path dir =
        target_path.has_parent_path() ? target_path.parent_path() : std::filesystem::path(".");
    // Hidden, and marked as temporary for anyone listing the directory.
    std::string prefix = ".";
    prefix += target_path.filename().string();
    prefix += ".tmp-";
    // An existing name (a 2^-64 chance per try) is skipped rather than opened.
    for (int attempt = 0; attempt < 16; ++attempt) {
      path_ = (dir / (prefix + RandomSuffix())).string();
      fd_ = open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, kFileMode);
      if (fd_ >= 0) return;
      if (errno != EEXIST) throw Failure(target, "create a temporary file", errno);
    }
    throw OutputError(target + ": cannot create a temporary file: every name tried exists");
  }
  ~TemporaryFile() {
    if (fd_ >= 0) close(fd_);
    if (!committed_) unlink(path_.c_str());
  }
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  // Writes `text`, closes the file and renames it over `target`. Errors name `target`, the
  // file the user knows, rather than the temporary name.
  void Commit(std::string_view text, const std::string& target) {
    WriteAll(fd_, text, target);
    const int fd = std::exchange(fd_, -1);
    CloseChecked(fd, target);
    if (rename(path_.c_str(), target.c_str()) != 0) throw Failure(target, "replace", errno);
    committed_ = true;
  }

 private:
  std::string path_;
  int fd_ = -1;
  bool committed_ = false;
};

// flock without waiting (retried on EINTR); false where another holder blocks it.
bool TryLock(int fd, int operation) {
  int status;
  do {
    status = flock(fd, operation | LOCK_NB);
  } while (status != 0 && errno == EINTR);
  return status == 0;
}

// The pid an exclusive holder wrote into its lock file, 0 if none is there (a read between
// its lock and its write finds none).
long HolderPid(int fd) {
  char text[32] = {};
  const ssize_t length = pread(fd, text, sizeof(text) - 1, 0);
  return length > 0 ? std::strtol(text, nullptr, 10) : 0;
}

std::string PidText(long pid) {
  return pid > 0 ? " (pid " + std::to_string(pid) + ")" : std::string();
}

void WriteFileAtomically(const std::string& path, std::string_view text) {
  TemporaryFile file(path);
  file.Commit(text, path);
}

}  // namespace

OutputDirectoryInUse::OutputDirectoryInUse(const std::string& message, long pid)
    : std::runtime_error(message), pid_(pid) {}

void WriteCsv(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<Eigen::VectorXd>& data) {
  std::ostringstream out;
  out << std::setprecision(12);
  for (size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
  out << "\n";
  const Eigen::Index rows = data.empty() ? 0 : data.front().size();
  for (Eigen::Index j = 0; j < rows; ++j) {
    for (size_t c = 0; c < data.size(); ++c) out << (c ? "," : "") << data[c](j);
    out << "\n";
  }
  WriteFileAtomically(path, out.view());
}

void WriteJsonAtomically(const std::string& path, const nlohmann::json& document) {
  // Serialised first: a document that cannot be dumped leaves nothing behind.
  WriteFileAtomically(path, document.dump(1) + "\n");
}

CsvStream::CsvStream() { buffer_ << std::setprecision(12); }

CsvStream::CsvStream(const std::string& path) : CsvStream() { Open(path); }

CsvStream::~CsvStream() {
  if (fd_ < 0) return;
  try {
    Flush();
  } catch (...) {
    // A destructor has no way to report it; Close() is the checked path.
  }
  close(fd_);
}

void CsvStream::Open(const std::string& path) {
  if (fd_ >= 0) throw std::logic_error(path + ": CsvStream is already open on " + path_);
  // O_NONBLOCK: opening a FIFO for writing would otherwise wait for a reader forever.
  const int fd = open(
      path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK, kFileMode);
  if (fd < 0) throw Failure(path, "open for writing", errno);
  struct stat info;
  if (fstat(fd, &info) != 0) {
    const int error = errno;
    close(fd);
    throw Failure(path, "open for writing", error);
  }
  // Character devices pass (a user may name /dev/null); FIFOs and sockets do not.
  if (!S_ISREG(info.st_mode) && !S_ISCHR(info.st_mode)) {
    close(fd);
    throw OutputError(path + ": cannot open for writing: not a regular file");
  }
  if (fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK) != 0) {
    const int error = errno;
    close(fd);
    throw Failure(path, "open for writing", error);
  }
  path_ = path;
  fd_ = fd;
  failure_.clear();
}

void CsvStream::Flush() {
  if (!failure_.empty()) throw OutputError(failure_);
  if (fd_ < 0) throw std::logic_error("CsvStream::Flush on a stream that is not open");
  const std::string text = std::move(buffer_).str();
  buffer_.str(std::string());
  try {
    WriteAll(fd_, text, path_);
  } catch (const OutputError& error) {
    failure_ = error.what();
    throw;
  }
}

void CsvStream::Close() {
  if (fd_ < 0) return;
  Flush();
  const int fd = std::exchange(fd_, -1);
  CloseChecked(fd, path_);
}

OutputDirectoryLock::OutputDirectoryLock(std::string directory) : directory_(std::move(directory)) {
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error) {
    throw OutputError(directory_ + ": cannot create output directory: " + error.message());
  }
  const std::string path = (std::filesystem::path(directory_) / kFileName).string();
  // O_NOFOLLOW: a link planted at the lock's name neither redirects the pid we write nor
  // creates its target; O_NONBLOCK: a FIFO there cannot make the open wait.
  fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK, kFileMode);
  if (fd_ < 0) throw Failure(path, "create the lock file", errno);
  try {
    struct stat info;
    if (fstat(fd_, &info) != 0) throw Failure(path, "create the lock file", errno);
    if (!S_ISREG(info.st_mode)) {
      throw OutputError(path + ": cannot create the lock file: not a regular file");
    }
    int status;
    do {
      status = flock(fd_, LOCK_EX | LOCK_NB);
    } while (status != 0 && errno == EINTR);
    if (status != 0 && errno == EWOULDBLOCK) {
      // Only shared holders: runs into directories inside this one (their pids are not
      // recorded); otherwise the exclusive holder, which writes its pid right after locking.
      if (TryLock(fd_, LOCK_SH)) {
        flock(fd_, LOCK_UN);
        throw OutputDirectoryInUse(directory_ +
                                       " is in use: another nfrc run writes into a "
                                       "directory inside it",
                                   0);
      }
      const long pid = HolderPid(fd_);
      throw OutputDirectoryInUse(directory_ + " is in use by another nfrc run" + PidText(pid), pid);
    }
    if (status != 0) throw Failure(path, "lock", errno);
    LockEnclosing();
    RefuseBusyChildren();
    const std::string pid = std::to_string(getpid()) + "\n";
    if (ftruncate(fd_, 0) != 0) throw Failure(path, "write", errno);
    WriteAll(fd_, pid, path);  // at offset 0: nothing has moved the fresh descriptor's offset
  } catch (...) {
    for (int fd : enclosing_) close(fd);
    close(fd_);
    throw;
  }
}

void OutputDirectoryLock::LockEnclosing() {
  std::error_code error;
  const std::filesystem::path canonical = std::filesystem::canonical(directory_, error);
  if (error) return;  // created just above: only a race with its removal gets here
  for (std::filesystem::path dir = canonical.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    const std::string path = (dir / kFileName).string();
    // Only directories that were an output have a lock file; none is created here.
    const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    if (fd >= 0) {
      struct stat info;
      if (fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
        close(fd);
      } else if (!TryLock(fd, LOCK_SH)) {
        const long pid = HolderPid(fd);
        close(fd);
        throw OutputDirectoryInUse(directory_ + " lies inside " + dir.string() +
                                       ", which another nfrc run" + PidText(pid) +
                                       " is writing (a sweep writes its runs there)",
                                   pid);
      } else {
        enclosing_.push_back(fd);
      }
    }
    if (dir == dir.root_path()) break;
  }
}

void OutputDirectoryLock::RefuseBusyChildren() const {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory_, error)) {
    std::error_code kind;
    if (!entry.is_directory(kind) || entry.is_symlink(kind)) continue;
    const std::string path = (entry.path() / kFileName).string();
    const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) continue;
    struct stat info;
    const bool busy = fstat(fd, &info) == 0 && S_ISREG(info.st_mode) && !TryLock(fd, LOCK_SH);
    const long pid = busy ? HolderPid(fd) : 0;
    close(fd);  // also releases the probe's shared lock
    if (busy) {
      throw OutputDirectoryInUse(directory_ + " is in use: another nfrc run" + PidText(pid) +
                                     " writes into " + entry.path().string() + " inside it",
                                 pid);
    }
  }
}

OutputDirectoryLock::~OutputDirectoryLock() {
  // Clearing the pid while still locked means a later run never names a finished process.
  // A failure here is harmless (the lock goes with the close) and a destructor cannot report it.
  [[maybe_unused]] const int cleared = ftruncate(fd_, 0);
  close(fd_);
  for (int fd : enclosing_) close(fd);
}

}  // namespace nfrc
