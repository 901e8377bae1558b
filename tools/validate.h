#pragma once

#include <atomic>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

#include "analysis/case.h"
#include "analysis/validation_settings.h"

namespace nfrc {

// `nfrc validate`: traces the case's branch (DIR/hbm/), solves it at exactly each requested ω
// (every crossing of the branch: several inside a fold), integrates the same model in time to
// a periodic steady state (IDA, or the explicit Lagrange-multiplier scheme when the case has a
// rigid obstacle) from each HBM solution or from rest, and compares per output DOF max |x|,
// first-harmonic amplitude, mean energy, RMS difference of the signals and phase counts. With
// a chirp configured it also sweeps up and down. Writes DIR/validation.json (rewritten after
// every ω, so a run that stops keeps what was done), DIR/signals_<k>.csv (HBM and transient
// on the same grid) and DIR/chirp_<up|down>.csv, prints a table to `table` and progress to
// `progress`. Returns the document; throws InputError for bad input.
nlohmann::json RunValidation(const Case& the_case, const ValidationSettings& settings,
                             const std::string& out_dir, std::ostream* progress,
                             std::ostream* table, const std::atomic<bool>* stop = nullptr,
                             const nlohmann::json& source = nullptr);

// True if every transient and chirp of the document ran (periodic or not) and every ω had an
// HBM solution: what `nfrc validate` turns into its exit status.
bool ValidationComplete(const nlohmann::json& document);

}  // namespace nfrc
