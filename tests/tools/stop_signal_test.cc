#include "tools/stop_signal.h"

#include <doctest/doctest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace nfrc {
namespace {

volatile sig_atomic_t g_custom_calls = 0;
void CustomHandler(int) { g_custom_calls = g_custom_calls + 1; }

// Whether `handler` is the one installed for `signal_number`.
bool Installed(int signal_number, void (*handler)(int)) {
  struct sigaction action;
  sigaction(signal_number, nullptr, &action);
  return action.sa_handler == handler;
}

// Installs `handler` for `signal_number` for as long as the object lives.
class ScopedHandler {
 public:
  ScopedHandler(int signal_number, void (*handler)(int)) : signal_number_(signal_number) {
    struct sigaction action = {};
    action.sa_handler = handler;
    sigemptyset(&action.sa_mask);
    sigaction(signal_number, &action, &saved_);
  }
  ~ScopedHandler() { sigaction(signal_number_, &saved_, nullptr); }

 private:
  int signal_number_;
  struct sigaction saved_;
};

TEST_CASE("StopSignal turns SIGINT, SIGTERM and SIGHUP into a stop request") {
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    CAPTURE(signal_number);
    const StopSignal stop;
    CHECK_FALSE(stop.requested());
    CHECK(stop.signal_number() == 0);
    CHECK(stop.signal_name().empty());
    const std::function<bool()> poll = stop.Poller();
    const std::atomic<bool>* flag = &stop.flag();
    CHECK_FALSE(poll());
    REQUIRE(raise(signal_number) == 0);
    CHECK(stop.requested());
    CHECK(poll());
    CHECK(flag->load());
    CHECK(stop.signal_number() == signal_number);
  }
}

TEST_CASE("StopSignal records the first signal and survives repeated SIGTERM and SIGHUP") {
  const StopSignal stop;
  raise(SIGHUP);
  raise(SIGHUP);  // one hangup may come twice (kernel and shell): the run must go on
  raise(SIGTERM);
  CHECK(stop.requested());
  CHECK(stop.signal_number() == SIGHUP);
  CHECK(stop.signal_name() == "SIGHUP");
}

TEST_CASE("StopSignal restores the previous handlers on destruction") {
  const ScopedHandler int_handler(SIGINT, CustomHandler);
  const ScopedHandler hup_handler(SIGHUP, SIG_DFL);
  {
    const StopSignal stop;
    CHECK_FALSE(Installed(SIGINT, CustomHandler));
    raise(SIGINT);
    CHECK(g_custom_calls == 0);
  }
  CHECK(Installed(SIGINT, CustomHandler));
  CHECK(Installed(SIGHUP, SIG_DFL));
  raise(SIGINT);
  CHECK(g_custom_calls == 1);
}

TEST_CASE("StopSignal leaves a signal the process ignores ignored (nohup)") {
  const ScopedHandler ignored(SIGHUP, SIG_IGN);
  const StopSignal stop;
  CHECK(Installed(SIGHUP, SIG_IGN));
  raise(SIGHUP);
  CHECK_FALSE(stop.requested());
  raise(SIGTERM);
  CHECK(stop.signal_number() == SIGTERM);
}

TEST_CASE("StopSignal: a new one starts unrequested, and only one may live at a time") {
  {
    const StopSignal stop;
    raise(SIGTERM);
    CHECK(stop.requested());
    CHECK_THROWS_AS(StopSignal(), std::logic_error);
  }
  const StopSignal stop;
  CHECK_FALSE(stop.requested());
  CHECK(stop.signal_number() == 0);
}

TEST_CASE("StopSignal: a second SIGINT while stopping kills the process (force-quit)") {
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    // _exit keeps doctest out of the child; its status tells the parent what happened.
    const StopSignal stop;
    raise(SIGINT);
    if (!stop.requested()) _exit(1);
    raise(SIGINT);
    _exit(2);  // reached only if the second SIGINT did not kill
  }
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  CHECK(WIFSIGNALED(status));
  CHECK((WIFSIGNALED(status) && WTERMSIG(status) == SIGINT));
}

}  // namespace
}  // namespace nfrc
