#include "tools/rewrite_schedule.h"

#include <doctest/doctest.h>

namespace nfrc {
namespace {

using Clock = RewriteSchedule::Clock;
using std::chrono::milliseconds;

TEST_CASE("rewrite schedule: the interval between quick writes, ten durations after slow ones") {
  RewriteSchedule schedule(milliseconds(1000));
  const Clock::time_point t0{};  // the clock's epoch: times below are offsets from it
  // A quick first write (1 ms) at 0.
  schedule.Wrote(t0, t0 + milliseconds(1));
  CHECK_FALSE(schedule.Due(false, t0 + milliseconds(500)));
  CHECK(schedule.Due(false, t0 + milliseconds(1002)));
  // An urgent change waits only for ten durations (10 ms).
  CHECK_FALSE(schedule.Due(true, t0 + milliseconds(5)));
  CHECK(schedule.Due(true, t0 + milliseconds(12)));
  // A slow write (3 s: a large document) spaces the next by 30 s, urgent or not.
  schedule.Wrote(t0 + milliseconds(2000), t0 + milliseconds(5000));
  CHECK_FALSE(schedule.Due(true, t0 + milliseconds(5000 + 29000)));
  CHECK_FALSE(schedule.Due(false, t0 + milliseconds(5000 + 29000)));
  CHECK(schedule.Due(true, t0 + milliseconds(5000 + 30001)));
  CHECK(schedule.writes() == 2);
}

TEST_CASE("rewrite schedule: writing is at most a tenth of the time, however many changes") {
  // A document whose write takes `cost` ms, changed every ms (urgent) for ten minutes: the
  // time spent writing stays near 1/(kDurationFactor + 1) of the whole.
  for (const int cost : {1, 40, 700}) {
    CAPTURE(cost);
    RewriteSchedule schedule(milliseconds(1000));
    Clock::time_point now{};
    long writing = 0;
    const Clock::time_point end = now + milliseconds(600000);
    while (now < end) {
      now += milliseconds(1);
      if (schedule.Due(true, now)) {
        schedule.Wrote(now, now + milliseconds(cost));
        now += milliseconds(cost);
        writing += cost;
      }
    }
    CHECK(static_cast<double>(writing) <= 600000.0 / (RewriteSchedule::kDurationFactor + 1) + cost);
  }
}

}  // namespace
}  // namespace nfrc
