#include "tools/command_line.h"

#include <doctest/doctest.h>

namespace nfrc {
namespace {

// The options of `nfrc refine` and `nfrc validate` together, as the CLI declares them.
const std::vector<OptionSpec> kSpecs = {
    OptionSpec::Value("--out"),     OptionSpec::Value("--omega"),   OptionSpec::Value("--steps"),
    OptionSpec::Value("--start"),   OptionSpec::Value("--measure"), OptionSpec::Value("--epsilons"),
    OptionSpec::Flag("--no-chirp"),
};

CommandLine Parse(const std::vector<std::string>& args) {
  return CommandLine("validate", args, kSpecs);
}

// The message of the UsageError that `action` throws, or "" if it throws none.
template <typename Action>
std::string UsageMessage(Action action) {
  try {
    action();
  } catch (const UsageError& error) {
    return error.what();
  }
  return "";
}

TEST_CASE("CommandLine reads options, values, flags and positionals") {
  const CommandLine line = Parse({"case.json", "--out", "dir", "--omega=1.5", "--no-chirp"});
  CHECK(line.positionals() == std::vector<std::string>{"case.json"});
  CHECK(line.Value("--out") == "dir");
  CHECK(line.Number("--omega") == 1.5);
  CHECK(line.Flag("--no-chirp"));
  CHECK_FALSE(line.Value("--start").has_value());
  CHECK_FALSE(line.Int("--steps", 1, 100).has_value());
  CHECK(line.NumberList("--epsilons").empty());
}

TEST_CASE("CommandLine: an option without its value says missing value, not unknown option") {
  CHECK(UsageMessage([] {
          Parse({"case.json", "--out"});
        }) == "nfrc validate: --out: missing value");
  CHECK(UsageMessage([] {
          Parse({"--out", "--omega", "1"});
        }) == "nfrc validate: --out: missing value");
  CHECK(UsageMessage([] { Parse({"--out="}); }) == "nfrc validate: --out: missing value");
}

TEST_CASE("CommandLine: unknown, repeated and misused options are usage errors") {
  CHECK(UsageMessage([] { Parse({"--outt", "dir"}); }) == "nfrc validate: unknown option --outt");
  CHECK(UsageMessage([] { Parse({"-x"}); }) == "nfrc validate: unknown option -x");
  CHECK(UsageMessage([] {
          Parse({"--out", "a", "--out", "b"});
        }) == "nfrc validate: --out: given more than once");
  CHECK(UsageMessage([] {
          Parse({"--no-chirp", "--no-chirp"});
        }) == "nfrc validate: --no-chirp: given more than once");
  CHECK(UsageMessage([] { Parse({"--no-chirp=yes"}); }) ==
        "nfrc validate: --no-chirp: takes no value");
}

TEST_CASE("CommandLine: a Repeated option may be given again, and options() keeps the order") {
  const std::vector<OptionSpec> specs = {OptionSpec::Repeated("--parameter"),
                                         OptionSpec::Repeated("--values"),
                                         OptionSpec::Value("--out"), OptionSpec::Flag("--quiet")};
  const CommandLine line("sweep",
                         {"case.json", "--parameter", "a", "--values=1,2", "--out", "dir",
                          "--parameter", "b", "--values", "3", "--quiet"},
                         specs);
  std::vector<std::string> seen;
  for (const GivenOption& option : line.options()) seen.push_back(option.name + " " + option.value);
  CHECK(seen == std::vector<std::string>{"--parameter a", "--values 1,2", "--out dir",
                                         "--parameter b", "--values 3", "--quiet "});
  CHECK(line.positionals() == std::vector<std::string>{"case.json"});
  CHECK(line.Value("--out") == "dir");
  CHECK(line.ParseNumberList("--values", "1,2") == std::vector<double>{1.0, 2.0});
  CHECK(line.ParseRange("--range", "0:1:3", 10) == std::vector<double>{0.0, 0.5, 1.0});
  CHECK(UsageMessage([&] { line.ParseRange("--range", "0:1", 10); }) ==
        "nfrc sweep: --range: expected FROM:TO:COUNT, got \"0:1\"");
  // Only the Repeated ones: the others are still refused twice.
  CHECK(UsageMessage([&] {
          CommandLine("sweep", {"--out", "a", "--out", "b"}, specs);
        }) == "nfrc sweep: --out: given more than once");
  CHECK(UsageMessage([&] { CommandLine("sweep", {"--parameter"}, specs); }) ==
        "nfrc sweep: --parameter: missing value");
  // The one-value getters cannot pick one of several values.
  CHECK_THROWS_AS(line.Value("--parameter"), std::logic_error);
}

TEST_CASE("CommandLine: a value may start with one dash, and -- ends the options") {
  const CommandLine line = Parse({"--omega", "-2.5", "--", "--out", "-"});
  CHECK(line.Number("--omega") == -2.5);
  CHECK(line.positionals() == std::vector<std::string>{"--out", "-"});
  CHECK_FALSE(line.Value("--out").has_value());
  CHECK(Parse({"--out=--odd"}).Value("--out") == "--odd");
}

TEST_CASE("CommandLine: a malformed number is a usage error naming the option") {
  CHECK(UsageMessage([] {
          Parse({"--omega", "abc"}).Number("--omega");
        }) == "nfrc validate: --omega: not a number: \"abc\"");
  CHECK(UsageMessage([] {
          Parse({"--omega", "1.5x"}).Number("--omega");
        }) == "nfrc validate: --omega: not a number: \"1.5x\"");
  CHECK(UsageMessage([] {
          Parse({"--omega", " 1"}).Number("--omega");
        }) == "nfrc validate: --omega: not a number: \" 1\"");
}

TEST_CASE("CommandLine: numbers must be finite") {
  for (const char* text : {"nan", "inf", "-inf", "infinity", "NaN"}) {
    CAPTURE(text);
    CHECK(UsageMessage([&] {
            Parse({"--omega", text}).Number("--omega");
          }) == std::string("nfrc validate: --omega: not a finite number: \"") + text + "\"");
  }
  CHECK(UsageMessage([] {
          Parse({"--omega", "1e999"}).Number("--omega");
        }).find("--omega: not a finite number (beyond double range)") != std::string::npos);
  CHECK(Parse({"--omega", "1e300"}).Number("--omega") == 1e300);
}

TEST_CASE("CommandLine: a positive number rejects zero and negatives") {
  CHECK(Parse({"--omega", "0.5"}).Number("--omega", NumberDomain::kPositive) == 0.5);
  CHECK(UsageMessage([] {
          Parse({"--omega", "0"}).Number("--omega", NumberDomain::kPositive);
        }) == "nfrc validate: --omega: must be > 0, got \"0\"");
  CHECK(UsageMessage([] {
          Parse({"--omega", "-1"}).Number("--omega", NumberDomain::kPositive);
        }) == "nfrc validate: --omega: must be > 0, got \"-1\"");
}

TEST_CASE("CommandLine: integers are parsed exactly, never overflow, and name the range") {
  CHECK(Parse({"--steps", "15"}).Int("--steps", 1, 1000) == 15);
  CHECK(Parse({"--steps", "-3"}).Int("--steps", -5, 5) == -3);
  CHECK(UsageMessage([] {
          Parse({"--steps", "1e20"}).Int("--steps", 1, 1000);
        }) == "nfrc validate: --steps: expected an integer in [1, 1000], got \"1e20\"");
  CHECK(UsageMessage([] {
          Parse({"--steps", "2.5"}).Int("--steps", 1, 1000);
        }) == "nfrc validate: --steps: expected an integer in [1, 1000], got \"2.5\"");
  CHECK(UsageMessage([] {
          Parse({"--steps", "+3"}).Int("--steps", 1, 1000);
        }) == "nfrc validate: --steps: expected an integer in [1, 1000], got \"+3\"");
  CHECK(UsageMessage([] {
          Parse({"--steps", "100000000000000000000"}).Int("--steps", 1, 1000);
        }) == "nfrc validate: --steps: out of range [1, 1000]: \"100000000000000000000\"");
  CHECK(UsageMessage([] {
          Parse({"--steps", "4294967297"}).Int("--steps", 1, 1000);
        }) == "nfrc validate: --steps: out of range [1, 1000]: \"4294967297\"");
  CHECK(UsageMessage([] {
          Parse({"--steps", "0"}).Int("--steps", 1, 1000);
        }) == "nfrc validate: --steps: out of range [1, 1000]: \"0\"");
}

TEST_CASE("CommandLine: number lists") {
  CHECK(Parse({"--omega", "1,2.5,3e2"}).NumberList("--omega") == std::vector<double>{1, 2.5, 300});
  CHECK(Parse({"--omega", "7"}).NumberList("--omega") == std::vector<double>{7});
  CHECK(UsageMessage([] {
          Parse({"--epsilons", "1e9,abc"}).NumberList("--epsilons");
        }) == "nfrc validate: --epsilons: not a number: \"abc\"");
  CHECK(UsageMessage([] {
          Parse({"--omega", "1,,2"}).NumberList("--omega");
        }) == "nfrc validate: --omega: empty item in list \"1,,2\"");
  CHECK(UsageMessage([] {
          Parse({"--omega", "1,2,"}).NumberList("--omega");
        }) == "nfrc validate: --omega: empty item in list \"1,2,\"");
  CHECK(UsageMessage([] {
          Parse({"--omega", "1,inf"}).NumberList("--omega");
        }) == "nfrc validate: --omega: not a finite number: \"inf\"");
  CHECK(UsageMessage([] {
          Parse({"--omega", "1,-2"}).NumberList("--omega", NumberDomain::kPositive);
        }) == "nfrc validate: --omega: must be > 0, got \"-2\"");
}

TEST_CASE("CommandLine: choices") {
  const std::vector<std::string> starts = {"hbm", "rest"};
  CHECK(Parse({"--start", "rest"}).Choice("--start", starts) == "rest");
  CHECK(UsageMessage([&] {
          Parse({"--start", "sideways"}).Choice("--start", starts);
        }) == "nfrc validate: --start: expected one of hbm|rest, got \"sideways\"");
  const std::vector<std::string> measures = {"max_abs", "min", "max", "h1", "energy"};
  CHECK(Parse({"--measure", "h1"}).Choice("--measure", measures) == "h1");
  CHECK(UsageMessage([&] {
          Parse({"--measure", "H1"}).Choice("--measure", measures);
        }) == "nfrc validate: --measure: expected one of max_abs|min|max|h1|energy, got \"H1\"");
}

TEST_CASE("CommandLine: Error prefixes the command, and undeclared getters are logic errors") {
  const CommandLine line = Parse({});
  CHECK(std::string(line.Error("needs a case file and --out DIR").what()) ==
        "nfrc validate: needs a case file and --out DIR");
  CHECK_THROWS_AS(line.Value("--nope"), std::logic_error);
  CHECK_THROWS_AS(line.Flag("--out"), std::logic_error);
  CHECK_THROWS_AS(line.Value("--no-chirp"), std::logic_error);
}

}  // namespace
}  // namespace nfrc
