#include "tools/rewrite_schedule.h"

#include <algorithm>

namespace nfrc {

bool RewriteSchedule::Due(bool urgent, Clock::time_point now) const {
  const Clock::duration spacing = kDurationFactor * last_duration_;
  const Clock::duration due = urgent ? spacing : std::max(spacing, interval_);
  return now - last_end_ > due;
}

void RewriteSchedule::Wrote(Clock::time_point start, Clock::time_point end) {
  last_end_ = end;
  last_duration_ = end - start;
  ++writes_;
}

}  // namespace nfrc
