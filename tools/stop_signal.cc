#include "tools/stop_signal.h"

#include <signal.h>

#include <array>
#include <cerrno>
#include <stdexcept>
#include <system_error>

namespace nfrc {
namespace {

// Only lock-free atomics may be touched from a signal handler.
static_assert(std::atomic<bool>::is_always_lock_free);
static_assert(std::atomic<int>::is_always_lock_free);

constexpr std::array<int, 3> kSignals = {SIGINT, SIGTERM, SIGHUP};

std::atomic<bool> g_requested{false};
std::atomic<int> g_signal{0};  // the first stop signal, 0 before one arrives
std::atomic<bool> g_alive{false};
// Set while nothing worth keeping has been computed (reading a case, reducing a model): a stop
// signal then takes the signal's default action at once instead of waiting for a poll.
std::atomic<bool> g_immediate{false};

// The dispositions found at construction, restored at destruction; one per kSignals entry.
std::array<struct sigaction, kSignals.size()> g_previous;
std::array<bool, kSignals.size()> g_installed{};

void OnStopSignal(int signal_number) {
  if (g_immediate.load() || (signal_number == SIGINT && g_requested.load())) {
    // Force-quit: the default action (termination) happens as the handler returns, because
    // the raised SIGINT is blocked until then. Both calls are async-signal-safe; errno is
    // kept for the interrupted code in case termination is somehow not immediate.
    const int saved_errno = errno;
    struct sigaction default_action = {};
    default_action.sa_handler = SIG_DFL;
    sigaction(signal_number, &default_action, nullptr);
    raise(signal_number);
    errno = saved_errno;
    return;
  }
  int none = 0;
  g_signal.compare_exchange_strong(none, signal_number);
  g_requested.store(true);
}

// Puts back every disposition that Install replaced.
void RestorePrevious() {
  for (size_t i = 0; i < kSignals.size(); ++i) {
    if (g_installed[i]) sigaction(kSignals[i], &g_previous[i], nullptr);
    g_installed[i] = false;
  }
}

// Installs `action` for every stop signal not inherited as ignored; throws std::system_error.
void Install(const struct sigaction& action) {
  for (size_t i = 0; i < kSignals.size(); ++i) {
    if (sigaction(kSignals[i], nullptr, &g_previous[i]) != 0) {
      throw std::system_error(errno, std::system_category(), "sigaction");
    }
    if (g_previous[i].sa_handler == SIG_IGN && !(g_previous[i].sa_flags & SA_SIGINFO)) continue;
    if (sigaction(kSignals[i], &action, nullptr) != 0) {
      throw std::system_error(errno, std::system_category(), "sigaction");
    }
    g_installed[i] = true;
  }
}

}  // namespace

StopSignal::StopSignal() {
  if (g_alive.exchange(true)) throw std::logic_error("only one StopSignal may exist at a time");
  g_requested.store(false);
  g_signal.store(0);
  struct sigaction action = {};
  action.sa_handler = OnStopSignal;
  action.sa_flags = SA_RESTART;
  sigemptyset(&action.sa_mask);
  // Every stop signal is blocked while the handler runs, so the "first signal" race is moot.
  for (int signal_number : kSignals) sigaddset(&action.sa_mask, signal_number);
  try {
    Install(action);
  } catch (...) {
    RestorePrevious();
    g_alive.store(false);
    throw;
  }
}

StopSignal::~StopSignal() {
  g_immediate.store(false);
  RestorePrevious();
  g_alive.store(false);
}

void StopSignal::set_immediate(bool immediate) const { g_immediate.store(immediate); }

bool StopSignal::requested() const { return g_requested.load(); }

int StopSignal::signal_number() const { return g_signal.load(); }

std::string StopSignal::signal_name() const {
  switch (g_signal.load()) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "";
  }
}

const std::atomic<bool>& StopSignal::flag() const { return g_requested; }

std::function<bool()> StopSignal::Poller() const {
  return [] { return g_requested.load(); };
}

}  // namespace nfrc
