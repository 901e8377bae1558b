#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/errors.h"
#include "tools/case_file.h"

namespace nfrc::testing {

// The InputError message ParseCase gives for a case document, or "no error".
inline std::string CaseError(const nlohmann::json& source) {
  try {
    ParseCase(source, ".");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

}  // namespace nfrc::testing
