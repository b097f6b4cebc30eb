// A triangle scene as loaded from disk: vertex positions [m], triangles, and their materials.
// Emission follows DESIGN.md: a face whose material has Ke emits radiance Ke [W/(m^2 sr)] one-sided along its
// front normal (counter-clockwise winding), with a cosine distribution, so its flux is Phi = pi * Ke * A [W].
//
// Materials come in three classes (DESIGN.md, "Material classes"); every reflectance is dimensionless, per
// channel in [0, 1]:
//   diffuse: Lambertian reflectance Kd.
//   mirror:  Lambertian Kd plus an ideal mirror of reflectance Ks, with Kd + Ks <= 1 per channel.
//   glass:   a smooth dielectric of refractive index Ni: Fresnel reflection, and refraction filtered by the
//            transmittance Tf (1 = clear). Its Kd is not used. A glass mesh is closed, front faces outward, so
//            a photon arriving on the front side enters it.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <optional>

#include "mesh/color.h"
#include "mesh/geometry.h"
#include "mesh/intensity_profile.h"
#include "mesh/sky_image.h"
#include "mesh/texture.h"

namespace pb {

enum class MaterialClass : uint8_t { kDiffuse, kMirror, kGlass };

struct Material {
  std::string name;
  MaterialClass kind = MaterialClass::kDiffuse;
  Rgb albedo;          // Kd: diffuse (Lambertian) reflectance; diffuse and mirror classes.
  Rgb emission;        // Ke: emitted radiance [W/(m^2 sr)], front side only.
  Rgb specular;        // Ks: ideal mirror reflectance; mirror class only, else 0.
  Rgb transmittance;   // Tf: fraction of refracted flux that passes; glass class only, else 0.
  float ior = 1.0f;    // Ni: refractive index inside the glass, relative to the outside (air = 1).
  int albedoTexture = -1;  // map_Kd: index into Scene::textures, or -1. The albedo is then Kd x texture.
  // map_Kd's -s and -o: the texture is read at (s, t) * textureScale + textureOffset; -clamp on: clamped to
  // [0, 1] instead of repeating.
  Point2 textureScale{1, 1}, textureOffset{0, 0};
  bool textureClamp = false;
  bool HasTextureTransform() const {
    return textureScale.u != 1 || textureScale.v != 1 || textureOffset.u != 0 || textureOffset.v != 0 || textureClamp;
  }
  bool IsEmissive() const { return !emission.IsBlack(); }
  bool IsSpecular() const { return kind != MaterialClass::kDiffuse; }
};

// The largest reflectance a diffuse or mirror material keeps, per channel of its albedo (times its texture's
// largest value) plus its specular. A surface that absorbs nothing keeps photons (and paths) bouncing until they
// escape: in a closed scene forever, and H = Phi / (A (1 - rho)) diverges. At 0.99 a photon's expected path is
// still bounded, at 100 surfaces. Both loaders cap with a warning: an OBJ's Kd 1, glTF's default base colour 1.
inline constexpr float kMaxReflectance = 0.99f;

// Scales m's albedo and specular down together so that no channel exceeds kMaxReflectance; returns the
// reflectance it had when it did.
inline std::optional<float> CapReflectance(Material& m, Rgb textureMaximum) {
  const float total = (m.albedo * textureMaximum + m.specular).Max();
  if (total <= kMaxReflectance) return std::nullopt;
  m.albedo = m.albedo * (kMaxReflectance / total);
  m.specular = m.specular * (kMaxReflectance / total);
  return total;
}

// Lights that are not surfaces, as a scene file declares them (glTF's KHR_lights_punctual, SCENE.lights.json):
//   point: radiant intensity I [W/sr] into every direction from `position`;
//   spot:  I times glTF's smooth falloff f = clamp((cos t - cos outer) / (cos inner - cos outer), 0, 1)^2, t the
//          angle from its axis `direction`;
//   sun:   a directional light: irradiance E [W/m^2] on a surface facing it, its light travelling along
//          `direction`, from outside the scene;
//   sky:   uniform radiance L [W/(m^2 sr)] arriving from every direction above the horizon (w . up > 0), or from
//          the whole sphere, from outside the scene.
enum class LightKind : uint8_t { kArea, kPoint, kSpot, kSun, kSky };

struct AnalyticLight {
  LightKind kind = LightKind::kPoint;
  std::string name;
  Rgb intensity;                 // point, spot: I [W/sr]; sun: E [W/m^2]; sky: L [W/(m^2 sr)]
  Point3 position;               // point, spot: local [m] (Scene::ToLocal)
  Vector3 direction{0, -1, 0};   // spot: its axis; sun: the direction its light travels. Unit.
  float cosInner = 1, cosOuter = 0.70710678f;  // spot: cosines of its cone angles, cosOuter < cosInner
  Vector3 up{0, 1, 0};           // sky: unit
  bool wholeSphere = false;      // sky: from every direction, not only above the horizon
  // point: its goniometric distribution (an IES file, mesh/ies_file.h), or null for the same intensity every way.
  // With one, I(w) = intensity [W/sr per cd] x the profile's I [cd], `direction` is the profile's nadir (vertical
  // angle 0) and `c0` its horizontal angle 0: unit, perpendicular to `direction`.
  std::shared_ptr<const IntensityProfile> profile;
  Vector3 c0{1, 0, 0};
  // sky: its radiance over directions as an image (mesh/sky_image.h), or null for the same L every way. With one,
  // L(w) = intensity x the image's texel, and `c0` is the sky's front (where the image's centre column looks):
  // unit, perpendicular to `up`.
  std::shared_ptr<const SkyImage> image;
  std::string source;            // where it was declared ("scene.gltf: /extensions/KHR_lights_punctual/lights/0")
};

// A window through which sun and sky light enter a closed scene (a lights file's "portals"): the parallelogram
// origin + a u + b v, a and b in [0, 1], with nothing outside it that blocks the light. Its inward normal is
// u x v normalised: the corners run counter-clockwise seen from inside. Local coordinates [m].
struct Portal {
  Point3 origin;
  Vector3 u, v;
  double Area() const { return Length(Cross(u, v)); }
  Normal3 Inward() const { return NormalFrom(Cross(u, v)); }
};

inline constexpr uint32_t kNoTexcoord = ~0u;

struct Triangle {
  std::array<uint32_t, 3> v{};  // indices into Scene::positions, counter-clockwise seen from the front.
  std::array<uint32_t, 3> vt{kNoTexcoord, kNoTexcoord, kNoTexcoord};  // indices into Scene::texcoords
  uint32_t material = 0;        // index into Scene::materials.
  uint32_t object = 0;          // index into Scene::objectNames.
  uint32_t sourceLine = 0;      // line of the OBJ 'f' statement it came from, for messages.
};

struct Scene {
  std::string path;  // the OBJ file, for messages.
  // World position [m] of the local origin: world = origin + local. The loader moves it to the bounding box's
  // centre when the scene lies further from the world origin than its own size, so that float coordinates keep
  // their precision there (a 10^5 m offset would cost 8 mm per coordinate); otherwise it is 0.
  std::array<double, 3> origin{0, 0, 0};
  std::vector<Point3> positions;  // local [m]
  std::vector<Triangle> triangles;
  std::vector<Material> materials;
  std::vector<Point2> texcoords;  // OBJ 'vt' (s, t)
  std::vector<Texture> textures;  // map_Kd images
  std::vector<std::string> materialLibraries;  // the mtllib files read, as resolved
  std::string lightsFile;                      // the lights file read (mesh/light_file.h), or ""
  std::vector<std::string> objectNames;     // from 'o' (or 'g') statements; "" before the first.
  std::vector<AnalyticLight> analyticLights;  // lights that are not surfaces (glTF, SCENE.lights.json)
  std::vector<Portal> portals;                // windows that sun and sky photons are aimed at (lights file)
  uint32_t degenerateTrianglesSkipped = 0;  // zero-area faces dropped at load time.
  uint32_t duplicateTrianglesSkipped = 0;   // exact repeats (same corners, same side) dropped at load time.

