#pragma once

#include <atomic>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

#include "analysis/case.h"
#include "analysis/validate.h"
#include "analysis/validation_settings.h"

namespace nfrc {

// `nfrc validate`: validates the case (ValidateCase) and writes what it finds as it goes
// (ValidationWriter): DIR/hbm/ (the branch), DIR/validation.json (rewritten after every ω, so
// a run that stops keeps what was done), DIR/signals_<k>.csv (HBM and transient on the same
// grid), DIR/chirp_<up|down>.csv, a table to `table` and progress to `progress`. `stop` (may
// be null) is polled between runs. `source` is the case as written, recorded in
// hbm/branch.json. Throws InputError for bad input and std::runtime_error for I/O.
ValidationResult RunValidation(const Case& the_case, const ValidationSettings& settings,
                               const std::string& out_dir, std::ostream* progress,
                               std::ostream* table, const std::atomic<bool>* stop = nullptr,
                               const nlohmann::json& source = nullptr);

}  // namespace nfrc
