#include "tools/case_manifest.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <sstream>
#include <unordered_set>
#include <utility>

#include "core/errors.h"
#include "tools/input_fields.h"
#include "tools/json_input.h"

namespace nfrc {
namespace {

// One step of a path: a member name, or an index into a list.
struct PathStep {
  std::string name;  // empty for an index
  size_t index = 0;
};

// "model.M[1][1]" as {model}{M}[1][1]; nullopt if the text is not such a path.
std::optional<std::vector<PathStep>> ParsePath(const std::string& path) {
  std::vector<PathStep> steps;
  size_t at = 0;
  const auto name_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
  };
  while (true) {
    const size_t start = at;
    while (at < path.size() && name_char(path[at])) ++at;
    if (at == start) return std::nullopt;
    steps.push_back({path.substr(start, at - start), 0});
    while (at < path.size() && path[at] == '[') {
      const size_t digits = ++at;
      while (at < path.size() && std::isdigit(static_cast<unsigned char>(path[at])) != 0) ++at;
      // At most 9 digits: no index of a case file is that large, and stoul cannot overflow.
      if (at == digits || at - digits > 9 || at >= path.size() || path[at] != ']') {
        return std::nullopt;
      }
      steps.push_back({"", std::stoul(path.substr(digits, at - digits))});
      ++at;
    }
    if (at == path.size()) return steps;
    if (path[at] != '.') return std::nullopt;
    ++at;
  }
}

std::string Describe(const nlohmann::json& value) {
  if (value.is_number_float()) {
    std::ostringstream text;
    text << value.get<double>();
    return text.str();
  }
  return value.dump();
}

// The steps of `change`'s path, or InputError naming `what` and the path.
std::vector<PathStep> StepsOf(const FieldChange& change, const std::string& what) {
  std::optional<std::vector<PathStep>> steps = ParsePath(change.path);
  if (!steps) {
    throw InputError(what + ": \"" + change.path +
                     "\" is not a field path (names joined by '.', list indices in [])");
  }
  return std::move(*steps);
}

bool SameStep(const PathStep& a, const PathStep& b) {
  return a.name == b.name && (!a.name.empty() || a.index == b.index);
}

}  // namespace

void CheckFieldChanges(const nlohmann::json& source, const std::vector<FieldChange>& changes,
                       const std::string& what) {
  std::vector<std::vector<PathStep>> paths;
  for (const FieldChange& change : changes) {
    // Named as ApplyFieldChange names it from VariantSource.
    const std::string where = what + ": " + change.path;
    const std::vector<PathStep> steps = StepsOf(change, where);
    const std::string named = where + ": \"" + change.path + "\" ";
    if (steps.back().name.empty() && change.value.is_null()) {
      throw InputError(named + "cannot remove an element of a list");
    }
    // The latest earlier change whose path leads to or into this one decides where the walk
    // starts: its value (what the case holds there once it applied), else the source.
    const nlohmann::json* node = &source;
    size_t first = 0;
    for (size_t k = paths.size(); k-- > 0;) {
      const std::vector<PathStep>& earlier = paths[k];
      if (earlier.size() > steps.size() ||
          !std::equal(earlier.begin(), earlier.end(), steps.begin(), SameStep)) {
        continue;
      }
      node = &changes[k].value;
      first = earlier.size();
      // That change removed the field (null): a path into it walks into nothing.
      if (node->is_null() && first < steps.size()) {
        throw InputError(named + "names \"" + earlier.back().name + "\", which is absent");
      }
      break;
    }
    for (size_t i = first; i < steps.size(); ++i) {
      const PathStep& step = steps[i];
      const bool last = i + 1 == steps.size();
      if (step.name.empty()) {
        if (!node->is_array() || step.index >= node->size()) {
          throw InputError(named + "indexes past the end of a list or into something else");
        }
        node = &(*node)[step.index];
      } else {
        if (!node->is_object()) throw InputError(named + "leads into something that has no fields");
        if (last) break;
        if (!node->contains(step.name)) {
          throw InputError(named + "names \"" + step.name + "\", which is absent");
        }
        node = &(*node)[step.name];
      }
    }
    paths.push_back(steps);
  }
}

