#pragma once

#include <nlohmann/json.hpp>

#include "analysis/validation_settings.h"

namespace nfrc {

// Reads a case's "validation" object (see ValidationSettings); throws InputError naming
// "validation.<field>". A null value gives the defaults.
ValidationSettings ReadValidationSettings(const nlohmann::json& validation);

}  // namespace nfrc
