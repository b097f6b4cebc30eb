#include "mesh/light_file.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "mesh/camera.h"
#include "mesh/errors.h"
#include "mesh/ies_file.h"
#include "mesh/input_file.h"
#include "mesh/sky_image.h"
#include "mesh/json_input.h"

namespace pb {
namespace {

// Reads one light's entries; `from` is where its "type" is written, for lines.
class LightReader {
 public:
  // `sky`: the file's portals, and what its sky images read so far hold, which this light's image adds to.
  LightReader(const JsonInput& in, const nlohmann::json& j, size_t index, size_t from, double efficacy, SkyMemory& sky)
      : in_(in), j_(j), owner_(fmt::format("light {}", index)), from_(from), efficacy_(efficacy), sky_(sky) {}

  AnalyticLight Read(const Scene& scene) {
    AnalyticLight light;
    if (!j_["type"].is_string()) Fail("type", "'type' must be a string");
    const std::string type = j_["type"].get<std::string>();
    light.name = j_.contains("name") && j_["name"].is_string() ? j_["name"].get<std::string>() : type;
    light.source = fmt::format("{}:{}", in_.path, in_.LineOfKey("type", from_));
    if (type == "point" || type == "spot") {
      light.kind = type == "point" ? LightKind::kPoint : LightKind::kSpot;
      const auto p = ReadTriple(in_, j_, "position_m", owner_, from_);
      light.position = scene.ToLocal(p[0], p[1], p[2]);
      if (j_.contains("ies")) {
        if (light.kind == LightKind::kSpot) Fail("ies", "an IES profile is a point light's: its cone is the profile's");
        Profile(light);
      } else {
        light.intensity = Strength("intensity_W_sr", "intensity_cd");
      }
      if (light.kind == LightKind::kSpot) Cone(light);
    } else if (type == "sun") {
      light.kind = LightKind::kSun;
      light.direction = Direction("direction");
      light.intensity = Strength("irradiance_W_m2", "illuminance_lux");
    } else if (type == "sky") {
      light.kind = LightKind::kSky;
      light.up = j_.contains("up") ? Direction("up") : Vector3{0, 1, 0};
      if (j_.contains("whole_sphere") && !j_["whole_sphere"].is_boolean())
        Fail("whole_sphere", "'whole_sphere' must be true or false");
      light.wholeSphere = j_.contains("whole_sphere") && j_["whole_sphere"].get<bool>();
      if (j_.contains("image")) {
        Image(light);
      } else {
        light.intensity = Strength("radiance_W_m2_sr", "luminance_nit");
      }
    } else {
      Fail("type", "'type' must be \"point\", \"spot\", \"sun\" or \"sky\"");
    }
    return light;
  }

 private:
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const {
    throw InputError(in_.path, in_.LineOfKey(key, from_), owner_ + ": " + message);
  }

  Vector3 Direction(const std::string& key) const {
    const auto d = ReadTriple(in_, j_, key, owner_, from_, true);
    if (d[0] == 0 && d[1] == 0 && d[2] == 0) Fail(key, "'" + key + "' must not be zero");
    return {float(d[0]), float(d[1]), float(d[2])};
  }

  double Number(const std::string& key, double lo, double hi) const {
    if (!j_[key].is_number()) Fail(key, "'" + key + "' must be a number");
    const double x = j_[key].get<double>();
    if (!(x >= lo && x <= hi)) Fail(key, fmt::format("'{}' must lie in [{:g}, {:g}]", key, lo, hi));
    return x;
  }

  // The radiometric value, or the photometric one over the luminous efficacy; times "color".
  Rgb Strength(const std::string& radiometric, const std::string& photometric) const {
    const bool r = j_.contains(radiometric), p = j_.contains(photometric);
    if (r == p) Fail("type", "give exactly one of '" + radiometric + "' and '" + photometric + "'");
    const double value = r ? Number(radiometric, 0, 1e30) : Number(photometric, 0, 1e30) / efficacy_;
    return Colour() * float(value);
  }

  Rgb Colour() const {
    if (!j_.contains("color")) return {1, 1, 1};
    const auto c = ReadTriple(in_, j_, "color", owner_, from_);
    if (c[0] < 0 || c[1] < 0 || c[2] < 0) Fail("color", "'color' must not be negative");
    return {float(c[0]), float(c[1]), float(c[2])};
  }

