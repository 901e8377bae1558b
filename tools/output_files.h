#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nfrc {

// Writes columns of equal length as CSV with a header line; throws std::runtime_error naming
// the file if it cannot be written.
void WriteCsv(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<Eigen::VectorXd>& data);

// Writes `document` to path.tmp and renames it over `path`, so a reader (or a run that stops
// part-way) never sees a half-written file.
void WriteJsonAtomically(const std::string& path, const nlohmann::json& document);

}  // namespace nfrc