void ApplyFieldChange(nlohmann::json* source, const FieldChange& change, const std::string& what) {
  const std::vector<PathStep> steps = StepsOf(change, what);
  const std::string named = what + ": \"" + change.path + "\" ";
  nlohmann::json* node = source;
  for (size_t i = 0; i < steps.size(); ++i) {
    const PathStep& step = steps[i];
    const bool last = i + 1 == steps.size();
    if (step.name.empty()) {
      if (!node->is_array() || step.index >= node->size()) {
        throw InputError(named + "indexes past the end of a list or into something else");
      }
      if (last && change.value.is_null()) {
        throw InputError(named + "cannot remove an element of a list");
      }
      node = &(*node)[step.index];
    } else {
      if (!node->is_object()) throw InputError(named + "leads into something that has no fields");
      const bool has = node->contains(step.name);
      if (!last && !has) throw InputError(named + "names \"" + step.name + "\", which is absent");
      if (last && change.value.is_null()) {
        node->erase(step.name);
        return;
      }
      node = &(*node)[step.name];
    }
  }
  *node = change.value;
}

nlohmann::json NumberJson(double value) {
  const bool whole = std::floor(value) == value && std::fabs(value) < 1e15;
  return whole ? nlohmann::json(static_cast<long long>(value)) : nlohmann::json(value);
}

nlohmann::json FieldAt(const nlohmann::json& source, const std::string& path) {
  const std::optional<std::vector<PathStep>> steps = ParsePath(path);
  if (!steps) return nullptr;
  const nlohmann::json* node = &source;
  for (const PathStep& step : *steps) {
    if (step.name.empty()) {
      if (!node->is_array() || step.index >= node->size()) return nullptr;
      node = &(*node)[step.index];
    } else {
      if (!node->is_object() || !node->contains(step.name)) return nullptr;
      node = &(*node)[step.name];
    }
  }
  return *node;
}

bool IsManifest(const nlohmann::json& document) {
  return document.is_object() && document.contains("manifest");
}

CaseManifest ParseManifest(const nlohmann::json& document, const std::string& path) {
  return ParseManifest(document, path,
                       [](const std::string& base_path) { return ReadJsonFile(base_path); });
}

