#include "mesh/camera.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "mesh/errors.h"
#include "mesh/input_file.h"

namespace pb {
namespace {

int LineOfByte(const std::string& text, size_t byte) {
  return 1 + int(std::count(text.begin(), text.begin() + std::min(byte, text.size()), '\n'));
}

// Finds the line where `key` is written, for messages about its value.
int LineOfKey(const std::string& text, const std::string& key) {
  const size_t at = text.find("\"" + key + "\"");
  return at == std::string::npos ? 0 : LineOfByte(text, at);
}

// Coordinates beyond this [m] are refused: float keeps their metres only to within 60 m, and lengths built from
// them would overflow.
constexpr double kMaxCoordinate = 1e9;

// Three numbers, each finite and within `limit` in magnitude; a direction (`unit`) is normalised in double, so
// that any non-zero length is accepted.
std::array<float, 3> ReadTriple(const nlohmann::json& j, const std::string& key, const std::string& path,
                                const std::string& text, bool unit = false) {
  if (!j.contains(key)) throw InputError(path, 0, "camera has no '" + key + "'");
  const nlohmann::json& v = j[key];
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw InputError(path, LineOfKey(text, key), "'" + key + "' must be an array of 3 numbers");
  std::array<double, 3> d{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  double scale = 1;
  if (unit) scale = std::max({std::fabs(d[0]), std::fabs(d[1]), std::fabs(d[2])});
  for (double x : d)
    if (!std::isfinite(x) || (!unit && std::fabs(x) > kMaxCoordinate))
      throw InputError(path, LineOfKey(text, key), "'" + key + "' must hold finite numbers" +
                                                       (unit ? std::string() : " within 1e9 m"));
  if (unit && !(scale > 0)) return {0, 0, 0};
  return {float(d[0] / scale), float(d[1] / scale), float(d[2] / scale)};
}

}  // namespace

Camera LoadCamera(const std::string& path) {
  RequireRegularFile(path, "camera file");
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open camera file");
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path, LineOfByte(text, e.byte ? e.byte - 1 : 0), "malformed JSON");
  } catch (const nlohmann::json::exception& e) {  // a number that overflows double, among others
    throw InputError(path, 0, std::string("unreadable JSON: ") + e.what());
  }
  const auto p = ReadTriple(j, "position_m", path, text), l = ReadTriple(j, "look_at_m", path, text),
             u = ReadTriple(j, "up", path, text, true);
  Camera c{{p[0], p[1], p[2]}, {l[0], l[1], l[2]}, {u[0], u[1], u[2]}, 0};
  if (!j.contains("vertical_fov_deg") || !j["vertical_fov_deg"].is_number())
    throw InputError(path, LineOfKey(text, "vertical_fov_deg"), "camera needs a number 'vertical_fov_deg'");
  c.verticalFovDeg = j["vertical_fov_deg"].get<float>();
  if (!(c.verticalFovDeg > 0 && c.verticalFovDeg < 180))
    throw InputError(path, LineOfKey(text, "vertical_fov_deg"), "'vertical_fov_deg' must lie in (0, 180)");
  const Vector3 view = Normalize(c.lookAt - c.position);  // both within 1e9 m: the difference cannot overflow
  if (!(c.lookAt.x != c.position.x || c.lookAt.y != c.position.y || c.lookAt.z != c.position.z))
    throw InputError(path, LineOfKey(text, "look_at_m"), "'look_at_m' equals 'position_m'");
  if (!(Length(Cross(view, c.up)) > 1e-6f * Length(c.up)))
    throw InputError(path, LineOfKey(text, "up"), "'up' is zero or parallel to the view direction");
  return c;
}

std::string CameraSidecarPath(const std::string& scenePath) {
  const size_t dot = scenePath.find_last_of('.'), slash = scenePath.find_last_of('/');
  const bool hasExtension = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return (hasExtension ? scenePath.substr(0, dot) : scenePath) + ".camera.json";
}

PinholeCamera::PinholeCamera(const Camera& c, int width, int height)
    : origin_(c.position), halfWidth_(0.5f * float(width)), halfHeight_(0.5f * float(height)) {
  forward_ = Normalize(c.lookAt - c.position);
  const Vector3 right = Normalize(Cross(forward_, c.up));
  const Vector3 up = Cross(right, forward_);
  const float pixel = std::tan(0.5f * c.verticalFovDeg * float(kPi) / 180.0f) / halfHeight_;  // plane at 1 m
  right_ = right * pixel;
  down_ = up * -pixel;
}

Vector3 PinholeCamera::Direction(float x, float y) const {
  return Normalize(forward_ + right_ * (x - halfWidth_) + down_ * (y - halfHeight_));
}

}  // namespace pb
