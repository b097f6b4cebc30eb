// Lights that are not surfaces, for scenes whose format has none (OBJ), or to add a sun and a sky to any scene: a
// sidecar SCENE.lights.json beside the scene (or the file --lights names), in the style of the camera sidecar.
//   {
//     "luminous_efficacy_lm_per_W": 683,      (optional: converts the photometric forms below)
//     "lights": [
//       {"type": "point", "name": "bulb", "position_m": [0, 2.4, 0], "intensity_W_sr": 5, "color": [1, 0.9, 0.8]},
//       {"type": "spot", "position_m": [1, 2.4, 0], "direction": [0, -1, 0], "intensity_cd": 3400,
//        "inner_cone_deg": 20, "outer_cone_deg": 35},
//       {"type": "sun", "direction": [0.4, -1, 0.3], "irradiance_W_m2": 600},
//       {"type": "sky", "radiance_W_m2_sr": 20, "up": [0, 1, 0], "whole_sphere": false},
//       {"type": "point", "ies": "downlight.ies", "position_m": [2, 2.6, 1], "direction": [0, -1, 0], "c0": [1, 0, 0]},
//       {"type": "sky", "image": "studio.exr", "rotation_deg": 90}
//     ],
//     "portals": [{"corners_m": [[1.5, 1, 4], [1.5, 2.2, 4], [3.5, 2.2, 4], [3.5, 1, 4]]}]
//   }
// "portals" (optional) are the windows of a closed scene: sun and sky photons, the scene's glTF ones included, then
// start on them instead of outside the scene (mesh/lights.h). Each is a parallelogram given by its four corners in
// order, counter-clockwise seen from inside; nothing outside it may block the light.
// Each light's strength is given once, radiometrically or photometrically (divided by the luminous efficacy,
// 683 lm/W by default: the definition of the candela at 555 nm), and multiplied by its optional "color":
//   point, spot: "intensity_W_sr" [W/sr] or "intensity_cd" [cd = lm/sr], on the spot's axis;
//   sun:         "irradiance_W_m2" [W/m^2] or "illuminance_lux" [lx = lm/m^2], on a surface facing it;
//   sky:         "radiance_W_m2_sr" [W/(m^2 sr)] or "luminance_nit" [cd/m^2].
// An IES lamp ("ies", mesh/ies_file.h) is a point light whose intensity is its file's candela table [cd] times
// "scale" (default 1) over the efficacy, aimed by "direction" (its nadir) and "c0" (its horizontal angle 0). A sky
// with an "image" (.exr or .hdr, lat-long: mesh/sky_image.h) has the image's radiance times its optional strength
// (default 1); the image's centre looks along "front", or -z turned by "rotation_deg" (counter-clockwise seen
// from above). Files are found from the lights file's folder as a scene's are (mesh/input_file.h).
// Positions are world coordinates in metres; directions need not be unit; a spot's cone angles lie in
// 0 <= inner < outer <= 90 degrees (defaults 0 and 45, as glTF's). Errors name file:line.
#pragma once

#include <string>
#include <vector>

#include "mesh/scene.h"

namespace pb {

inline constexpr double kDefaultLuminousEfficacy = 683;  // [lm/W]

// "dir/scene.obj" -> "dir/scene.lights.json".
std::string LightsSidecarPath(const std::string& scenePath);

struct LightsFile {
  std::vector<AnalyticLight> lights;
  std::vector<Portal> portals;
};

// The lights and portals of `path`, in `scene`'s local coordinates (Scene::ToLocal). InputError naming file:line.
LightsFile LoadLightsFile(const std::string& path, const Scene& scene);

// Adds to `scene` the lights and portals of the file `named` (--lights), or else of the scene's sidecar
// (LightsSidecarPath) where there is one, and records it as Scene::lightsFile.
void AddLightsFile(Scene& scene, const std::string& named);

}  // namespace pb
