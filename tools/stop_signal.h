#pragma once

#include <atomic>
#include <functional>
#include <string>

namespace nfrc {

// Turns SIGINT, SIGTERM and SIGHUP into a stop request that long runs poll between steps, so
// an interrupted run (Ctrl-C, kill, a closed terminal or ssh session) keeps what it computed
// and writes its summary instead of dying with the summary still "running".
//
// While an object lives, sigaction handlers (SA_RESTART, so interrupted reads and writes
// resume) do nothing but store to lock-free atomics, which is async-signal-safe. The
// destructor restores the handlers that were there before. A signal the process inherited as
// ignored stays ignored (`nohup nfrc ...` keeps running after a hangup; a background job of a
// script keeps ignoring Ctrl-C), as shells expect.
//
// Force-quit: a second SIGINT after any stop request restores SIGINT's default action and
// kills the process at once, for a user whose run does not reach its next poll soon enough.
// The same happens to any stop signal while set_immediate(true) holds.
// A repeated SIGTERM or SIGHUP only keeps the request: one hangup may deliver SIGHUP twice
// (from the kernel and from the shell), and a service manager escalates to SIGKILL itself.
//
// Signal dispositions are per process, so at most one StopSignal may live at a time; the
// state it records is process-wide, which is why flag() and Poller() stay valid after it goes.
class StopSignal {
 public:
  // Clears any earlier request and installs the handlers; throws std::logic_error if another
  // StopSignal is alive, std::system_error if sigaction fails.
  StopSignal();
  ~StopSignal();
  StopSignal(const StopSignal&) = delete;
  StopSignal& operator=(const StopSignal&) = delete;

  // Immediate (while a command reads its case, reduces a model or plans a sweep: nothing
  // computed yet is worth keeping): a stop signal takes its default action at once, ending the
  // process. Deferred (the default, and once a run has begun): it raises the stop request.
  void set_immediate(bool immediate) const;

  // True once a stop signal has arrived.
  bool requested() const;
  // The first stop signal received (SIGINT, SIGTERM or SIGHUP), 0 if none.
  int signal_number() const;
  // "SIGINT", "SIGTERM" or "SIGHUP" for signal_number(), "" if none: for summary messages.
  std::string signal_name() const;

  // The request flag, for library code taking `const std::atomic<bool>* stop`.
  const std::atomic<bool>& flag() const;
  // A callable returning requested(), for code that polls through std::function.
  std::function<bool()> Poller() const;
};

}  // namespace nfrc
