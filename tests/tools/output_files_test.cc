#include "tools/output_files.h"

#include <doctest/doctest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

namespace nfrc {
namespace {

namespace fs = std::filesystem;

// A fresh, empty directory per test (the pid keeps parallel test processes apart).
fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("nfrc_output_files_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteFile(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::set<std::string> Entries(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

// Makes every write past `bytes` of a regular file fail with EFBIG, as a full disk makes
// them fail with ENOSPC, for as long as the object lives. SIGXFSZ is ignored meanwhile (its
// default action would end the process).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    REQUIRE(setrlimit(RLIMIT_FSIZE, &limit) == 0);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_handler_);
  }

 private:
  rlimit saved_;
  void (*previous_handler_)(int);
};

// A document whose dump is far larger than `bytes`.
nlohmann::json LargeDocument(int bytes) {
  return {{"points", std::vector<double>(static_cast<size_t>(bytes) / 4, 1.25)}};
}

TEST_CASE("WriteJsonAtomically writes the document and leaves no temporary file") {
  const fs::path dir = FreshDir("json");
  const nlohmann::json document = {{"points", {1, 2, 3}}, {"summary", "running"}};
  WriteJsonAtomically((dir / "branch.json").string(), document);
  WriteJsonAtomically((dir / "branch.json").string(), document);  // replaces the first
  CHECK(nlohmann::json::parse(ReadFile(dir / "branch.json")) == document);
  CHECK(Entries(dir) == std::set<std::string>{"branch.json"});
}

TEST_CASE("WriteJsonAtomically never follows a link planted at the old predictable temp name") {
  const fs::path dir = FreshDir("json_symlink");
  const fs::path victim = dir / "victim.txt";
  WriteFile(victim, "precious\n");
  fs::create_symlink(victim, dir / "branch.json.tmp");
  WriteJsonAtomically((dir / "branch.json").string(), {{"a", 1}});
  CHECK(ReadFile(victim) == "precious\n");
  CHECK(fs::is_symlink(dir / "branch.json.tmp"));
  CHECK(Entries(dir) == std::set<std::string>{"branch.json", "branch.json.tmp", "victim.txt"});
}

TEST_CASE("WriteJsonAtomically replaces a link at the target instead of writing through it") {
  const fs::path dir = FreshDir("json_target_symlink");
  const fs::path victim = dir / "victim.txt";
  WriteFile(victim, "precious\n");
  fs::create_symlink(victim, dir / "branch.json");
  WriteJsonAtomically((dir / "branch.json").string(), {{"a", 1}});
  CHECK(ReadFile(victim) == "precious\n");
  CHECK_FALSE(fs::is_symlink(dir / "branch.json"));
  CHECK(nlohmann::json::parse(ReadFile(dir / "branch.json"))["a"] == 1);
}

TEST_CASE(
    "WriteJsonAtomically on a full disk throws OutputError, keeps the old file, leaves no temp") {
  const fs::path dir = FreshDir("json_full");
  const std::string path = (dir / "branch.json").string();
  WriteJsonAtomically(path, {{"old", true}});
  const std::string before = ReadFile(path);
  std::string message;
  {
    const FileSizeLimit limit(4096);
    try {
      WriteJsonAtomically(path, LargeDocument(100000));
    } catch (const OutputError& error) {
      message = error.what();
    }
  }
  CHECK(message == path + ": cannot write: File too large");
  CHECK(ReadFile(path) == before);
  CHECK(Entries(dir) == std::set<std::string>{"branch.json"});
}

TEST_CASE("WriteJsonAtomically removes the temp file when the rename fails") {
  const fs::path dir = FreshDir("json_rename");
  fs::create_directories(dir / "branch.json" / "occupied");  // a directory cannot be replaced
  CHECK_THROWS_WITH_AS(WriteJsonAtomically((dir / "branch.json").string(), {{"a", 1}}),
                       doctest::Contains("branch.json: cannot replace: "), OutputError);
  CHECK(Entries(dir) == std::set<std::string>{"branch.json"});
}

TEST_CASE("WriteJsonAtomically into a missing directory names the file") {
  const fs::path dir = FreshDir("json_missing");
  const std::string path = (dir / "no" / "branch.json").string();
  CHECK_THROWS_WITH_AS(
      WriteJsonAtomically(path, {{"a", 1}}),
      doctest::Contains(
          (path + ": cannot create a temporary file: No such file or directory").c_str()),
      OutputError);
}

TEST_CASE("WriteCsv writes header and rows, atomically and never through a link") {
  const fs::path dir = FreshDir("csv");
  const fs::path victim = dir / "victim.txt";
  WriteFile(victim, "precious\n");
  fs::create_symlink(victim, dir / "signals_0.csv");
  Eigen::VectorXd t(2), x(2);
  t << 0.0, 0.5;
  x << 1.0, 1.0 / 3.0;
  WriteCsv((dir / "signals_0.csv").string(), {"t", "x"}, {t, x});
  CHECK(ReadFile(dir / "signals_0.csv") == "t,x\n0,1\n0.5,0.333333333333\n");
  CHECK(ReadFile(victim) == "precious\n");
  CHECK(Entries(dir) == std::set<std::string>{"signals_0.csv", "victim.txt"});
}

TEST_CASE("WriteCsv on a full disk throws OutputError and leaves no temp file") {
  const fs::path dir = FreshDir("csv_full");
  const Eigen::VectorXd column = Eigen::VectorXd::LinSpaced(20000, 0.0, 1.0);
  {
    const FileSizeLimit limit(4096);
    CHECK_THROWS_WITH_AS(WriteCsv((dir / "signals_0.csv").string(), {"t"}, {column}),
                         doctest::Contains("cannot write: File too large"), OutputError);
  }
  CHECK(Entries(dir).empty());
}

TEST_CASE("CsvStream writes what was appended at each Flush, with manipulators") {
  const fs::path dir = FreshDir("stream");
  const fs::path path = dir / "branch.csv";
  WriteFile(path, "an older run's much longer content\n");
  CsvStream csv(path.string());
  csv << "index,omega\n";
  csv.Flush();
  CHECK(ReadFile(path) == "index,omega\n");  // truncated, then the header only
  csv << 1 << ',' << 1.0 / 3.0 << '\n';
  CHECK(ReadFile(path) == "index,omega\n");  // nothing before the flush
  csv.Flush();
  csv << std::setprecision(3) << 2 << ',' << 2.0 / 3.0 << '\n';
  csv.Close();
  CHECK(ReadFile(path) == "index,omega\n1,0.333333333333\n2,0.667\n");
}

TEST_CASE(
    "CsvStream refuses a link at the target, to /dev/full or to a file, leaving it as it was") {
  const fs::path dir = FreshDir("stream_symlink");
  fs::create_symlink("/dev/full", dir / "branch.csv");
  CHECK_THROWS_WITH_AS(
      CsvStream((dir / "branch.csv").string()),
      doctest::Contains("branch.csv: cannot open for writing: it is a symbolic link"), OutputError);
  const fs::path victim = dir / "victim.txt";
  WriteFile(victim, "precious\n");
  fs::create_symlink(victim, dir / "other.csv");
  CHECK_THROWS_AS(CsvStream((dir / "other.csv").string()), OutputError);
  CHECK(ReadFile(victim) == "precious\n");
  // A dangling link is not followed to create its target either.
  fs::create_symlink(dir / "created_through_link", dir / "dangling.csv");
  CHECK_THROWS_AS(CsvStream((dir / "dangling.csv").string()), OutputError);
  CHECK_FALSE(fs::exists(dir / "created_through_link"));
}

TEST_CASE("CsvStream on a full device throws OutputError at the first Flush, and every later one") {
  CsvStream csv("/dev/full");
  csv << "index,omega\n";
  CHECK_THROWS_WITH_AS(csv.Flush(),
                       doctest::Contains("/dev/full: cannot write: No space left on device"),
                       OutputError);
  CHECK_THROWS_AS(csv.Flush(), OutputError);
  CHECK_THROWS_AS(csv.Close(), OutputError);
}

TEST_CASE("CsvStream refuses a FIFO at the target instead of waiting for a reader") {
  const fs::path dir = FreshDir("stream_fifo");
  REQUIRE(mkfifo((dir / "branch.csv").c_str(), 0600) == 0);
  CHECK_THROWS_AS(CsvStream((dir / "branch.csv").string()), OutputError);
}

TEST_CASE("Two OutputDirectoryLocks on one directory: the second is refused, naming the pid") {
  const fs::path dir = FreshDir("lock") / "out";  // created by the lock
  {
    const OutputDirectoryLock first(dir.string());
    CHECK(fs::is_directory(dir));
    CHECK(ReadFile(dir / OutputDirectoryLock::kFileName) == std::to_string(getpid()) + "\n");
    try {
      const OutputDirectoryLock second(dir.string());
      FAIL("the second lock was granted");
    } catch (const OutputDirectoryInUse& error) {
      CHECK(error.pid() == getpid());
      CHECK(std::string(error.what()) ==
            dir.string() + " is in use by another nfrc run (pid " + std::to_string(getpid()) + ")");
    }
  }
  const OutputDirectoryLock again(dir.string());  // released on destruction
}

TEST_CASE("OutputDirectoryLock conflicts across processes and is released when the holder dies") {
  const fs::path dir = FreshDir("lock_fork");
  int ready[2];
  REQUIRE(pipe(ready) == 0);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    // The child holds the lock until it is killed; _exit keeps doctest out of the child.
    try {
      const OutputDirectoryLock lock(dir.string());
      const char byte = 'x';
      if (write(ready[1], &byte, 1) != 1) _exit(2);
      pause();
    } catch (...) {
    }
    _exit(1);
  }
  close(ready[1]);
  char byte = 0;
  REQUIRE(read(ready[0], &byte, 1) == 1);
  close(ready[0]);
  try {
    const OutputDirectoryLock lock(dir.string());
    FAIL("the lock held by the child was granted");
  } catch (const OutputDirectoryInUse& error) {
    CHECK(error.pid() == child);
  }
  kill(child, SIGKILL);
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  CHECK(WIFSIGNALED(status));
  const OutputDirectoryLock lock(dir.string());  // the OS dropped the dead holder's lock
}

TEST_CASE("OutputDirectoryLock never follows a link planted at the lock file's name") {
  const fs::path dir = FreshDir("lock_symlink");
  const fs::path victim = dir / "victim.txt";
  WriteFile(victim, "precious\n");
  fs::create_symlink(victim, dir / OutputDirectoryLock::kFileName);
  CHECK_THROWS_WITH_AS(OutputDirectoryLock(dir.string()),
                       doctest::Contains("cannot create the lock file: it is a symbolic link"),
                       OutputError);
  CHECK(ReadFile(victim) == "precious\n");
}

TEST_CASE("OutputDirectoryLock on a path that is a file throws OutputError") {
  const fs::path dir = FreshDir("lock_file");
  WriteFile(dir / "plain", "x");
  CHECK_THROWS_WITH_AS(OutputDirectoryLock((dir / "plain").string()),
                       doctest::Contains("cannot create output directory"), OutputError);
}

}  // namespace
}  // namespace nfrc
