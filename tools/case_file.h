#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "continuation/options.h"
#include "core/harmonic_set.h"
#include "models/model_builder.h"
#include "nonlinearities/nonlinearity.h"

namespace nfrc {

// A parsed case file: everything `nfrc run` needs, validated.
struct Case {
  std::string path;       // file it came from (empty if parsed from memory)
  std::string base_dir;   // directory relative matrix files resolve against
  nlohmann::json source;  // the case as written
  ModelDefinition model;
  HarmonicSet harmonics{1, false};
  std::vector<std::unique_ptr<Nonlinearity>> laws;
  ContinuationOptions continuation;
  std::vector<int> output_dofs;           // model DOF indices
  std::vector<std::string> output_names;  // as the case names them (index or name)
  std::vector<double> signals_at;         // ω at which time signals are written
};

// Reads and validates a case file. Throws InputError naming the file or field.
Case LoadCase(const std::string& path);

// The same from an in-memory JSON value; relative matrix files resolve against base_dir.
Case ParseCase(const nlohmann::json& source, const std::string& base_dir);

}  // namespace nfrc