  // The file that the string at `key` names, found from the lights file's folder as a scene's files are.
  std::string NamedFile(const std::string& key, const std::string& what) const {
    const std::string name = j_[key].get<std::string>();
    const std::optional<std::string> file = FindNamedFile(in_.path, name);
    if (!file) Fail(key, what + " '" + name + "' is not there");
    return *file;
  }

  // A point light's IES profile: the file (found as the scene's files are, from the lights file's folder), its
  // candela values times "scale" and "color" over the luminous efficacy, its nadir "direction" and "c0".
  void Profile(AnalyticLight& light) const {
    if (!j_["ies"].is_string()) Fail("ies", "'ies' must name an IES file");
    for (const char* strength : {"intensity_W_sr", "intensity_cd"})
      if (j_.contains(strength)) Fail(strength, fmt::format("'{}' and 'ies' both give the intensity: give one", strength));
    light.profile = std::make_shared<const IntensityProfile>(LoadIesFile(NamedFile("ies", "the IES file")));
    const double scale = j_.contains("scale") ? Number("scale", 0, 1e30) : 1;
    light.intensity = Colour() * float(scale / efficacy_);
    light.direction = j_.contains("direction") ? Direction("direction") : Vector3{0, -1, 0};
    const Vector3 c0 = j_.contains("c0") ? Direction("c0") : std::fabs(light.direction.x) < 0.9f ? Vector3{1, 0, 0}
                                                                                                 : Vector3{0, 0, 1};
    const Vector3 across = c0 - light.direction * Dot(c0, light.direction);
    if (!(Length(across) > 1e-3f * Length(c0))) Fail("c0", "'c0' must not be parallel to 'direction'");
    light.c0 = Normalize(across);
  }

  // A sky's image (found as the scene's files are), its texels times the optional strength ("radiance_W_m2_sr" or
  // "luminance_nit", else 1) and "color"; its front (where the image's centre looks) is "front", or -z (+x for a
  // sky whose up is along z) turned by "rotation_deg" counter-clockwise seen from above, made perpendicular to up.
  // A constant image is a constant sky.
  void Image(AnalyticLight& light) const {
    if (!j_["image"].is_string()) Fail("image", "'image' must name an OpenEXR or Radiance HDR file");
    SkyImage image = LoadSkyImage(NamedFile("image", "the sky image"), kMaxSkyPixels, sky_);
    sky_.held += SkyImageBytes(image.texels.size(), sky_.portals);
    const bool strong = j_.contains("radiance_W_m2_sr") || j_.contains("luminance_nit");
    light.intensity = strong ? Strength("radiance_W_m2_sr", "luminance_nit") : Colour();
    const Vector3 up = light.up, base = std::fabs(up.z) < 0.9f ? Vector3{0, 0, -1} : Vector3{1, 0, 0};
    if (j_.contains("front") && j_.contains("rotation_deg")) Fail("front", "give 'front' or 'rotation_deg', not both");
    const Vector3 towards = j_.contains("front") ? Direction("front") : base;
    const Vector3 across = towards - up * Dot(towards, up);
    if (!(Length(across) > 1e-3f)) Fail("front", "'front' must not be parallel to 'up'");
    const Vector3 front = Normalize(across);
    const double turn = j_.contains("rotation_deg") ? Number("rotation_deg", -360, 360) * kPi / 180 : 0;
    light.c0 = Normalize(front * float(std::cos(turn)) + Cross(up, front) * float(std::sin(turn)));
    if (image.IsConstant()) {
      light.intensity = light.intensity * image.texels.front();
      return;
    }
    light.image = std::make_shared<const SkyImage>(std::move(image));
  }

  void Cone(AnalyticLight& light) const {
    const double inner = j_.contains("inner_cone_deg") ? Number("inner_cone_deg", 0, 90) : 0;
    const double outer = j_.contains("outer_cone_deg") ? Number("outer_cone_deg", 0, 90) : 45;
    if (!(inner < outer)) Fail("outer_cone_deg", "'inner_cone_deg' must be less than 'outer_cone_deg'");
    light.cosInner = float(std::cos(inner * kPi / 180)), light.cosOuter = float(std::cos(outer * kPi / 180));
    light.direction = j_.contains("direction") ? Direction("direction") : Vector3{0, -1, 0};
  }

