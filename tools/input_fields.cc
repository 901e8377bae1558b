#include "tools/input_fields.h"

#include <algorithm>
#include <cmath>

namespace nfrc {
namespace {

std::string Describe(const nlohmann::json& value) {
  std::string text = value.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

}  // namespace

InputFields::InputFields(const nlohmann::json& object, std::string path)
    : object_(object), path_(std::move(path)) {
  if (!object_.is_object()) {
    throw InputError(path_ + ": expected an object, got " + Describe(object_));
  }
}

bool InputFields::Has(const std::string& key) const { return object_.contains(key); }

void InputFields::Fail(const std::string& key, const std::string& problem) const {
  throw InputError(path_ + "." + key + ": " + problem);
}

const nlohmann::json& InputFields::Get(const std::string& key) {
  if (!object_.contains(key)) Fail(key, "missing (required)");
  if (std::find(read_.begin(), read_.end(), key) == read_.end()) read_.push_back(key);
  return object_.at(key);
}

const nlohmann::json& InputFields::RequiredValue(const std::string& key) { return Get(key); }

const nlohmann::json& InputFields::RequiredObject(const std::string& key) {
  const nlohmann::json& value = Get(key);
  if (!value.is_object()) Fail(key, "expected an object, got " + Describe(value));
  return value;
}

double InputFields::RequiredNumber(const std::string& key) {
  const nlohmann::json& value = Get(key);
  if (!value.is_number()) Fail(key, "expected a number, got " + Describe(value));
  const double number = value.get<double>();
  if (!std::isfinite(number)) Fail(key, "must be finite");
  return number;
}

double InputFields::OptionalNumber(const std::string& key, double fallback) {
  return Has(key) ? RequiredNumber(key) : fallback;
}

int InputFields::RequiredInt(const std::string& key) {
  const nlohmann::json& value = Get(key);
  if (!value.is_number_integer()) Fail(key, "expected an integer, got " + Describe(value));
  // An unsigned value above the int64 range would wrap to a negative one.
  if (value.is_number_unsigned() && value.get<unsigned long long>() > 2147483647ULL) {
    Fail(key, "integer out of range");
  }
  const auto number = value.get<long long>();
  if (number < -2147483647LL || number > 2147483647LL) Fail(key, "integer out of range");
  return static_cast<int>(number);
}

int InputFields::OptionalInt(const std::string& key, int fallback) {
  return Has(key) ? RequiredInt(key) : fallback;
}

bool InputFields::OptionalBool(const std::string& key, bool fallback) {
  if (!Has(key)) return fallback;
  const nlohmann::json& value = Get(key);
  if (!value.is_boolean()) Fail(key, "expected true or false, got " + Describe(value));
  return value.get<bool>();
}

std::string InputFields::RequiredString(const std::string& key) {
  const nlohmann::json& value = Get(key);
  if (!value.is_string()) Fail(key, "expected a string, got " + Describe(value));
  return value.get<std::string>();
}

std::string InputFields::OptionalString(const std::string& key, const std::string& fallback) {
  return Has(key) ? RequiredString(key) : fallback;
}

std::vector<double> InputFields::OptionalNumberList(const std::string& key) {
  std::vector<double> numbers;
  if (!Has(key)) return numbers;
  const nlohmann::json& value = Get(key);
  if (!value.is_array()) Fail(key, "expected a list of numbers, got " + Describe(value));
  for (const auto& item : value) {
    if (!item.is_number() || !std::isfinite(item.get<double>())) {
      Fail(key, "expected a list of finite numbers, got " + Describe(item));
    }
    numbers.push_back(item.get<double>());
  }
  return numbers;
}

int InputFields::RequiredDof(const std::string& key, const LinearModel& model) {
  return ResolveDof(Get(key), model, path_ + "." + key);
}

void InputFields::Finish() const {
  for (const auto& item : object_.items()) {
    if (std::find(read_.begin(), read_.end(), item.key()) == read_.end()) {
      throw InputError(path_ + "." + item.key() + ": unknown key");
    }
  }
}

int ResolveDof(const nlohmann::json& value, const LinearModel& model, const std::string& where) {
  const int num_dofs = model.num_dofs();
  if (value.is_number_integer()) {
    if (value.is_number_unsigned() && value.get<unsigned long long>() > 2147483647ULL) {
      throw InputError(where + ": DOF " + value.dump() + " out of range 0.." +
                       std::to_string(num_dofs - 1));
    }
    const auto index = value.get<long long>();
    if (index < 0 || index >= num_dofs) {
      throw InputError(where + ": DOF " + std::to_string(index) + " out of range 0.." +
                       std::to_string(num_dofs - 1));
    }
    return static_cast<int>(index);
  }
  if (value.is_string()) {
    const int index = model.FindDof(value.get<std::string>());
    if (index < 0) {
      throw InputError(where + ": no DOF named \"" + value.get<std::string>() + "\"");
    }
    return index;
  }
  throw InputError(where + ": expected a DOF index or name, got " + Describe(value));
}

}  // namespace nfrc
