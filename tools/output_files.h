#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace nfrc {

// An output file could not be created, written, closed or renamed into place (full disk,
// failing device, permissions, a symbolic link where a file should be). The message names
// the file and the system's reason. The CLI maps it to exit 4 (I/O error).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The output directory is locked by another live nfrc run (see OutputDirectoryLock). The CLI
// maps it to exit 1, not 4: nothing failed to read or write and no device is at fault; the
// command asked for a directory that is busy, and the remedy is the user's (another --out,
// or waiting for that run), like any other bad input. Exit 4 stays reserved for real I/O
// failures, which scripts may want to treat differently (retry elsewhere, alert).
class OutputDirectoryInUse : public std::runtime_error {
 public:
  // `pid` is the holder's process id as recorded in the lock file, 0 if unknown; `message`
  // says how the directory is in use.
  OutputDirectoryInUse(const std::string& message, long pid);
  long pid() const { return pid_; }

 private:
  long pid_;
};

// Writes columns of equal length as CSV with a header line, atomically as
// WriteJsonAtomically does (a symbolic link at `path` is replaced, never written through).
// Throws OutputError naming the file if it cannot be written.
void WriteCsv(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<Eigen::VectorXd>& data);

// Writes `document` to a new temporary file in path's directory and renames it over `path`,
// so a reader (or a run that stops part-way) never sees a half-written file. The temporary
// name is unpredictable and created exclusively (O_EXCL | O_NOFOLLOW), so nothing planted in
// the directory is ever followed; on any failure it is removed and OutputError is thrown.
void WriteJsonAtomically(const std::string& path, const nlohmann::json& document);

// A file written line by line while a run goes on (branch.csv): text accumulates in memory
// through operator<< and goes to the file at Flush(), with every write and the close checked,
// so a full disk stops the run with OutputError instead of silently losing points. The file is
// created or truncated, but never through a symbolic link (O_NOFOLLOW), and a FIFO or
// directory at the path is refused rather than blocked on or written into. After a failure
// the stream stays failed: every later Flush() throws again.
class CsvStream {
 public:
  // A closed stream; Open() it before writing.
  CsvStream();
  // Opens `path` as Open() does.
  explicit CsvStream(const std::string& path);
  // Flushes and closes, ignoring errors (a destructor cannot report them: call Close()).
  ~CsvStream();
  CsvStream(const CsvStream&) = delete;
  CsvStream& operator=(const CsvStream&) = delete;

  // Creates or truncates `path`; throws OutputError if it cannot, or if it is a symbolic link.
  void Open(const std::string& path);
  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

  // Appends `value` as an std::ostream would format it; manipulators such as
  // std::setprecision apply (the default precision is 12 significant digits).
  template <typename T>
  CsvStream& operator<<(const T& value) {
    buffer_ << value;
    return *this;
  }

  // Writes what was appended since the last Flush() to the file; throws OutputError (naming
  // the file and the system's reason) if any of it cannot be written.
  void Flush();
  // Flushes and closes the file, checking both; throws OutputError.
  void Close();

 private:
  std::string path_;
  int fd_ = -1;
  std::ostringstream buffer_;
  std::string failure_;  // the first error's message; non-empty once the stream has failed
};

// An exclusive lock on an output directory for the lifetime of the object, so two runs never
// interleave their files in one directory. Take it on `--out DIR` before anything is written.
// It is an flock(2) on DIR/.nfrc.lock, which holds the owner's pid for the message a second
// run gets; the OS drops the lock when the process exits or dies, so no stale lock can block
// a later run. The file itself stays (removing it would let two runs lock different inodes).
// Output directories nest (a sweep writes its runs into DIR/<k>/): every enclosing directory
// that has a lock file is locked shared, so a run into DIR/0 is refused while a sweep holds
// DIR; and a directory whose immediate subdirectory a live run holds is refused, so a sweep
// into DIR is refused while a run holds DIR/0.
class OutputDirectoryLock {
 public:
  static constexpr const char* kFileName = ".nfrc.lock";

  // Creates `directory` if needed and locks it without waiting. Throws OutputDirectoryInUse
  // if another run (or another OutputDirectoryLock in this process) holds it or an enclosing
  // output directory, OutputError if the directory or lock file cannot be created (or the
  // lock file is a symbolic link).
  explicit OutputDirectoryLock(std::string directory);
  // Releases the locks.
  ~OutputDirectoryLock();
  OutputDirectoryLock(const OutputDirectoryLock&) = delete;
  OutputDirectoryLock& operator=(const OutputDirectoryLock&) = delete;

  const std::string& directory() const { return directory_; }

 private:
  // Shared locks on the enclosing output directories; throws OutputDirectoryInUse.
  void LockEnclosing();
  // Throws OutputDirectoryInUse if a live run holds an immediate subdirectory.
  void RefuseBusyChildren() const;

  std::string directory_;
  int fd_ = -1;
  std::vector<int> enclosing_;  // shared-locked lock files of enclosing directories
};

}  // namespace nfrc
