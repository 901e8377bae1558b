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

// Natural-parameter LCP-HBM stepping (continuation.method "lemke_stepping").
struct SteppingOptions {
  int points = 201;  // evenly spaced ω from omega_start to omega_end, both included
  bool track_contact =
      true;  // warm-start Lemke where the cold solve is trivial (see lcp_stepping.h)
};

// A parsed case file: everything `nfrc run` needs, validated.
struct Case {
  std::string path;       // file it came from (empty if parsed from memory)
  std::string base_dir;   // directory relative matrix files resolve against
  nlohmann::json source;  // the case as written
  ModelDefinition model;
  HarmonicSet harmonics{1, false};
  std::vector<std::unique_ptr<Nonlinearity>> laws;
  // "arclength" (the continuation engine) or "lemke_stepping" (LCP-HBM, lcp_stepping.h);
  // both take the ω range from `continuation`.
  std::string method = "arclength";
  ContinuationOptions continuation;
  SteppingOptions stepping;
  std::vector<int> output_dofs;           // model DOF indices
  std::vector<std::string> output_names;  // as the case names them (index or name)
  std::vector<double> signals_at;         // ω at which time signals are written
  // The optional "validation" object for `nfrc validate` (tools/validation_settings.h), as
  // written; null when absent. `nfrc run` does not read it.
  nlohmann::json validation;
};

// Reads and validates a case file. Throws InputError naming the file or field.
Case LoadCase(const std::string& path);

// The same from an in-memory JSON value; relative matrix files resolve against base_dir.
Case ParseCase(const nlohmann::json& source, const std::string& base_dir);

}  // namespace nfrc