  const JsonInput& in_;
  const nlohmann::json& j_;
  std::string owner_;
  size_t from_;
  double efficacy_;
  SkyMemory& sky_;
};

}  // namespace

void AddLightsFile(Scene& scene, const std::string& named) {
  const std::string path = named.empty() ? LightsSidecarPath(scene.path) : named;
  std::error_code error;  // a sidecar whose name cannot exist (past the file system's limit) is simply absent
  if (named.empty() && !std::filesystem::is_regular_file(path, error)) return;
  LightsFile file = LoadLightsFile(path, scene);
  for (AnalyticLight& light : file.lights) scene.analyticLights.push_back(std::move(light));
  scene.portals = std::move(file.portals);
  scene.lightsFile = path;
}

std::string LightsSidecarPath(const std::string& scenePath) {
  const std::string camera = CameraSidecarPath(scenePath);
  return camera.substr(0, camera.size() - std::string(".camera.json").size()) + ".lights.json";
}

// The portal `index`, its corners in order; they must form a parallelogram of non-zero area.
Portal ReadPortal(const JsonInput& in, const nlohmann::json& j, size_t index, const Scene& scene) {
  const int line = in.LineOfKey("corners_m", in.NthKey("corners_m", index));
  const std::string owner = fmt::format("portal {}", index);
  if (!j.is_object() || !j.contains("corners_m") || !j["corners_m"].is_array() || j["corners_m"].size() != 4)
    throw InputError(in.path, line, owner + ": 'corners_m' must hold its 4 corners");
  std::array<Point3, 4> c;
  for (size_t k = 0; k < 4; ++k) {
    const auto p = ReadTriple(in, nlohmann::json{{"corner", j["corners_m"][k]}}, "corner", owner);
    c[k] = scene.ToLocal(p[0], p[1], p[2]);
  }
  const Portal portal{c[0], c[1] - c[0], c[3] - c[0]};
  const Vector3 skew = c[2] - (c[1] + portal.v);
  if (!(portal.Area() > 0) || Length(skew) > 1e-3f * (Length(portal.u) + Length(portal.v)))
    throw InputError(in.path, line, owner + ": its corners must form a parallelogram of non-zero area, in order");
  return portal;
}

LightsFile LoadLightsFile(const std::string& path, const Scene& scene) {
  const JsonInput in = ReadJsonInput(path, "lights file");
  const nlohmann::json& j = in.json;
  if (!j.is_object() || !j.contains("lights") || !j["lights"].is_array())
    throw InputError(path, in.LineOfKey("lights"), "a lights file is an object with an array 'lights'");
  double efficacy = kDefaultLuminousEfficacy;
  if (j.contains("luminous_efficacy_lm_per_W")) {
    const nlohmann::json& e = j["luminous_efficacy_lm_per_W"];
    efficacy = e.is_number() ? e.get<double>() : 0;
    if (!(efficacy >= 1 && efficacy <= 683))
      throw InputError(path, in.LineOfKey("luminous_efficacy_lm_per_W"),
                       "'luminous_efficacy_lm_per_W' must lie in [1, 683]");
  }
  LightsFile file;
  std::vector<AnalyticLight>& lights = file.lights;
  SkyMemory sky{.portals = j.contains("portals") && j["portals"].is_array() ? j["portals"].size() : 0};
  for (size_t i = 0; i < j["lights"].size(); ++i) {
    const nlohmann::json& entry = j["lights"][i];
    const size_t from = in.NthKey("type", i);
    if (!entry.is_object() || !entry.contains("type"))
      throw InputError(path, in.LineOfKey("lights"), fmt::format("light {} is not an object with a 'type'", i));
    lights.push_back(LightReader(in, entry, i, from, efficacy, sky).Read(scene));
  }
  if (j.contains("portals")) {
    if (!j["portals"].is_array()) throw InputError(path, in.LineOfKey("portals"), "'portals' must be an array");
    for (size_t i = 0; i < j["portals"].size(); ++i) file.portals.push_back(ReadPortal(in, j["portals"][i], i, scene));
  }
  return file;
}

}  // namespace pb
