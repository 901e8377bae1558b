#include "tools/fold_curve_writer.h"

#include <filesystem>
#include <utility>

#include "tools/output_files.h"

namespace nfrc {

FoldCurveWriter::FoldCurveWriter(std::string dir, const Case& the_case,
                                 const std::string& parameter, double from, double to,
                                 nlohmann::json source)
    : path_(std::move(dir) + "/fold_curve.json"), output_names_(the_case.output_names) {
  std::filesystem::create_directories(std::filesystem::path(path_).parent_path());
  document_["parameter"] = parameter;
  document_["from"] = from;
  document_["to"] = to;
  document_["case"] = std::move(source);
  document_["points"] = nlohmann::json::array();
  document_["cusps"] = nlohmann::json::array();
  document_["turns"] = nlohmann::json::array();
  document_["curves"] = nlohmann::json::array();
  document_["status"] = "running";
  Write();
}

void FoldCurveWriter::OnPoint(int curve, const FoldCurvePoint& point) {
  nlohmann::json out = {{"curve", curve},
                        {"parameter", point.parameter},
                        {"omega", point.omega},
                        {"energy", point.energy},
                        {"newton", point.newton_iterations}};
  for (size_t i = 0; i < point.max_abs.size() && i < output_names_.size(); ++i) {
    out["max_abs_" + output_names_[i]] = point.max_abs[i];
  }
  document_["points"].push_back(std::move(out));
  if (schedule_.Due(false)) Write();
}

void FoldCurveWriter::OnCurve(const FoldCurve& curve) {
  const int index = curves_++;
  for (const FoldCurveTurn& turn : curve.turns) {
    const nlohmann::json out = {{"curve", index},
                                {"parameter", turn.parameter},
                                {"omega", turn.omega},
                                {"after_point", turn.after_point},
                                {"cusp", turn.cusp}};
    document_["turns"].push_back(out);
    if (turn.cusp) document_["cusps"].push_back(out);
  }
  document_["curves"].push_back({{"start_fold", curve.start_fold},
                                 {"start_omega", curve.start_omega},
                                 {"termination", ToString(curve.summary.reason)},
                                 {"message", curve.summary.message},
                                 {"points", curve.points.size()},
                                 {"newton", curve.summary.total_newton_iterations},
                                 {"seconds", curve.summary.wall_time_seconds}});
  Write();
}

void FoldCurveWriter::Finish(const FoldCurveResult& result, const std::string& status) {
  document_["branch_folds"] = result.branch_folds;
  document_["notes"] = result.notes;
  document_["status"] = status;
  Write();
}

void FoldCurveWriter::Write() {
  schedule_.Timed([&] { WriteJsonAtomically(path_, document_); });
}

}  // namespace nfrc
