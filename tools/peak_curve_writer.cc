#include "tools/peak_curve_writer.h"

#include <filesystem>
#include <utility>

#include "tools/output_files.h"

namespace nfrc {

PeakCurveWriter::PeakCurveWriter(std::string dir, const std::string& parameter, double from,
                                 double to, const std::string& measure, nlohmann::json source)
    : path_(std::move(dir) + "/peak_curve.json"), measure_(measure) {
  std::filesystem::create_directories(std::filesystem::path(path_).parent_path());
  document_["parameter"] = parameter;
  document_["from"] = from;
  document_["to"] = to;
  document_["measure"] = measure;
  document_["case"] = std::move(source);
  document_["points"] = nlohmann::json::array();
  document_["curves"] = nlohmann::json::array();
  Write();
}

void PeakCurveWriter::OnCurve(const PeakCurve& curve) {
  const int index = curves_++;
  for (const PeakCurvePoint& point : curve.points) {
    document_["points"].push_back({{"curve", index},
                                   {"parameter", point.parameter},
                                   {"omega", point.omega},
                                   {measure_, point.measure},
                                   {"solves", point.solves}});
  }
  document_["curves"].push_back({{"start_point", curve.start_point},
                                 {"start_omega", curve.start_omega},
                                 {"termination", ToString(curve.end)},
                                 {"message", curve.message},
                                 {"points", curve.points.size()},
                                 {"solves", curve.solves},
                                 {"seconds", curve.seconds}});
  Write();
}

void PeakCurveWriter::Finish(const PeakCurveResult& result) {
  document_["branch_peaks"] = result.branch_peaks;
  document_["notes"] = result.notes;
  Write();
}

void PeakCurveWriter::Write() { WriteJsonAtomically(path_, document_); }

}  // namespace nfrc