  // Every file the scene was read from, with what it was: the OBJ, its material libraries and its textures. No
  // output may overwrite one of them.
  std::vector<std::pair<std::string, std::string>> InputFiles() const {
    std::vector<std::pair<std::string, std::string>> files{{"the scene", path}};
    for (const std::string& library : materialLibraries) files.emplace_back("the material library", library);
    for (const Texture& texture : textures) files.emplace_back("the texture", texture.path);
    if (!lightsFile.empty()) files.emplace_back("the lights file", lightsFile);
    for (const AnalyticLight& light : analyticLights)
      if (light.profile) files.emplace_back("the IES file", light.profile->Source());
      else if (light.image) files.emplace_back("the sky image", light.image->source);
    return files;
  }

  Point3 Corner(uint32_t triangle, int k) const { return positions[triangles[triangle].v[k]]; }
  // (p1 - p0) x (p2 - p0): points to the front side, length = 2 * area [m^2].
  Vector3 AreaVector(uint32_t triangle) const {
    const Point3 p0 = Corner(triangle, 0);
    return Cross(Corner(triangle, 1) - p0, Corner(triangle, 2) - p0);
  }
  float Area(uint32_t triangle) const { return 0.5f * Length(AreaVector(triangle)); }
  Normal3 FrontNormal(uint32_t triangle) const { return NormalFrom(AreaVector(triangle)); }
  // The point with barycentrics (1 - b1 - b2, b1, b2), Embree's convention.
  Point3 PointAt(uint32_t triangle, float b1, float b2) const {
    const Point3 p0 = Corner(triangle, 0);
    return p0 + (Corner(triangle, 1) - p0) * b1 + (Corner(triangle, 2) - p0) * b2;
  }
  const Material& MaterialOf(uint32_t triangle) const { return materials[triangles[triangle].material]; }
  // Texture coordinates of corner k (meaningful when the triangle's material is textured).
  Point2 Texcoord(uint32_t triangle, int k) const { return texcoords[triangles[triangle].vt[k]]; }
  // Diffuse reflectance at barycentrics (b1, b2): Kd, times the map_Kd texture where there is one.
  Rgb AlbedoAt(uint32_t triangle, float b1, float b2) const { return AlbedoAt(MaterialOf(triangle), triangle, b1, b2); }
  // The same, for callers that already hold the triangle's material (the photon and path loops).
  Rgb AlbedoAt(const Material& m, uint32_t triangle, float b1, float b2) const {
    if (m.albedoTexture < 0) return m.albedo;
    const Point2 t0 = Texcoord(triangle, 0), t1 = Texcoord(triangle, 1), t2 = Texcoord(triangle, 2);
    return AlbedoAtTexcoord(m, {t0.u + (t1.u - t0.u) * b1 + (t2.u - t0.u) * b2,
                                t0.v + (t1.v - t0.v) * b1 + (t2.v - t0.v) * b2});
  }
  // Diffuse reflectance of `m` at texture coordinates st (Kd when it has no texture).
  Rgb AlbedoAtTexcoord(const Material& m, Point2 st) const {
    if (m.albedoTexture < 0) return m.albedo;
    const Point2 at{st.u * m.textureScale.u + m.textureOffset.u, st.v * m.textureScale.v + m.textureOffset.v};
    return m.albedo * textures[size_t(m.albedoTexture)].Sample(at, m.textureClamp);
  }
  bool Recentred() const { return origin[0] != 0 || origin[1] != 0 || origin[2] != 0; }
  Point3 ToLocal(double x, double y, double z) const {
    return {float(x - origin[0]), float(y - origin[1]), float(z - origin[2])};
  }
  std::array<double, 3> ToWorld(Point3 p) const { return {origin[0] + p.x, origin[1] + p.y, origin[2] + p.z}; }
  // The largest |coordinate| of any vertex, locally [m]: the scale of float rounding in this scene.
  float LargestCoordinate() const {
    float largest = 0;
    for (const Point3& p : positions) largest = std::max(largest, MaxAbsComponent(p));
    return largest;
  }
  // The diagonal of the vertices' bounding box [m]: the scene's size; 0 without vertices.
  double Diagonal() const {
    if (positions.empty()) return 0;
    Point3 lo = positions.front(), hi = lo;
    for (const Point3& p : positions)
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)}, hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    return double(Length(hi - lo));
  }
};

// Material `textured`'s variant for faces that have no texture coordinates to read its albedo texture with (an OBJ
// face without v/t, a glTF primitive without the TEXCOORD_n its material names): Kd times the image's mean, with no
// texture, named "<name> (untextured)". `variants` remembers those made (textured material -> variant), so each is
// added to `scene` once.
inline uint32_t UntexturedVariant(Scene& scene, uint32_t textured, std::unordered_map<uint32_t, uint32_t>& variants) {
  const auto [it, isNew] = variants.emplace(textured, uint32_t(scene.materials.size()));
  if (isNew) {
    Material m = scene.materials[textured];
    m.albedo = m.albedo * scene.textures[size_t(m.albedoTexture)].Mean();
    m.albedoTexture = -1;
    m.textureScale = {1, 1}, m.textureOffset = {0, 0}, m.textureClamp = false;
    m.name += " (untextured)";
    scene.materials.push_back(m);
  }
  return it->second;
}

}  // namespace pb
