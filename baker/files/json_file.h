// JSON reports (--report) staged as outputs: two-space indented, and never fatal on text from scene files. A name
// in any encoding (a Latin-1 material name from a 3ds Max export) has its invalid UTF-8 replaced by U+FFFD.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "baker/files/atomic_file.h"

namespace pb {

// `text` with every byte that is not part of valid UTF-8 replaced by U+FFFD (nlohmann::json's own replacement).
inline std::string ValidUtf8(const std::string& text) {
  const std::string quoted = nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return nlohmann::json::parse(quoted).get<std::string>();
}

inline void WriteJsonFile(OutputFiles& outputs, const std::string& path, const nlohmann::json& j) {
  const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  outputs.Write(path, [&](std::ostream& out) { out << text; });
}

}  // namespace pb
