#pragma once

#include <chrono>

namespace nfrc {

// When a document that grows as a run goes (branch.json, sweep.json, fold_curve.json, ...) is
// rewritten: at most every `interval` (what a reader of it, a plot or a user, sees is never
// older), or every kDurationFactor times the last write's duration if that is longer, so that
// rewriting a large document stays about a tenth of the run however often it changes (a
// 100 000-run sweep.json of 31 MB is not rewritten after every run). An urgent change (a fold,
// a finished run) waits for the duration rule only. The run's last write is not scheduled:
// writers make it unconditionally.
class RewriteSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kDurationFactor = 10;

  explicit RewriteSchedule(Clock::duration interval) : interval_(interval) {}

  // Whether a rewrite is due at `now`.
  bool Due(bool urgent, Clock::time_point now = Clock::now()) const;
  // Records a write that ran from `start` to `end`.
  void Wrote(Clock::time_point start, Clock::time_point end = Clock::now());
  // Runs `write` and records how long it took.
  template <typename Write>
  void Timed(Write&& write) {
    const Clock::time_point start = Clock::now();
    write();
    Wrote(start);
  }
  int writes() const { return writes_; }

 private:
  Clock::duration interval_;
  Clock::time_point last_end_{};
  Clock::duration last_duration_{};
  int writes_ = 0;
};

}  // namespace nfrc
