// scene-to-gltf: writes a scene that bake reads (OBJ + MTL, or glTF, with its lights file) as a glTF 2.0 input
// scene: the inverse of mesh/gltf_loader.h's material mapping, so that the glTF bakes as the source does.
//   diffuse Kd          -> baseColorFactor Kd, metallic 0, roughness 1 (times map_Kd as baseColorTexture, with its
//                          -s/-o as KHR_texture_transform and -clamp as CLAMP_TO_EDGE; the image by its path)
//   mirror Kd + Ks      -> baseColorFactor Kd + Ks, metallicFactor mean(Ks) / mean(Kd + Ks), roughness 0
//   glass Tf, Ni        -> KHR_materials_transmission 1, baseColorFactor Tf, KHR_materials_ior Ni
//   Ke                  -> emissiveFactor Ke / max(Ke), KHR_materials_emissive_strength max(Ke)
//   point, spot, sun    -> KHR_lights_punctual (W/sr and W/m^2 times --luminous-efficacy: candela and lux)
//   sky, IES lamps,     -> glTF has none: written to OUT.lights.json beside the output, which bake reads (an IES
//   portals                lamp or a sky image names its file by its absolute path)
// One node per object, one primitive per material; --without MATERIAL leaves that material's faces out.
//   scene-to-gltf SCENE -o OUT.glb|OUT.gltf [--lights FILE] [--without MATERIAL]... [--scale S]
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "baker/files/atomic_file.h"
#include "baker/files/gltf_buffers.h"
#include "baker/files/json_file.h"
#include "baker/option_ranges.h"
#include "mesh/errors.h"
#include "mesh/scene_file.h"
#include "mesh/light_file.h"
#include "tools/cli_options.h"

namespace {

// Lights that glTF cannot hold, which go to the lights file beside the output.
bool InSidecar(const pb::AnalyticLight& light) { return light.kind == pb::LightKind::kSky || light.profile; }


namespace tg = tinygltf;
using pb::Rgb;

std::vector<double> Factor(Rgb c, double alpha = -1) {
  std::vector<double> v{c.r, c.g, c.b};
  if (alpha >= 0) v.push_back(alpha);
  return v;
}

tg::Value Object(std::initializer_list<std::pair<const std::string, tg::Value>> members) {
  return tg::Value(tg::Value::Object(members));
}

class Converter {
 public:
  Converter(const pb::Scene& scene, std::set<std::string> without, double efficacy, std::string outFolder)
      : scene_(scene), without_(std::move(without)), efficacy_(efficacy), folder_(std::move(outFolder)) {}

  tg::Model Convert() {
    model_.asset.version = "2.0";
    model_.asset.generator = "photonbake scene-to-gltf " PB_VERSION;
    for (const pb::Material& m : scene_.materials) model_.materials.push_back(MaterialOf(m));
    tg::Scene s;
    for (const auto& [object, faces] : FacesByObject()) s.nodes.push_back(MeshNode(object, faces));
    for (const pb::AnalyticLight& light : scene_.analyticLights)
      if (!InSidecar(light)) s.nodes.push_back(LightNode(light));
    model_.scenes.push_back(s);
    model_.defaultScene = 0;
    model_.extensionsUsed.assign(used_.begin(), used_.end());
    return std::move(model_);
  }

 private:
  void Use(const std::string& extension) { used_.insert(extension); }

