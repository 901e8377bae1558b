#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/linear_model.h"
#include "nonlinearities/law_spec.h"

namespace nfrc {

// Reads one entry of a case's "nonlinearities" list into its specification, by "type".
// `path` names the entry in messages ("nonlinearities[0]"); throws InputError naming the
// field for an unknown or missing type (listing the known ones) and for any bad field.
LawSpec ReadLaw(const nlohmann::json& spec, const std::string& path, const LinearModel& model);

}  // namespace nfrc
