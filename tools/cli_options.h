// Command-line helpers shared by the tools (bake, render): options that take one of a fixed set of names, and
// the common exit-status contract: 0 on success, 1 for bad input (InputError, message names file:line) or any
// other failure (out of memory, a library's exception: caught, so that no temporary output is left), 2 for a bad
// command line (CLI11's message).
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <optional>
#include <string>
#include <string_view>

#include "baker/runtime/progress.h"
#include "mesh/errors.h"

namespace pb::tools {

// An option that takes one of a fixed set of names; anything else is refused with the list of valid names.
template <typename Enum>
void AddNamedOption(CLI::App& app, const std::string& flag, Enum& target, std::optional<Enum> (*parse)(std::string_view),
                    std::string (*name)(Enum), const std::string& names, const std::string& noun,
                    const std::string& help) {
  const auto valid = [=](const std::string& text) {
    return parse(text) ? std::string() : "unknown " + noun + " '" + text + "'; choose one of: " + names;
  };
  app.add_option_function<std::string>(flag, [&target, parse](const std::string& text) { target = *parse(text); },
                                        help + ": " + names)
      ->check(CLI::Validator(valid, "NAME", "name"))
      ->default_str(name(target));
}

// "8x16" -> (8, 16); CLI11 refuses anything else before the run starts.
inline bool ParsePair(const std::string& text, int& a, int& b) {
  const size_t x = text.find('x');
  if (x == std::string::npos) return false;
  try {
    size_t endA = 0, endB = 0;
    a = std::stoi(text.substr(0, x), &endA);
    b = std::stoi(text.substr(x + 1), &endB);
    return endA == x && endB == text.size() - x - 1 && a > 0 && b > 0;
  } catch (const std::exception&) {
    return false;
  }
}

inline void AddPairOption(CLI::App& app, const std::string& flag, int& a, int& b, const std::string& help) {
  app.add_option_function<std::string>(flag, [&a, &b](const std::string& text) { ParsePair(text, a, b); }, help)
      ->check(CLI::Validator(
          [](const std::string& text) {
            int x = 0, y = 0;
            return ParsePair(text, x, y) ? std::string() : "expects AxB with whole numbers > 0, e.g. 8x16";
          },
          "AxB", "pair"))
      ->default_str(std::to_string(a) + "x" + std::to_string(b));
}

// A random seed: a whole number in [0, 2^64 - 1], in decimal. CLI11 alone would read -1 and 2^64 alike as 2^64 - 1,
// so that two seeds the user told apart gave the same bytes.
inline bool ParseSeed(const std::string& text, uint64_t& seed) {
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, seed);
  return !text.empty() && error == std::errc() && stop == end;
}

inline void AddSeedOption(CLI::App& app, uint64_t& seed, const std::string& help) {
  app.add_option_function<std::string>("--seed", [&seed](const std::string& text) { ParseSeed(text, seed); }, help)
      ->check(CLI::Validator(
          [](const std::string& text) {
            uint64_t value = 0;
            return ParseSeed(text, value) ? std::string() : "expects a whole number from 0 to 18446744073709551615";
          },
          "", "seed"))
      ->type_name("UINT")
      ->default_str(std::to_string(seed));
}

// Parses the command line, checks the options' ranges with `validate` (an InputError there is a bad command line,
// exit 2), and runs `work`, mapping errors to the exit statuses above.
template <typename Validate, typename Work>
int RunTool(CLI::App& app, int argc, char** argv, Validate&& validate, Work&& work) {
  app.get_formatter()->column_width(24);
  app.set_version_flag("--version", "photonbake " PB_VERSION, "print the version and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    validate();
  } catch (const InputError& e) {
    fmt::print(stderr, "{}\n", TerminalSafe(e.what()));
    return 2;
  }
  try {
    work();
    return 0;
  } catch (const InputError& e) {
    fmt::print(stderr, "{}\n", TerminalSafe(e.what()));
    return 1;
  } catch (const std::bad_alloc&) {  // caught, so that the outputs' temporaries are removed as the stack unwinds
    fmt::print(stderr, "error: out of memory; nothing was written\n");
    return 1;
  } catch (const std::exception& e) {  // a library's own exception that no stage turned into an InputError
    fmt::print(stderr, "error: {}\n", TerminalSafe(e.what()));
    return 1;
  }
}

// A length, count or factor as a double: "1e300" is +inf and "1e-400" 0, never an exception; the option's own
// range check then refuses it. Malformed text is refused by the option's validator before this runs.
inline double ParseNumber(const std::string& text) { return std::strtod(text.c_str(), nullptr); }

}  // namespace pb::tools
