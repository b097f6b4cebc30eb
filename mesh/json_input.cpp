#include "mesh/json_input.h"

#include <algorithm>
#include <cmath>

#include "mesh/errors.h"
#include "mesh/input_file.h"

namespace pb {
namespace {

int LineOfByte(const std::string& text, size_t byte) {
  return 1 + int(std::count(text.begin(), text.begin() + std::min(byte, text.size()), '\n'));
}

}  // namespace

int JsonInput::LineOfKey(const std::string& key, size_t from) const {
  const size_t at = text.find("\"" + key + "\"", std::min(from, text.size()));
  return at == std::string::npos ? 0 : LineOfByte(text, at);
}

size_t JsonInput::NthKey(const std::string& key, size_t n) const {
  size_t at = text.find("\"" + key + "\"");
  for (size_t i = 0; i < n && at != std::string::npos; ++i) at = text.find("\"" + key + "\"", at + 1);
  return at;
}

JsonInput ReadJsonInput(const std::string& path, const std::string& what) {
  JsonInput in{path, ReadRegularFile(path, what), {}};
  try {
    in.json = nlohmann::json::parse(in.text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path, LineOfByte(in.text, e.byte ? e.byte - 1 : 0), "malformed JSON");
  } catch (const nlohmann::json::exception& e) {  // a number that overflows double, among others
    throw InputError(path, 0, std::string("unreadable JSON: ") + e.what());
  }
  return in;
}

std::array<double, 3> ReadTriple(const JsonInput& in, const nlohmann::json& j, const std::string& key,
                                 const std::string& owner, size_t from, bool unit) {
  if (!j.contains(key)) throw InputError(in.path, in.LineOfKey("type", from), owner + " has no '" + key + "'");
  const nlohmann::json& v = j[key];
  const int line = in.LineOfKey(key, from);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw InputError(in.path, line, "'" + key + "' must be an array of 3 numbers");
  std::array<double, 3> d{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  for (double x : d)
    if (!std::isfinite(x) || (!unit && std::fabs(x) > kMaxJsonCoordinate))
      throw InputError(in.path, line, "'" + key + "' must hold finite numbers" + (unit ? std::string() : " within 1e9 m"));
  if (!unit) return d;
  const double scale = std::max({std::fabs(d[0]), std::fabs(d[1]), std::fabs(d[2])});
  if (!(scale > 0)) return {0, 0, 0};
  const double x = d[0] / scale, y = d[1] / scale, z = d[2] / scale, length = std::sqrt(x * x + y * y + z * z);
  return {x / length, y / length, z / length};
}

int LineNestedDeeperThan(std::string_view json, size_t most) {
  int line = 1;
  size_t depth = 0;
  bool inString = false;
  for (size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (c == '\n') ++line;
    if (inString) {
      if (c == '\\') ++i;  // an escaped character, a quote among them
      else if (c == '"') inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > most) return line;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return 0;
}

}  // namespace pb
