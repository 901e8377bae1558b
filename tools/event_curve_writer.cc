#include "tools/event_curve_writer.h"

#include <filesystem>
#include <utility>

#include "tools/output_files.h"

namespace nfrc {

EventCurveWriter::EventCurveWriter(std::string path, const std::string& parameter, double from,
                                   double to, const std::string& measure, nlohmann::json source)
    : path_(std::move(path)), measure_(measure) {
  std::filesystem::create_directories(std::filesystem::path(path_).parent_path());
  document_["parameter"] = parameter;
  document_["from"] = from;
  document_["to"] = to;
  document_["measure"] = measure;
  document_["case"] = std::move(source);
  document_["points"] = nlohmann::json::array();
  document_["curves"] = nlohmann::json::array();
  document_["status"] = "running";
  Write();
}

void EventCurveWriter::OnPoint(int curve, const EventCurvePoint& point) {
  document_["points"].push_back({{"curve", curve},
                                 {"parameter", point.parameter},
                                 {"omega", point.omega},
                                 {measure_, point.measure},
                                 {"solves", point.solves}});
  if (schedule_.Due(false)) Write();
}

void EventCurveWriter::OnCurve(const EventCurve& curve) {
  ++curves_;
  document_["curves"].push_back({{"start_point", curve.start_point},
                                 {"start_omega", curve.start_omega},
                                 {"termination", ToString(curve.end)},
                                 {"message", curve.message},
                                 {"points", curve.points.size()},
                                 {"solves", curve.solves},
                                 {"seconds", curve.seconds}});
  Write();
}

void EventCurveWriter::Finish(const EventCurveResult& result, const std::string& status) {
  document_["branch_events"] = result.branch_events;
  document_["notes"] = result.notes;
  document_["status"] = status;
  Write();
}

void EventCurveWriter::Write() {
  schedule_.Timed([&] { WriteJsonAtomically(path_, document_); });
}

}  // namespace nfrc
