#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/linear_model.h"

namespace nfrc {

// Reads the "model" object of a case file by its "type" ("matrices" or "rod"). Relative file
// paths are resolved against base_dir. Throws InputError naming the field or file for any
// problem: unknown keys, wrong sizes, negative masses, bad files.
ModelDefinition BuildModel(const nlohmann::json& spec, const std::string& base_dir);

}  // namespace nfrc
