#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/linear_model.h"
#include "tools/reduction_reader.h"

namespace nfrc {

// Reads the "model" object of a case file by its "type" ("matrices" or "rod"). Relative file
// paths are resolved against base_dir. Throws InputError naming the field or file for any
// problem: unknown keys, wrong sizes, negative masses, bad files. A "reduction" object is
// returned in `reduction` (the full model is returned: the caller reduces it once it knows
// the boundary DOFs, ApplyReduction); without `reduction` one is refused.
ModelDefinition BuildModel(const nlohmann::json& spec, const std::string& base_dir,
                           std::optional<ReductionRequest>* reduction = nullptr);

}  // namespace nfrc
