#include "tools/output_files.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <stdexcept>

namespace nfrc {

void WriteCsv(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<Eigen::VectorXd>& data) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  out << std::setprecision(12);
  for (size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
  out << "\n";
  for (Eigen::Index j = 0; j < data.front().size(); ++j) {
    for (size_t c = 0; c < data.size(); ++c) out << (c ? "," : "") << data[c](j);
    out << "\n";
  }
  if (!out) throw std::runtime_error(path + ": write failed");
}

void WriteJsonAtomically(const std::string& path, const nlohmann::json& document) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary);
    if (!out) throw std::runtime_error(temporary + ": cannot open for writing");
    out << document.dump(1) << "\n";
    if (!out) throw std::runtime_error(temporary + ": write failed");
  }
  std::filesystem::rename(temporary, path);
}


}  // namespace nfrc
