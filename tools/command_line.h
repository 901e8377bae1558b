#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace nfrc {

// The command line is malformed: an unknown or repeated option, a missing value, a value that
// is not a number, an integer out of range, a choice not offered. The message starts with
// "nfrc <command>: " and names the option. The CLI maps it to exit 2 (bad command line) and
// prints the usage after it.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An option a subcommand accepts, named with its dashes ("--out").
struct OptionSpec {
  std::string name;
  bool takes_value = true;
  bool repeatable = false;  // may be given more than once

  // `--name VALUE` or `--name=VALUE`.
  static OptionSpec Value(std::string name) { return {std::move(name), true, false}; }
  // `--name` alone.
  static OptionSpec Flag(std::string name) { return {std::move(name), false, false}; }
  // `--name VALUE`, any number of times: read with CommandLine::options() (in order), not with
  // the getters, which take one value.
  static OptionSpec Repeated(std::string name) { return {std::move(name), true, true}; }
};

// An option as given on the command line; flags have an empty value.
struct GivenOption {
  std::string name;
  std::string value;
};

// Which numbers an option accepts; every number must be finite.
enum class NumberDomain { kFinite, kPositive };

// The arguments of one subcommand, parsed against the options it accepts. The constructor
// reads every argument, so unknown options, missing values and repeated options are reported
// before any work starts; the typed getters then check each value, naming the option. An
// argument starting with "--" never serves as a value (so `--out --omega 1` is "--out: missing
// value"); write `--out=--odd-name` for such a value. A lone "-" is a positional argument and
// "--" ends the options. Getters for an option not in the specs, or for a Repeated one, throw
// std::logic_error.
class CommandLine {
 public:
  // `command` is how messages name the subcommand ("run" gives "nfrc run: ...").
  CommandLine(std::string command, const std::vector<std::string>& args,
              const std::vector<OptionSpec>& specs);

  // The arguments that are not options or their values, in order.
  const std::vector<std::string>& positionals() const { return positionals_; }
  // Every option given, in command-line order (for options whose meaning depends on their
  // neighbours, such as `nfrc sweep`'s --parameter followed by its --values).
  const std::vector<GivenOption>& options() const { return options_; }

  // True if the flag was given.
  bool Flag(const std::string& name) const;
  // The value as given; nullopt if the option is absent.
  std::optional<std::string> Value(const std::string& name) const;
  // A finite number in `domain`; nullopt if absent.
  std::optional<double> Number(const std::string& name,
                               NumberDomain domain = NumberDomain::kFinite) const;
  // An integer (decimal digits, optional minus sign) in [min, max]; nullopt if absent.
  std::optional<int> Int(const std::string& name, int min, int max) const;
  // FROM:TO:COUNT as COUNT (2 to max_count) evenly spaced numbers, both ends included;
  // empty if absent.
  std::vector<double> Range(const std::string& name, int max_count) const;
  // Comma-separated numbers ("1,2.5,3"), each finite and in `domain`; empty if absent.
  std::vector<double> NumberList(const std::string& name,
                                 NumberDomain domain = NumberDomain::kFinite) const;
  // The parsers of Range and NumberList, for a value taken from options(): `name` is the
  // option that messages name.
  std::vector<double> ParseRange(const std::string& name, const std::string& text,
                                 int max_count) const;
  std::vector<double> ParseNumberList(const std::string& name, const std::string& text,
                                      NumberDomain domain = NumberDomain::kFinite) const;
  // One of `allowed`; nullopt if absent.
  std::optional<std::string> Choice(const std::string& name,
                                    const std::vector<std::string>& allowed) const;

  // A UsageError with this command's prefix, for checks the caller makes (e.g. "needs a case
  // file and --out DIR").
  UsageError Error(const std::string& message) const;

 private:
  const OptionSpec& Spec(const std::string& name) const;
  double ParseNumber(const std::string& name, const std::string& text, NumberDomain domain) const;
  int ParseInt(const std::string& name, const std::string& text, int min, int max) const;

  std::string command_;
  std::vector<OptionSpec> specs_;
  std::map<std::string, std::string> values_;  // given options; flags map to ""
  std::vector<GivenOption> options_;           // the same, in order, repeats included
  std::vector<std::string> positionals_;
};

}  // namespace nfrc