  tg::Material MaterialOf(const pb::Material& m) {
    tg::Material g;
    g.name = m.name;
    tg::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    pbr.metallicFactor = 0, pbr.roughnessFactor = 1;
    pbr.baseColorFactor = Factor(m.albedo, 1);
    if (m.kind == pb::MaterialClass::kMirror) {
      const Rgb base = m.albedo + m.specular;
      pbr.baseColorFactor = Factor(base, 1);
      pbr.metallicFactor = base.Mean() > 0 ? m.specular.Mean() / base.Mean() : 1;
      pbr.roughnessFactor = 0;
    } else if (m.kind == pb::MaterialClass::kGlass) {
      pbr.baseColorFactor = Factor(m.transmittance, 1);
      pbr.roughnessFactor = 0;
      g.extensions["KHR_materials_transmission"] = Object({{"transmissionFactor", tg::Value(1.0)}});
      g.extensions["KHR_materials_ior"] = Object({{"ior", tg::Value(double(m.ior))}});
      Use("KHR_materials_transmission"), Use("KHR_materials_ior");
    }
    if (m.IsEmissive()) {
      const double peak = std::max({m.emission.r, m.emission.g, m.emission.b});
      g.emissiveFactor = Factor(m.emission * float(peak > 1 ? 1 / peak : 1));
      if (peak > 1) {
        g.extensions["KHR_materials_emissive_strength"] = Object({{"emissiveStrength", tg::Value(peak)}});
        Use("KHR_materials_emissive_strength");
      }
    }
    if (m.albedoTexture >= 0) pbr.baseColorTexture = TextureOf(m);
    return g;
  }

  tg::TextureInfo TextureOf(const pb::Material& m) {
    tg::Image image;
    const std::filesystem::path file = scene_.textures[size_t(m.albedoTexture)].path;
    image.uri = std::filesystem::relative(std::filesystem::absolute(file), std::filesystem::absolute(folder_)).string();
    model_.images.push_back(image);
    tg::Sampler sampler;
    if (m.textureClamp) sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    model_.samplers.push_back(sampler);
    tg::Texture texture;
    texture.source = int(model_.images.size() - 1), texture.sampler = int(model_.samplers.size() - 1);
    model_.textures.push_back(texture);
    tg::TextureInfo info;
    info.index = int(model_.textures.size() - 1);
    if (m.HasTextureTransform()) {  // our (s, t) -> glTF's (u, 1 - t): u' = a u + b, v' = c v + d
      info.extensions["KHR_texture_transform"] = Object(
          {{"scale", tg::Value(tg::Value::Array{tg::Value(double(m.textureScale.u)), tg::Value(double(m.textureScale.v))})},
           {"offset", tg::Value(tg::Value::Array{tg::Value(double(m.textureOffset.u)),
                                                 tg::Value(double(1 - m.textureScale.v - m.textureOffset.v))})}});
      Use("KHR_texture_transform");
    }
    return info;
  }

  // Kept triangles by object, then by material, in scene order.
  std::map<uint32_t, std::map<uint32_t, std::vector<uint32_t>>> FacesByObject() const {
    std::map<uint32_t, std::map<uint32_t, std::vector<uint32_t>>> faces;
    for (uint32_t t = 0; t < scene_.triangles.size(); ++t) {
      const pb::Triangle& tri = scene_.triangles[t];
      if (without_.count(scene_.materials[tri.material].name)) continue;
      faces[tri.object][tri.material].push_back(t);
    }
    return faces;
  }

  int MeshNode(uint32_t object, const std::map<uint32_t, std::vector<uint32_t>>& byMaterial) {
    tg::Mesh mesh;
    mesh.name = scene_.objectNames[object].empty() ? fmt::format("object {}", object) : scene_.objectNames[object];
    for (const auto& [material, triangles] : byMaterial) mesh.primitives.push_back(Primitive(material, triangles));
    model_.meshes.push_back(mesh);
    tg::Node node;
    node.name = mesh.name;
    node.mesh = int(model_.meshes.size() - 1);
    if (scene_.Recentred()) node.translation = {scene_.origin[0], scene_.origin[1], scene_.origin[2]};
    model_.nodes.push_back(node);
    return int(model_.nodes.size() - 1);
  }

