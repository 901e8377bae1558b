#include "tools/command_line.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

namespace nfrc {
namespace {

std::string Quoted(const std::string& text) { return "\"" + text + "\""; }

}  // namespace

CommandLine::CommandLine(std::string command, const std::vector<std::string>& args,
                         const std::vector<OptionSpec>& specs)
    : command_(std::move(command)), specs_(specs) {
  bool options_ended = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (options_ended || arg == "-" || arg.empty() || arg[0] != '-') {
      positionals_.push_back(arg);
      continue;
    }
    if (arg == "--") {
      options_ended = true;
      continue;
    }
    const size_t equals = arg.find('=');
    const std::string name = arg.substr(0, equals);
    const auto spec = std::find_if(specs_.begin(), specs_.end(),
                                   [&](const OptionSpec& s) { return s.name == name; });
    if (spec == specs_.end()) throw Error("unknown option " + name);
    if (values_.count(name) && !spec->repeatable) throw Error(name + ": given more than once");
    std::string value;
    if (!spec->takes_value) {
      if (equals != std::string::npos) throw Error(name + ": takes no value");
    } else if (equals != std::string::npos) {
      value = arg.substr(equals + 1);
    } else if (i + 1 < args.size() && args[i + 1].rfind("--", 0) != 0) {
      value = args[++i];
    }
    if (spec->takes_value && value.empty()) throw Error(name + ": missing value");
    values_[name] = value;
    options_.push_back({name, value});
  }
}

UsageError CommandLine::Error(const std::string& message) const {
  return UsageError("nfrc " + command_ + ": " + message);
}

const OptionSpec& CommandLine::Spec(const std::string& name) const {
  for (const OptionSpec& spec : specs_) {
    if (spec.name == name && spec.repeatable) {
      throw std::logic_error(name + " may be repeated: read it from options()");
    }
    if (spec.name == name) return spec;
  }
  throw std::logic_error("nfrc " + command_ + ": option " + name + " was not declared");
}

bool CommandLine::Flag(const std::string& name) const {
  if (Spec(name).takes_value) throw std::logic_error(name + " takes a value, not a flag");
  return values_.count(name) > 0;
}

std::optional<std::string> CommandLine::Value(const std::string& name) const {
  if (!Spec(name).takes_value) throw std::logic_error(name + " is a flag, not a value");
  const auto found = values_.find(name);
  if (found == values_.end()) return std::nullopt;
  return found->second;
}

double CommandLine::ParseNumber(const std::string& name, const std::string& text,
                                NumberDomain domain) const {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (error == std::errc::result_out_of_range) {
    throw Error(name + ": not a finite number (beyond double range): " + Quoted(text));
  }
  if (error != std::errc() || stop != end) throw Error(name + ": not a number: " + Quoted(text));
  if (!std::isfinite(value)) throw Error(name + ": not a finite number: " + Quoted(text));
  if (domain == NumberDomain::kPositive && !(value > 0.0)) {
    throw Error(name + ": must be > 0, got " + Quoted(text));
  }
  return value;
}

std::optional<double> CommandLine::Number(const std::string& name, NumberDomain domain) const {
  const std::optional<std::string> text = Value(name);
  if (!text) return std::nullopt;
  return ParseNumber(name, *text, domain);
}

int CommandLine::ParseInt(const std::string& name, const std::string& text, int min,
                          int max) const {
  // Parsed as long long so that a huge value is reported as out of range, not as garbage.
  long long value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  std::string range = "[";  // appended piecewise: GCC 12's -Wrestrict misfires on "[" + string
  range += std::to_string(min) + ", " + std::to_string(max) + "]";
  if ((error != std::errc() && error != std::errc::result_out_of_range) || stop != end) {
    throw Error(name + ": expected an integer in " + range + ", got " + Quoted(text));
  }
  if (error == std::errc::result_out_of_range || value < min || value > max) {
    throw Error(name + ": out of range " + range + ": " + Quoted(text));
  }
  return static_cast<int>(value);
}

std::optional<int> CommandLine::Int(const std::string& name, int min, int max) const {
  const std::optional<std::string> text = Value(name);
  if (!text) return std::nullopt;
  return ParseInt(name, *text, min, max);
}

std::vector<double> CommandLine::Range(const std::string& name, int max_count) const {
  const std::optional<std::string> text = Value(name);
  if (!text) return {};
  return ParseRange(name, *text, max_count);
}

std::vector<double> CommandLine::ParseRange(const std::string& name, const std::string& text,
                                            int max_count) const {
  const size_t first = text.find(':');
  const size_t second = first == std::string::npos ? first : text.find(':', first + 1);
  if (second == std::string::npos)
    throw Error(name + ": expected FROM:TO:COUNT, got " + Quoted(text));
  const double from = ParseNumber(name, text.substr(0, first), NumberDomain::kFinite);
  const double to =
      ParseNumber(name, text.substr(first + 1, second - first - 1), NumberDomain::kFinite);
  const int count = ParseInt(name, text.substr(second + 1), 2, max_count);
  std::vector<double> values;
  for (int k = 0; k < count; ++k) values.push_back(from + (to - from) * k / (count - 1));
  return values;
}

std::vector<double> CommandLine::NumberList(const std::string& name, NumberDomain domain) const {
  const std::optional<std::string> text = Value(name);
  if (!text) return {};
  return ParseNumberList(name, *text, domain);
}

std::vector<double> CommandLine::ParseNumberList(const std::string& name, const std::string& text,
                                                 NumberDomain domain) const {
  std::vector<double> list;
  // Every item between commas must be a number: "1,,2" and "1,2," are errors.
  size_t begin = 0;
  while (true) {
    const size_t comma = text.find(',', begin);
    const std::string item = text.substr(begin, comma - begin);
    if (item.empty()) throw Error(name + ": empty item in list " + Quoted(text));
    list.push_back(ParseNumber(name, item, domain));
    if (comma == std::string::npos) return list;
    begin = comma + 1;
  }
}

std::optional<std::string> CommandLine::Choice(const std::string& name,
                                               const std::vector<std::string>& allowed) const {
  const std::optional<std::string> text = Value(name);
  if (!text) return std::nullopt;
  if (std::find(allowed.begin(), allowed.end(), *text) != allowed.end()) return text;
  std::string options;
  for (const std::string& choice : allowed) options += (options.empty() ? "" : "|") + choice;
  throw Error(name + ": expected one of " + options + ", got " + Quoted(*text));
}

}  // namespace nfrc
