#pragma once

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nfrc {

// A change to one field of a case file: the field's path in the JSON ("model.M[1][1]",
// "harmonics.max", "nonlinearities[0].law") and its new value; null removes the field, so that
// its default applies.
struct FieldChange {
  std::string path;
  nlohmann::json value;
};

// Applies `change` to `source`. The path must lead through objects and lists that exist (an
// index within its list); only its last name may be new. Otherwise InputError naming `what`
// and the path. What the new value means is left to the case reader.
void ApplyFieldChange(nlohmann::json* source, const FieldChange& change, const std::string& what);
// Throws as ApplyFieldChange would for `changes` applied in order to `source`, without
// copying or changing anything; each change is named "<what>: <path>" in messages.
void CheckFieldChanges(const nlohmann::json& source, const std::vector<FieldChange>& changes,
                       const std::string& what);
// A number as a case file writes it: whole numbers as integers (so that integer fields such as
// harmonics.max accept them), others as doubles.
nlohmann::json NumberJson(double value);
// The value at `path`, null if any part of the path is missing.
nlohmann::json FieldAt(const nlohmann::json& source, const std::string& path);

// One member of a manifest: its name and its changes to the base case.
struct CaseVariant {
  std::string name;
  std::vector<FieldChange> changes;
};

// A manifest: a base case file and the variants of it a study runs, in place of near-copies
// of the case. Its file holds
//   {"manifest": "what the variants are for", "base": "case.json",
//    "variants": [{"name": "n8", "set": {"nonlinearities[0].normal_load": 8}}, ...]}
// or, for a grid, "parameters": [{"path", "values"}, ...] (the Cartesian product, the last
// parameter varying fastest, as `nfrc sweep`) with optional "names", one per grid point.
// A member is named FILE#NAME (or FILE#INDEX) wherever a case file is read.
struct CaseManifest {
  std::string path;       // the manifest file
  std::string base_path;  // the base case file, resolved against the manifest's folder
  nlohmann::json base;    // the base case as read
  std::vector<CaseVariant> variants;
};

bool IsManifest(const nlohmann::json& document);
// Throws InputError naming the manifest file and the field.
CaseManifest ParseManifest(const nlohmann::json& document, const std::string& path);
// The same with the base case's JSON from `read_base` (given the base's resolved path) instead
// of its file: for a fuzzer, which reads no file.
CaseManifest ParseManifest(const nlohmann::json& document, const std::string& path,
                           const std::function<nlohmann::json(const std::string&)>& read_base);
CaseManifest ReadManifest(const std::string& path);
// The members' names joined by ", " (for messages listing them).
std::string MemberNames(const CaseManifest& manifest);
// The index of the member named `member` (a name, or an index among the variants); InputError
// listing the names if there is none.
size_t FindVariant(const CaseManifest& manifest, const std::string& member);
// The case-file JSON of variant `index`: the base with its changes, titled after the variant
// unless it sets "title". InputError naming the manifest and the variant if a change does not
// apply.
nlohmann::json VariantSource(const CaseManifest& manifest, size_t index);

}  // namespace nfrc