  // The triangles' corners, a vertex per distinct (position, texture coordinate) pair.
  tg::Primitive Primitive(uint32_t material, const std::vector<uint32_t>& triangles) {
    const bool textured = scene_.materials[material].albedoTexture >= 0;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> vertexOf;
    std::vector<std::array<float, 3>> positions;
    std::vector<std::array<float, 2>> texcoords;
    std::vector<std::array<uint32_t, 3>> faces;
    for (uint32_t t : triangles) {
      std::array<uint32_t, 3> face{};
      for (int k = 0; k < 3; ++k) {
        const pb::Triangle& tri = scene_.triangles[t];
        const uint32_t vt = textured ? tri.vt[size_t(k)] : pb::kNoTexcoord;
        const auto [it, isNew] = vertexOf.emplace(std::pair{tri.v[size_t(k)], vt}, uint32_t(positions.size()));
        if (isNew) {
          const pb::Point3 p = scene_.positions[tri.v[size_t(k)]];
          positions.push_back({p.x, p.y, p.z});
          if (textured) texcoords.push_back({scene_.texcoords[vt].u, 1 - scene_.texcoords[vt].v});
        }
        face[size_t(k)] = it->second;
      }
      faces.push_back(face);
    }
    pb::GltfBufferWriter buffers(model_);
    tg::Primitive p;
    p.mode = TINYGLTF_MODE_TRIANGLES;
    p.material = int(material);
    p.attributes["POSITION"] = buffers.Vec3(positions, true);
    if (textured) p.attributes["TEXCOORD_0"] = buffers.Vec2(texcoords);
    p.indices = buffers.Indices(faces);
    return p;
  }

  // A node at the light, turned so that its -z axis is the light's direction.
  int LightNode(const pb::AnalyticLight& light) {
    tg::Light g;
    g.name = light.name;
    g.color = {1, 1, 1};
    const float peak = std::max({light.intensity.r, light.intensity.g, light.intensity.b});
    if (peak > 0) g.color = Factor(light.intensity * (1 / peak));
    g.intensity = peak * efficacy_;
    g.type = light.kind == pb::LightKind::kSun ? "directional" : light.kind == pb::LightKind::kSpot ? "spot" : "point";
    if (light.kind == pb::LightKind::kSpot)
      g.spot.innerConeAngle = std::acos(double(light.cosInner)), g.spot.outerConeAngle = std::acos(double(light.cosOuter));
    model_.lights.push_back(g);
    Use("KHR_lights_punctual");
    tg::Node node;
    node.name = light.name;
    node.extensions["KHR_lights_punctual"] = Object({{"light", tg::Value(int(model_.lights.size() - 1))}});
    if (light.kind != pb::LightKind::kSun) {
      const std::array<double, 3> p = scene_.ToWorld(light.position);
      node.translation = {p[0], p[1], p[2]};
    }
    if (light.kind != pb::LightKind::kPoint) node.rotation = RotationFromMinusZ(light.direction);
    model_.nodes.push_back(node);
    return int(model_.nodes.size() - 1);
  }

  // The unit quaternion (x, y, z, w) turning (0, 0, -1) onto the unit vector d.
  static std::vector<double> RotationFromMinusZ(pb::Vector3 d) {
    const double ax = d.y, ay = -d.x, az = 0, w = 1 - d.z;  // (0,0,-1) x d and 1 + (0,0,-1) . d
    if (w < 1e-9) return {1, 0, 0, 0};                       // d = (0, 0, 1): half a turn about x
    const double n = std::sqrt(ax * ax + ay * ay + az * az + w * w);
    return {ax / n, ay / n, az / n, w / n};
  }

