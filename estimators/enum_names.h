// Names of the small enums the command line takes (kernels, estimators): parse a name, list all names.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace pb {

template <typename Enum, size_t N>
std::optional<Enum> ParseName(std::string_view name, const std::array<Enum, N>& all, std::string (*nameOf)(Enum)) {
  for (Enum e : all)
    if (name == nameOf(e)) return e;
  return std::nullopt;
}

// "a, b, c", for --help and error messages.
template <typename Enum, size_t N>
std::string JoinNames(const std::array<Enum, N>& all, std::string (*nameOf)(Enum)) {
  std::string names;
  for (Enum e : all) names += (names.empty() ? "" : ", ") + nameOf(e);
  return names;
}

}  // namespace pb
