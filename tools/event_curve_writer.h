#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "analysis/event_curve.h"
#include "tools/rewrite_schedule.h"

namespace nfrc {

// Writes DIR/peak_curve.json or DIR/neimark_sacker_curve.json (`path`), rewritten (atomically)
// as points come (on a RewriteSchedule of kInterval), after each curve and at the end, so an
// interrupted, failing or killed run keeps the points already found:
// - "parameter", "from", "to", "measure", "branch_events", "notes", "case" (as written),
//   "status" ("running" until Finish, then "complete", "incomplete" or "interrupted");
// - "points": [{"curve", "parameter", "omega", <measure>, "solves"}], each curve's points in
//   order from the case's value towards "to", curve after curve;
// - "curves": [{"start_point", "start_omega", "termination", "message", "points", "solves",
//   "seconds"}].
// It only writes: it never solves.
class EventCurveWriter : public EventCurveObserver {
 public:
  // Creates the directory of `path` and writes the document without curves; OutputError if it
  // cannot.
  EventCurveWriter(std::string path, const std::string& parameter, double from, double to,
                   const std::string& measure, nlohmann::json source);
  void OnPoint(int curve, const EventCurvePoint& point) override;
  void OnCurve(const EventCurve& curve) override;
  // The final document (notes and counts of the finished run, and its status).
  void Finish(const EventCurveResult& result, const std::string& status);

  static constexpr std::chrono::milliseconds kInterval{1000};

 private:
  void Write();

  RewriteSchedule schedule_{kInterval};
  std::string path_;
  std::string measure_;
  nlohmann::json document_;
  int curves_ = 0;
};

}  // namespace nfrc