CaseManifest ParseManifest(const nlohmann::json& document, const std::string& path,
                           const std::function<nlohmann::json(const std::string&)>& read_base) {
  CaseManifest manifest;
  manifest.path = path;
  try {
    InputFields fields(document, "manifest");
    fields.RequiredString("manifest");
    const std::string base = fields.RequiredString("base");
    const std::filesystem::path folder = std::filesystem::absolute(path).parent_path();
    manifest.base_path = (folder / base).lexically_normal().string();
    if (base.find('#') != std::string::npos) {
      fields.Fail("base", "must be a case file, not a member of a manifest");
    }
    const bool has_variants = fields.Has("variants");
    const bool has_grid = fields.Has("parameters");
    if (has_variants == has_grid) {
      fields.Fail(has_variants ? "parameters" : "variants",
                  "give exactly one of \"variants\" and \"parameters\"");
    }
    if (has_variants) {
      const nlohmann::json& list = fields.RequiredValue("variants");
      if (!list.is_array() || list.empty()) fields.Fail("variants", "expected a non-empty list");
      for (size_t k = 0; k < list.size(); ++k) {
        InputFields variant(list[k], "manifest.variants[" + std::to_string(k) + "]");
        CaseVariant member{variant.RequiredString("name"), {}};
        if (variant.Has("set")) {
          const nlohmann::json& set = variant.RequiredValue("set");
          if (!set.is_object()) variant.Fail("set", "expected an object of path: value");
          for (const auto& [field, value] : set.items()) member.changes.push_back({field, value});
        }
        variant.Finish();
        manifest.variants.push_back(std::move(member));
      }
    } else {
      const nlohmann::json& axes = fields.RequiredValue("parameters");
      if (!axes.is_array() || axes.empty()) fields.Fail("parameters", "expected a non-empty list");
      std::vector<std::pair<std::string, std::vector<double>>> grid;
      size_t runs = 1;
      for (size_t i = 0; i < axes.size(); ++i) {
        InputFields axis(axes[i], "manifest.parameters[" + std::to_string(i) + "]");
        if (!axis.Has("values")) axis.Fail("values", "missing (required)");
        grid.emplace_back(axis.RequiredString("path"), axis.OptionalNumberList("values"));
        axis.Finish();
        if (grid.back().second.empty()) axis.Fail("values", "expected at least one value");
        runs *= grid.back().second.size();
        // A study of thousands of named cases belongs to `nfrc sweep --range`, not a file.
        if (runs > 10000) axis.Fail("values", "the grid has more than 10000 points");
      }
      std::vector<std::string> names;
      if (fields.Has("names")) {
        const nlohmann::json& list = fields.RequiredValue("names");
        if (!list.is_array() || list.size() != runs) {
          fields.Fail("names", "expected one name per grid point (" + std::to_string(runs) + ")");
        }
        for (const nlohmann::json& name : list) {
          if (!name.is_string()) fields.Fail("names", "expected strings");
          names.push_back(name.get<std::string>());
        }
      }
      for (size_t k = 0; k < runs; ++k) {
        CaseVariant member{names.empty() ? std::to_string(k) : names[k], {}};
        size_t rest = k;  // row-major: the last axis varies fastest
        std::vector<FieldChange> changes(grid.size());
        for (size_t i = grid.size(); i-- > 0;) {
          const std::vector<double>& values = grid[i].second;
          const double value = values[rest % values.size()];
          rest /= values.size();
          changes[i] = {grid[i].first, NumberJson(value)};
        }
        member.changes = std::move(changes);
        manifest.variants.push_back(std::move(member));
      }
    }
    fields.Finish();
    std::unordered_set<std::string> names;  // not pairwise: quadratic in the members
    for (size_t k = 0; k < manifest.variants.size(); ++k) {
      const std::string& name = manifest.variants[k].name;
      if (name.empty() || name.find('#') != std::string::npos) {
        throw InputError("manifest.variants[" + std::to_string(k) +
                         "].name: must be non-empty, without #");
      }
      if (!names.insert(name).second) {
        throw InputError("manifest.variants: the name \"" + name + "\" is given twice");
      }
    }
  } catch (const InputError& error) {
    throw InputError(path + ": " + error.what());
  }
  try {
    manifest.base = read_base(manifest.base_path);
  } catch (const InputError& error) {
    throw InputError(path + ": manifest.base: " + error.what());
  }
  if (IsManifest(manifest.base)) {
    throw InputError(path + ": manifest.base: " + manifest.base_path +
                     " is a manifest, not a case file");
  }
  // Every variant's paths checked against the base without building any (a copy of the base
  // per member made a grid of 10 000 members take minutes); a member is built when it is run.
  for (const CaseVariant& variant : manifest.variants) {
    CheckFieldChanges(manifest.base, variant.changes,
                      manifest.path + ": variant \"" + variant.name + "\": set");
  }
  return manifest;
}

CaseManifest ReadManifest(const std::string& path) {
  const nlohmann::json document = ReadJsonFile(path);
  if (!IsManifest(document)) {
    throw InputError(path + ": manifest: absent (this is a case file, not a manifest)");
  }
  return ParseManifest(document, path);
}

std::string MemberNames(const CaseManifest& manifest) {
  std::string names;
  for (const CaseVariant& variant : manifest.variants) {
    names += (names.empty() ? "" : ", ") + variant.name;
  }
  return names;
}

size_t FindVariant(const CaseManifest& manifest, const std::string& member) {
  for (size_t k = 0; k < manifest.variants.size(); ++k) {
    if (manifest.variants[k].name == member) return k;
  }
  const bool index = !member.empty() && member.size() < 9 &&
                     member.find_first_not_of("0123456789") == std::string::npos;
  if (index && std::stoul(member) < manifest.variants.size()) return std::stoul(member);
  throw InputError(manifest.path + ": manifest.variants: no member \"" + member +
                   "\" (the members are " + MemberNames(manifest) + ")");
}

nlohmann::json VariantSource(const CaseManifest& manifest, size_t index) {
  const CaseVariant& variant = manifest.variants.at(index);
  nlohmann::json source = manifest.base;
  std::string title = source.is_object() ? source.value("title", std::string()) : std::string();
  std::string changed;
  bool titled = false;
  for (const FieldChange& change : variant.changes) {
    ApplyFieldChange(&source, change,
                     manifest.path + ": variant \"" + variant.name + "\": set: " + change.path);
    titled = titled || change.path == "title";
    changed += (changed.empty() ? "" : ", ") + change.path + " = " + Describe(change.value);
  }
  if (!titled && source.is_object()) {
    source["title"] = title + (title.empty() ? "" : " ") + "[" + variant.name +
                      (changed.empty() ? "" : ": " + changed) + "]";
  }
  return source;
}

}  // namespace nfrc
