#include "mesh/camera.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "mesh/errors.h"
#include "mesh/json_input.h"

namespace pb {

Camera LoadCamera(const std::string& path) {
  const JsonInput in = ReadJsonInput(path, "camera file");
  const nlohmann::json& j = in.json;
  auto point = [&](const char* key, bool unit = false) {
    const std::array<double, 3> d = ReadTriple(in, j, key, "camera", 0, unit);
    return std::array<float, 3>{float(d[0]), float(d[1]), float(d[2])};
  };
  const auto p = point("position_m"), l = point("look_at_m"), u = point("up", true);
  Camera c{{p[0], p[1], p[2]}, {l[0], l[1], l[2]}, {u[0], u[1], u[2]}, 0};
  if (!j.is_object() || !j.contains("vertical_fov_deg") || !j["vertical_fov_deg"].is_number())
    throw InputError(path, in.LineOfKey("vertical_fov_deg"), "camera needs a number 'vertical_fov_deg'");
  c.verticalFovDeg = j["vertical_fov_deg"].get<float>();
  if (!(c.verticalFovDeg > 0 && c.verticalFovDeg < 180))
    throw InputError(path, in.LineOfKey("vertical_fov_deg"), "'vertical_fov_deg' must lie in (0, 180)");
  const Vector3 view = Normalize(c.lookAt - c.position);  // both within 1e9 m: the difference cannot overflow
  if (!(c.lookAt.x != c.position.x || c.lookAt.y != c.position.y || c.lookAt.z != c.position.z))
    throw InputError(path, in.LineOfKey("look_at_m"), "'look_at_m' equals 'position_m'");
  if (!(Length(Cross(view, c.up)) > 1e-6f * Length(c.up)))
    throw InputError(path, in.LineOfKey("up"), "'up' is zero or parallel to the view direction");
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
