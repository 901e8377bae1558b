#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/linear_model.h"
#include "nonlinearities/nonlinearity.h"

namespace nfrc {

// Builds a law from its case-file object; `path` names the object in error messages.
using NonlinearityFactory = std::unique_ptr<Nonlinearity> (*)(const nlohmann::json& spec,
                                                              const std::string& path,
                                                              const LinearModel& model);

// Case-file "type" → factory. Adding a law adds one line here.
const std::map<std::string, NonlinearityFactory>& NonlinearityRegistry();

// Builds the law named by spec["type"]; throws InputError naming the field for an unknown
// or missing type (listing the known ones) and for any bad field of the law.
std::unique_ptr<Nonlinearity> MakeNonlinearity(const nlohmann::json& spec, const std::string& path,
                                               const LinearModel& model);

}  // namespace nfrc
