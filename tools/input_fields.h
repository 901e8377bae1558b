#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/linear_model.h"

namespace nfrc {

// Strict reader of one JSON object of a case file. Every read names the field in its error
// message; Finish() rejects keys nobody read, so a misspelt option never passes silently.
class InputFields {
 public:
  // `path` is how messages name this object, e.g. "model" or "nonlinearities[1]".
  InputFields(const nlohmann::json& object, std::string path);

  const std::string& path() const { return path_; }
  bool Has(const std::string& key) const;

  double RequiredNumber(const std::string& key);
  double OptionalNumber(const std::string& key, double fallback);
  int RequiredInt(const std::string& key);
  int OptionalInt(const std::string& key, int fallback);
  bool OptionalBool(const std::string& key, bool fallback);
  std::string RequiredString(const std::string& key);
  std::string OptionalString(const std::string& key, const std::string& fallback);
  std::vector<double> OptionalNumberList(const std::string& key);
  // The raw value (marks the key as read); throws if missing.
  const nlohmann::json& RequiredValue(const std::string& key);
  // A nested object, for a nested InputFields; throws if missing or not an object.
  const nlohmann::json& RequiredObject(const std::string& key);

  // A DOF given as an index or, if the model names its DOFs, as a name.
  int RequiredDof(const std::string& key, const LinearModel& model);

  // Throws naming the first key present in the object but never read.
  void Finish() const;

  // Throws InputError("<path>.<key>: <problem>").
  [[noreturn]] void Fail(const std::string& key, const std::string& problem) const;

 private:
  const nlohmann::json& Get(const std::string& key);

  const nlohmann::json& object_;
  std::string path_;
  std::vector<std::string> read_;
};

// Resolves a DOF written as an index or a name; `where` names the field in messages.
int ResolveDof(const nlohmann::json& value, const LinearModel& model, const std::string& where);

}  // namespace nfrc