  const pb::Scene& scene_;
  std::set<std::string> without_;
  double efficacy_;
  std::string folder_;
  tg::Model model_;
  std::set<std::string> used_;
};

// The lights file's entry of a sky or an IES lamp.
nlohmann::json SidecarEntry(const pb::Scene& scene, const pb::AnalyticLight& l) {
  if (l.kind == pb::LightKind::kSky) {
    nlohmann::json sky = {{"type", "sky"}, {"name", l.name}, {"radiance_W_m2_sr", 1},  // L as its colour: exact
                          {"color", {l.intensity.r, l.intensity.g, l.intensity.b}}, {"up", {l.up.x, l.up.y, l.up.z}},
                          {"whole_sphere", l.wholeSphere}};
    if (l.image) sky["image"] = std::filesystem::absolute(l.image->source).string(), sky["front"] = {l.c0.x, l.c0.y, l.c0.z};
    return sky;
  }
  const pb::Rgb perCandela = l.intensity * float(pb::kDefaultLuminousEfficacy);  // the file's default efficacy
  const std::array<double, 3> p = scene.ToWorld(l.position);
  return {{"type", "point"}, {"name", l.name}, {"ies", std::filesystem::absolute(l.profile->Source()).string()},
          {"position_m", {p[0], p[1], p[2]}}, {"direction", {l.direction.x, l.direction.y, l.direction.z}},
          {"c0", {l.c0.x, l.c0.y, l.c0.z}}, {"color", {perCandela.r, perCandela.g, perCandela.b}}};
}

void WriteSidecarLights(pb::OutputFiles& outputs, const std::string& path, const pb::Scene& scene) {
  nlohmann::json lights = nlohmann::json::array();
  for (const pb::AnalyticLight& l : scene.analyticLights)
    if (InSidecar(l)) lights.push_back(SidecarEntry(scene, l));
  nlohmann::json portals = nlohmann::json::array();
  for (const pb::Portal& p : scene.portals) {
    nlohmann::json corners = nlohmann::json::array();
    for (const pb::Point3 c : {p.origin, p.origin + p.u, p.origin + p.u + p.v, p.origin + p.v}) {
      const std::array<double, 3> w = scene.ToWorld(c);
      corners.push_back({w[0], w[1], w[2]});
    }
    portals.push_back({{"corners_m", corners}});
  }
  if (lights.empty() && portals.empty()) return;
  nlohmann::json file = {{"lights", lights}};
  if (!portals.empty()) file["portals"] = portals;
  pb::WriteJsonFile(outputs, path, file);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"scene-to-gltf: a scene that bake reads, written as a glTF 2.0 input scene"};
  std::string scenePath, outputPath, lightsPath;
  std::vector<std::string> without;
  float scale = 1;
  double efficacy = pb::kDefaultLuminousEfficacy;
  app.add_option("scene", scenePath, "OBJ (with MTL) or glTF scene")->required();
  app.add_option("-o,--output", outputPath, "glTF to write: .glb (binary) or .gltf (buffer as a data URI)")->required();
  app.add_option("--lights", lightsPath, "lights file; default SCENE.lights.json where it exists");
  app.add_option("--without", without, "leave out the faces of this material (repeatable)");
  app.add_option("--scale", scale, "metres per scene unit; [1e-6, 1e6]")->capture_default_str();
  app.add_option("--luminous-efficacy", efficacy, "lm/W for the lights' candela and lux; [1, 683]")->capture_default_str();
  const auto validate = [&] {  // with bake's ranges (baker/option_ranges.h)
    pb::RequireScale(scale);
    pb::RequireLuminousEfficacy(efficacy);
    if (!pb::HasGltfExtension(outputPath)) throw pb::InputError(outputPath, 0, "the output must end in .glb or .gltf");
  };
  return pb::tools::RunTool(app, argc, argv, validate, [&] {
    pb::LoadedScene loaded = pb::LoadScene(scenePath, {scale, efficacy});
    pb::AddLightsFile(loaded.scene, lightsPath);
    for (const std::string& w : loaded.warnings) std::fprintf(stderr, "%s\n", w.c_str());
    const std::string folder = std::filesystem::path(outputPath).parent_path().string();
    tg::Model model =
        Converter(loaded.scene, {without.begin(), without.end()}, efficacy, folder.empty() ? "." : folder).Convert();
    pb::OutputFiles outputs;
    pb::WriteGltfModel(outputs, outputPath, std::move(model));
    WriteSidecarLights(outputs, pb::LightsSidecarPath(outputPath), loaded.scene);
    outputs.Commit();
    std::printf("scene-to-gltf: %s -> %s (%zu meshes, %zu materials, %zu lights)\n", scenePath.c_str(),
                outputPath.c_str(), model.meshes.size(), model.materials.size(), model.lights.size());
  });
}
