// JSON input files (the camera and lights sidecars) as read here: regular files only (mesh/input_file.h), parsed
// by nlohmann::json, with errors that name file:line. nlohmann::json keeps no positions, so a key's line is found
// in the text: the first time it is written at or after a given byte (an entry's own "type", say).
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

namespace pb {

struct JsonInput {
  std::string path, text;
  nlohmann::json json;

  // The line where "key" is first written at or after byte `from`; 0 when it is not.
  int LineOfKey(const std::string& key, size_t from = 0) const;
  // The byte at which the n-th (from 0) writing of "key" starts; npos when there are fewer.
  size_t NthKey(const std::string& key, size_t n) const;
};

// InputError "path:line: error: malformed JSON" (or naming `what` when the file cannot be read).
JsonInput ReadJsonInput(const std::string& path, const std::string& what);

// The line of `json` on which its arrays and objects first nest deeper than `most` (brackets inside strings
// skipped), or 0 where they never do. For readers that recurse (tinygltf's overflows its stack at 100,000 levels);
// this scan does not.
int LineNestedDeeperThan(std::string_view json, size_t most);

// Coordinates beyond this [m] are refused: float keeps their metres only to within 60 m, and lengths built from
// them would overflow.
inline constexpr double kMaxJsonCoordinate = 1e9;

// Member `key` of `j` as three finite numbers within kMaxJsonCoordinate, in double; with `unit`, a direction,
// normalised (any non-zero length is accepted; zero gives (0, 0, 0)). `owner` names j in messages ("camera",
// "light 2"); `from` is where j is written in the text, for the line.
std::array<double, 3> ReadTriple(const JsonInput& in, const nlohmann::json& j, const std::string& key,
                                 const std::string& owner, size_t from = 0, bool unit = false);

}  // namespace pb
