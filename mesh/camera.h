// A pinhole camera as plain data, and the rays through its image. World units are metres.
// The bundled scenes carry their camera beside them as SCENE.camera.json (data/box/README.md):
//   {"position_m": [x, y, z], "look_at_m": [x, y, z], "up": [x, y, z], "vertical_fov_deg": degrees}
// The image plane is square-pixelled; the horizontal field of view follows from the aspect ratio. Pixel (0, 0)
// is the top-left corner; image coordinates run right (x) and down (y), in pixels.
#pragma once

#include <string>

#include "mesh/geometry.h"

namespace pb {

struct Camera {
  Point3 position;         // [m]
  Point3 lookAt;           // [m], any point on the optical axis in front of the camera
  Vector3 up{0, 1, 0};     // world direction that appears upward; not parallel to the view
  float verticalFovDeg = 40;  // full vertical angle, in (0, 180) degrees
};

// Reads a camera sidecar; InputError naming file:line on malformed JSON, a missing key or an invalid camera.
Camera LoadCamera(const std::string& path);

// "dir/scene.obj" -> "dir/scene.camera.json".
std::string CameraSidecarPath(const std::string& scenePath);

class PinholeCamera {
 public:
  PinholeCamera(const Camera& camera, int width, int height);
  Point3 Origin() const { return origin_; }
  // Unit world direction through the image point (x, y) [pixels], x in [0, width), y in [0, height).
  Vector3 Direction(float x, float y) const;

 private:
  Point3 origin_;
  Vector3 forward_, right_, down_;  // right_ and down_ are scaled to one pixel on the plane at distance 1
  float halfWidth_, halfHeight_;    // [pixels]
};

}  // namespace pb
