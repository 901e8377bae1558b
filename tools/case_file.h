#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "analysis/case.h"

namespace nfrc {

// A case file as read: the typed case and the JSON it came from (for the outputs' record of
// what was run). JSON stays here, at the edge.
struct CaseFile {
  nlohmann::json source;  // of a manifest's member: the base case with the member's changes
  Case the_case;
  std::string base_dir;  // the folder relative matrix files resolve against
};

// Reads and validates a case file, or the member of a manifest named as FILE#NAME (see
// CaseManifest). Throws InputError naming the file and the field.
CaseFile ReadCaseFile(const std::string& path);
Case LoadCase(const std::string& path);

// The same from an in-memory JSON value; relative matrix files resolve against base_dir.
Case ParseCase(const nlohmann::json& source, const std::string& base_dir);

}  // namespace nfrc
