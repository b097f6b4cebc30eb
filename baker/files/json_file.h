// JSON reports (--report) staged as outputs: two-space indented, and never fatal on text from scene files. A name
// in any encoding (a Latin-1 material name from a 3ds Max export) has its invalid UTF-8 replaced by U+FFFD.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "baker/files/atomic_file.h"

namespace pb {

inline void WriteJsonFile(OutputFiles& outputs, const std::string& path, const nlohmann::json& j) {
  const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  outputs.Write(path, [&](std::ostream& out) { out << text; });
}

}  // namespace pb
