#include "mesh/gltf_loader.h"

#include <fmt/format.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>

#include "mesh/errors.h"
#include "mesh/gltf_accessor.h"
#include "mesh/gltf_file.h"
#include "mesh/gltf_hierarchy.h"
#include "mesh/mtl_loader.h"
#include "mesh/scene_builder.h"
#include "mesh/text_lines.h"

namespace pb {
namespace {

namespace tg = tinygltf;
using gltf::Accessor, gltf::Apply, gltf::FromTrs, gltf::kIdentity, gltf::LinearDeterminant, gltf::Matrix,
    gltf::Multiply;

unsigned char uchar(char c) { return static_cast<unsigned char>(c); }

// The extensions this loader reads (or knowingly ignores); a file that requires any other is refused.
const std::set<std::string>& KnownExtensions() {
  static const std::set<std::string> known{"KHR_texture_transform", "KHR_materials_emissive_strength",
                                           "KHR_materials_transmission", "KHR_materials_ior",
                                           "KHR_materials_unlit", "KHR_lights_punctual",
                                           "EXT_mesh_gpu_instancing"};
  return known;
}

// ---- texture coordinates ------------------------------------------------------------------------------------

// KHR_texture_transform: (u', v') = T R S (u, v), then our (s, t) = (u', 1 - v').
struct UvTransform {
  int texCoord = 0;                        // the TEXCOORD_n set it reads
  std::array<double, 6> m{1, 0, 0, 0, 1, 0};  // u' = m0 u + m1 v + m2, v' = m3 u + m4 v + m5
  Point2 Apply(double u, double v) const {
    return {float(m[0] * u + m[1] * v + m[2]), float(1.0 - (m[3] * u + m[4] * v + m[5]))};
  }
};


// What a primitive needs to know about its material beyond the index: which texture coordinates to read.
struct MaterialUse {
  uint32_t material = 0;
  std::optional<UvTransform> albedoUv;  // when the albedo is textured
  int emissiveTexture = -1;             // Scene::textures index of the emissive texture, or -1
  UvTransform emissiveUv;
};

std::string Folder(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

// A URI's %XX escapes decoded (glTF URIs are RFC 3986; "my%20wood.png" names "my wood.png").
std::string DecodeUri(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uchar(uri[i + 1])) && std::isxdigit(uchar(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

bool StartsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

const tg::Value* Member(const tg::ExtensionMap& extensions, const std::string& extension, const std::string& key) {
  const auto it = extensions.find(extension);
  if (it == extensions.end() || !it->second.Has(key)) return nullptr;
  return &it->second.Get(key);
}
double NumberOr(const tg::ExtensionMap& extensions, const std::string& extension, const std::string& key,
                double otherwise) {
  const tg::Value* v = Member(extensions, extension, key);
  return v && v->IsNumber() ? v->GetNumberAsDouble() : otherwise;
}

// ---- the loader ---------------------------------------------------------------------------------------------

class GltfReader {
 public:
  GltfReader(const std::string& path, const LoadOptions& options)
      : path_(path), options_(options), builder_(result_.scene) {
    result_.scene.path = path;
  }

  LoadedScene Read() {
    PB_CHECK(options_.scale > 0.0f && std::isfinite(options_.scale), "LoadOptions::scale is finite and > 0");
    GltfFile file = ReadGltfFile(path_);
    model_ = std::move(file.model);
    imageBytes_ = std::move(file.imageBytes);
    for (const std::string& line : file.warnings) Warn("tinygltf " + line.substr(0, 24), "/", line);
    RequireKnownExtensions();
    for (const auto& [node, world] : gltf::SceneNodes(model_, path_)) {
      if (model_.nodes[size_t(node)].mesh >= 0) AddNode(node, world);
      AddPunctualLight(node, world);
    }
    builder_.StorePositions(path_);
    if (result_.scene.triangles.empty()) RefuseEmpty();
    for (auto& [light, world] : lights_) {
      if (light.kind != LightKind::kSun) light.position = result_.scene.ToLocal(world[0], world[1], world[2]);
      result_.scene.analyticLights.push_back(std::move(light));
    }
    result_.warnings = warnings_.Lines();
    return std::move(result_);
  }

 private:
  [[noreturn]] void Fail(const std::string& where, const std::string& message) const {
    throw InputError(path_, 0, where + ": " + message);
  }
  void Warn(const std::string& kind, const std::string& where, const std::string& message) {
    warnings_.Add(kind, path_ + ": warning: " + where + ": " + message);
  }

  void RequireKnownExtensions() const {
    for (const std::string& used : model_.extensionsUsed)
      for (const char* compression : kGltfCompressions)
        if (used == compression) RefuseGltfCompression(path_, used);
    for (size_t i = 0; i < model_.extensionsRequired.size(); ++i)
      if (!KnownExtensions().count(model_.extensionsRequired[i]))
        Fail(fmt::format("/extensionsRequired/{}", i),
             "the file requires extension '" + model_.extensionsRequired[i] + "', which photonbake does not read");
  }

  uint32_t ObjectOf(int node) {
    const auto [it, isNew] = objectOfNode_.emplace(node, uint32_t(result_.scene.objectNames.size()));
    if (isNew) {
      const tg::Node& n = model_.nodes[size_t(node)];
      std::string name = n.name;
      if (name.empty() && n.mesh >= 0 && size_t(n.mesh) < model_.meshes.size()) name = model_.meshes[size_t(n.mesh)].name;
      if (name.empty()) name = fmt::format("node {}", node);
      result_.scene.objectNames.push_back(name);
    }
    return it->second;
  }

  void AddNode(int node, const Matrix& world) {
    const tg::Node& n = model_.nodes[size_t(node)];
    const std::string where = fmt::format("/nodes/{}", node);
    if (size_t(n.mesh) >= model_.meshes.size()) Fail(where, fmt::format("mesh {} does not exist", n.mesh));
    if (n.skin >= 0) Warn("skin", where, "skins are not applied: the mesh is baked as stored");
    const tg::Mesh& mesh = model_.meshes[size_t(n.mesh)];
    for (const Matrix& instance : gltf::InstanceTransforms(model_, n, where, path_))
      for (size_t p = 0; p < mesh.primitives.size(); ++p)
        AddPrimitive(mesh.primitives[p], fmt::format("/meshes/{}/primitives/{}", n.mesh, p),
                     Multiply(world, instance), ObjectOf(node));
  }

  void AddPrimitive(const tg::Primitive& primitive, const std::string& where, const Matrix& world, uint32_t object) {
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        primitive.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      firstIgnored_ = firstIgnored_.empty() ? where : firstIgnored_;
      return Warn("mode", where, fmt::format("mode {} (points or lines) has no area to bake; skipped", primitive.mode));
    }
    if (!primitive.targets.empty()) Warn("morph", where, "morph targets are not applied: the mesh is baked as stored");
    if (primitive.attributes.count("COLOR_0"))
      Warn("vertex colour", where + "/attributes/COLOR_0",
           "vertex colours are not read: the surface takes its material's base colour");
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) return Warn("no position", where, "no POSITION attribute; skipped");
    const Accessor positions(model_, position->second, 3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, where + "/attributes/POSITION", path_);
    const uint32_t first = AddPositions(positions, world, where);
    const MaterialUse use = MaterialOf(primitive.material, where);
    std::optional<Accessor> texcoords;
    if (use.albedoUv) texcoords = TexcoordAccessor(primitive, use.albedoUv->texCoord, positions.count(), where);
    const bool flip = LinearDeterminant(world) < 0;
    const uint32_t firstTexcoord = uint32_t(result_.scene.texcoords.size());
    if (texcoords)
      for (size_t i = 0; i < texcoords->count(); ++i)
        result_.scene.texcoords.push_back(use.albedoUv->Apply(texcoords->Get(i, 0), texcoords->Get(i, 1)));
    // A textured base colour with no coordinates to read it: the colour times the image's mean, as in an OBJ.
    uint32_t material = use.albedoUv && !texcoords ? UntexturedVariant(result_.scene, use.material, untextured_)
                                                   : use.material;
    const std::vector<std::array<uint32_t, 3>> corners = Corners(primitive, positions.count(), where);
    if (use.emissiveTexture >= 0) material = EmissiveVariant(primitive, use, material, where, first, corners);
    for (std::array<uint32_t, 3> c : corners) {
      if (flip) std::swap(c[1], c[2]);
      Triangle t{{first + c[0], first + c[1], first + c[2]}, {kNoTexcoord, kNoTexcoord, kNoTexcoord}, material, object, 0};
      if (texcoords) t.vt = {firstTexcoord + c[0], firstTexcoord + c[1], firstTexcoord + c[2]};
      AddTriangle(t, where);
    }
  }

  uint32_t AddPositions(const Accessor& positions, const Matrix& world, const std::string& where) {
    const uint32_t first = uint32_t(builder_.PositionCount());
    const double s = options_.scale;
    for (size_t i = 0; i < positions.count(); ++i) {
      const double local[3] = {positions.Get(i, 0), positions.Get(i, 1), positions.Get(i, 2)};
      Position p = Apply(world, local);
      for (double& x : p) x *= s;
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        Fail(where + "/attributes/POSITION", fmt::format("position {} is not finite", i));
      builder_.AddPosition(p);
    }
    return first;
  }

  std::optional<Accessor> TexcoordAccessor(const tg::Primitive& primitive, int set, size_t vertices,
                                           const std::string& where) {
    const std::string name = fmt::format("TEXCOORD_{}", set);
    const auto it = primitive.attributes.find(name);
    if (it == primitive.attributes.end()) {
      Warn("no texcoords", where, "the material is textured but the primitive has no " + name +
                                      "; the texture's mean is used instead");
      return std::nullopt;
    }
    Accessor a(model_, it->second, 2,
               {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
               where + "/attributes/" + name, path_);
    if (a.count() != vertices)
      Fail(where + "/attributes/" + name, fmt::format("{} texture coordinates for {} positions", a.count(), vertices));
    return a;
  }

  // The primitive's triangles as corner indices into its own vertices.
  std::vector<std::array<uint32_t, 3>> Corners(const tg::Primitive& primitive, size_t vertices,
                                               const std::string& where) const {
    std::vector<uint32_t> index;
    if (primitive.indices >= 0) {
      const Accessor a(model_, primitive.indices, 1,
                       {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                        TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                       where + "/indices", path_);
      index.reserve(a.count());
      for (size_t i = 0; i < a.count(); ++i) {
        const uint64_t k = a.Index(i);
        if (k >= vertices) Fail(where + "/indices", fmt::format("index {} is {}, out of range ({} vertices)", i, k, vertices));
        index.push_back(uint32_t(k));
      }
    } else {
      for (size_t i = 0; i < vertices; ++i) index.push_back(uint32_t(i));
    }
    std::vector<std::array<uint32_t, 3>> triangles;
    const size_t n = index.size();
    if (primitive.mode == TINYGLTF_MODE_TRIANGLES) {
      for (size_t i = 0; i + 2 < n; i += 3) triangles.push_back({index[i], index[i + 1], index[i + 2]});
    } else if (primitive.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {  // glTF 3.7.2.1: every other one reversed
      for (size_t i = 0; i + 2 < n; ++i)
        triangles.push_back({index[i], index[i + 1 + i % 2], index[i + 2 - i % 2]});
    } else {
      for (size_t i = 1; i + 1 < n; ++i) triangles.push_back({index[i], index[i + 1], index[0]});
    }
    return triangles;
  }

  void AddTriangle(const Triangle& t, const std::string& where) {
    const SceneBuilder::Outcome added = builder_.AddTriangle(t, 0);
    if (added.skipped == SceneBuilder::Skipped::kZeroArea) Warn("zero-area", where, "zero-area triangle skipped");
    if (added.skipped == SceneBuilder::Skipped::kRepeat)
      Warn("repeat", where, "triangle repeats an earlier one (same corners, same side); skipped");
  }

  [[noreturn]] void RefuseEmpty() const {
    if (!firstIgnored_.empty()) Fail(firstIgnored_, "scene has no triangles to bake: only points and lines");
    if (result_.scene.degenerateTrianglesSkipped > 0)
      throw InputError(path_, 0, "scene has no faces to bake: every triangle has zero area");
    throw InputError(path_, 0, "scene has no triangles (no node of its scene carries a mesh of triangles)");
  }

  // ---- KHR_lights_punctual ----

  // The light a node carries, if any: placed at the node's origin, pointing along its -z axis. Candela and lux are
  // turned into W/sr and W/m^2 over the luminous efficacy.
  void AddPunctualLight(int node, const Matrix& world) {
    const tg::Node& n = model_.nodes[size_t(node)];
    const tg::Value* index = Member(n.extensions, "KHR_lights_punctual", "light");
    if (!index) return;
    const std::string where = fmt::format("/nodes/{}/extensions/KHR_lights_punctual/light", node);
    const int l = index->IsNumber() ? int(index->GetNumberAsDouble()) : -1;
    if (l < 0 || size_t(l) >= model_.lights.size())
      Fail(where, fmt::format("light {} does not exist ({} lights)", l, model_.lights.size()));
    const tg::Light& g = model_.lights[size_t(l)];
    const std::string self = fmt::format("/extensions/KHR_lights_punctual/lights/{}", l);
    AnalyticLight light;
    light.name = g.name.empty() ? (n.name.empty() ? g.type + " " + std::to_string(l) : n.name) : g.name;
    light.source = path_ + ": " + self;
    if (g.type == "point") light.kind = LightKind::kPoint;
    else if (g.type == "spot") light.kind = LightKind::kSpot;
    else if (g.type == "directional") light.kind = LightKind::kSun;
    else Fail(self, "type '" + g.type + "' is not point, spot or directional");
    if (!(g.intensity >= 0 && g.intensity <= 1e30)) Fail(self, "intensity must lie in [0, 1e30]");
    const Rgb colour = g.color.size() == 3 ? Colour(g.color) : Rgb{1, 1, 1};
    if (colour.r < 0 || colour.g < 0 || colour.b < 0) Fail(self, "color must not be negative");
    light.intensity = colour * float(g.intensity / options_.luminousEfficacy);
    if (g.range > 0) Warn("range", self, "range is ignored: the light falls off with the inverse square everywhere");
    if (light.kind == LightKind::kSpot) {
      const double inner = g.spot.innerConeAngle, outer = g.spot.outerConeAngle;
      if (!(inner >= 0 && inner < outer && outer <= kPi / 2 + 1e-9))
        Fail(self + "/spot", "cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
      light.cosInner = float(std::cos(inner)), light.cosOuter = float(std::cos(outer));
    }
    const double origin[3] = {0, 0, 0}, ahead[3] = {0, 0, -1};
    Position at = Apply(world, origin);
    const Position tip = Apply(world, ahead);
    const double d[3] = {tip[0] - at[0], tip[1] - at[1], tip[2] - at[2]};
    for (double& x : at) x *= options_.scale;
    // Within the bounds a lights file's positions keep (1e9 m): a light at 1e300, or under a transform that
    // overflows, would reach the ray tracer as infinities.
    if (!std::all_of(at.begin(), at.end(), [](double x) { return std::abs(x) <= SceneBuilder::kMaxSceneSize; }))
      Fail(where, fmt::format("the light lies at ({:g}, {:g}, {:g}) m after the nodes' transforms: beyond {:g} m",
                              at[0], at[1], at[2], SceneBuilder::kMaxSceneSize));
    const double length = std::hypot(d[0], d[1], d[2]);
    if (light.kind != LightKind::kPoint) {
      if (!(length > 0 && std::isfinite(length))) Fail(where, "the node's transform flattens or overflows the light's direction");
      light.direction = Normalize(Vector3{float(d[0] / length), float(d[1] / length), float(d[2] / length)});
    }
    lights_.emplace_back(light, at);
  }

  // ---- materials ----

  MaterialUse MaterialOf(int index, const std::string& where) {
    if (index < 0) return {DefaultMaterial()};
    if (size_t(index) >= model_.materials.size()) Fail(where + "/material", fmt::format("material {} does not exist", index));
    const auto it = materials_.find(index);
    if (it != materials_.end()) return it->second;
    return materials_[index] = ConvertMaterial(index);
  }

  uint32_t DefaultMaterial() {
    if (!defaultMaterial_) {
      Material m{"(default)"};
      m.albedo = {kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo};
      defaultMaterial_ = AppendMaterial(m);
    }
    return *defaultMaterial_;
  }
  uint32_t AppendMaterial(const Material& m) {
    result_.scene.materials.push_back(m);
    return uint32_t(result_.scene.materials.size() - 1);
  }

  static Rgb Colour(const std::vector<double>& c) {
    return c.size() >= 3 ? Rgb{float(c[0]), float(c[1]), float(c[2])} : Rgb{1, 1, 1};
  }

  MaterialUse ConvertMaterial(int index) {
    const tg::Material& g = model_.materials[size_t(index)];
    const std::string where = fmt::format("/materials/{}", index);
    const tg::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    Material m{g.name.empty() ? fmt::format("material {}", index) : g.name};
    const Rgb base = Colour(pbr.baseColorFactor);
    const double metallic = pbr.metallicFactor, roughness = pbr.roughnessFactor;
    const double transmission = NumberOr(g.extensions, "KHR_materials_transmission", "transmissionFactor", 0);
    RequireFactors(g, base, where);
    if (transmission > 0) {
      m.kind = MaterialClass::kGlass;
      m.transmittance = base * float(std::min(transmission, 1.0));
      m.ior = GlassIor(g, where);
      if (roughness > 0.1) Warn("rough glass", where, "rough transmission is baked as smooth glass");
    } else if (metallic > 0 && roughness <= 0.1) {
      m.kind = MaterialClass::kMirror;
      m.specular = base * float(metallic);
      m.albedo = base * float(1 - metallic);
    } else {
      m.albedo = base;
      if (metallic > 0) Warn("rough metal", where, "a rough metal (roughness > 0.1) is baked as diffuse base colour");
    }
    m.emission = Colour(g.emissiveFactor.size() == 3 ? g.emissiveFactor : std::vector<double>{0, 0, 0}) *
                 float(NumberOr(g.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1));
    WarnIgnored(g, where);
    if (g.doubleSided && m.IsEmissive())
      Warn("double-sided light", where, "doubleSided is not read for emission: the surface emits from its front side "
                                        "only (a back-to-back copy of its faces emits from both)");
    MaterialUse use;
    if (pbr.baseColorTexture.index >= 0 && m.kind != MaterialClass::kGlass) {
      if (const std::optional<int> texture = TextureOf(pbr.baseColorTexture, where + "/pbrMetallicRoughness/baseColorTexture", &m.textureClamp)) {
        m.albedoTexture = *texture;
        use.albedoUv = UvOf(pbr.baseColorTexture);
      }
    }
    const Rgb textureMaximum = m.albedoTexture >= 0 ? result_.scene.textures[size_t(m.albedoTexture)].maximum : Rgb{1, 1, 1};
    if (const std::optional<float> total = CapReflectance(m, textureMaximum))  // glTF's default base colour is 1
      Warn("reflectance cap", where, fmt::format("reflectance {:.3f} capped at 0.99, since a surface that absorbs nothing "
                                                 "never ends a path in a closed scene", *total));
    if (g.emissiveTexture.index >= 0 && m.IsEmissive()) {
      bool clamp = false;
      if (const std::optional<int> texture = TextureOf(g.emissiveTexture, where + "/emissiveTexture", &clamp)) {
        use.emissiveTexture = *texture;
        use.emissiveUv = UvOf(g.emissiveTexture);
      }
    }
    use.material = AppendMaterial(m);
    return use;
  }

  // The factors glTF bounds, where a value out of bounds would make light: a negative base or emissive colour, a
  // metallic or roughness factor outside [0, 1] (metallic 2 gives a negative diffuse part).
  void RequireFactors(const tg::Material& g, Rgb base, const std::string& where) const {
    const std::string pbr = where + "/pbrMetallicRoughness";
    if (std::min({base.r, base.g, base.b}) < 0) Fail(pbr + "/baseColorFactor", "must not be negative");
    for (const auto& [value, name] : {std::pair{g.pbrMetallicRoughness.metallicFactor, "metallicFactor"},
                                      std::pair{g.pbrMetallicRoughness.roughnessFactor, "roughnessFactor"}})
      if (!(value >= 0 && value <= 1)) Fail(pbr + "/" + name, fmt::format("{} must lie in [0, 1]", value));
    for (double e : g.emissiveFactor)
      if (!(e >= 0)) Fail(where + "/emissiveFactor", "must not be negative");
    if (!(NumberOr(g.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1) >= 0))
      Fail(where + "/extensions/KHR_materials_emissive_strength/emissiveStrength", "must not be negative");
  }

  // KHR_materials_ior's index, 1.5 when absent; one outside (0, 10], which glass cannot have here (an OBJ's Ni is
  // refused there), is read as 1.5 with a warning.
  float GlassIor(const tg::Material& g, const std::string& where) {
    const double ior = NumberOr(g.extensions, "KHR_materials_ior", "ior", 1.5);
    if (ior > 0 && ior <= 10) return float(ior);
    Warn("ior", where + "/extensions/KHR_materials_ior/ior", fmt::format("ior {} is outside (0, 10]: baked as 1.5", ior));
    return 1.5f;
  }

  void WarnIgnored(const tg::Material& g, const std::string& where) {
    if (g.normalTexture.index >= 0) Warn("normal texture", where, "normalTexture is ignored");
    if (g.occlusionTexture.index >= 0) Warn("occlusion texture", where, "occlusionTexture is ignored");
    if (g.pbrMetallicRoughness.metallicRoughnessTexture.index >= 0)
      Warn("metallic texture", where, "metallicRoughnessTexture is ignored; the factors are used");
    if (g.alphaMode != "OPAQUE") Warn("alpha", where, "alphaMode " + g.alphaMode + " is ignored: the surface is opaque");
    for (const auto& [name, value] : g.extensions)
      if (name == "KHR_materials_unlit") {
        Warn("unlit", where, "KHR_materials_unlit is read as diffuse base colour");
      } else if (!KnownExtensions().count(name)) {
        Warn("extension " + name, where, "material extension " + name + " is ignored");
      }
  }

  UvTransform UvOf(const tg::TextureInfo& info) const {
    UvTransform uv;
    uv.texCoord = info.texCoord;
    const auto it = info.extensions.find("KHR_texture_transform");
    if (it == info.extensions.end()) return uv;
    const tg::Value& x = it->second;
    auto pair = [&](const char* key, double a, double b) -> std::array<double, 2> {
      if (!x.Has(key) || !x.Get(key).IsArray() || x.Get(key).ArrayLen() != 2) return {a, b};
      return {x.Get(key).Get(0).GetNumberAsDouble(), x.Get(key).Get(1).GetNumberAsDouble()};
    };
    const auto offset = pair("offset", 0, 0), scale = pair("scale", 1, 1);
    const double r = x.Has("rotation") ? x.Get("rotation").GetNumberAsDouble() : 0;
    if (x.Has("texCoord")) uv.texCoord = x.Get("texCoord").GetNumberAsInt();
    // T R S with R = [cos r, sin r; -sin r, cos r] (the extension's matrix, row-major).
    const double c = std::cos(r), s = std::sin(r);
    uv.m = {c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1]};
    return uv;
  }

  // The texture `info` names, decoded once per image; nullopt (with a warning) when its image was not found.
  std::optional<int> TextureOf(const tg::TextureInfo& info, const std::string& where, bool* clamp) {
    if (size_t(info.index) >= model_.textures.size()) Fail(where, fmt::format("texture {} does not exist", info.index));
    const tg::Texture& texture = model_.textures[size_t(info.index)];
    if (texture.sampler >= 0 && size_t(texture.sampler) < model_.samplers.size()) {
      const tg::Sampler& s = model_.samplers[size_t(texture.sampler)];
      *clamp = s.wrapS == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE && s.wrapT == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
      if (!*clamp && (s.wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT || s.wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT))
        Warn("wrap", fmt::format("/samplers/{}", texture.sampler), "this wrap mode is read as REPEAT");
    }
    const int image = texture.source;
    if (image < 0 || size_t(image) >= model_.images.size())
      Fail(fmt::format("/textures/{}", info.index), fmt::format("image {} does not exist", image));
    const auto known = textureOfImage_.find(image);
    if (known != textureOfImage_.end()) return known->second;
    std::optional<int>& slot = textureOfImage_[image];
    const auto bytes = imageBytes_.find(image);
    if (bytes == imageBytes_.end()) {
      Warn("image not found", fmt::format("/images/{}", image),
           "image '" + model_.images[size_t(image)].uri + "' could not be read; its material keeps its factor");
      return slot;
    }
    result_.scene.textures.push_back(DecodeTexture(ImageName(image), bytes->second));
    return slot = int(result_.scene.textures.size() - 1);
  }

  // An external image's file; an embedded one is named by the glTF file itself.
  std::string ImageName(int image) const {
    const std::string& uri = model_.images[size_t(image)].uri;
    if (uri.empty() || StartsWith(uri, "data:")) return path_;
    return Folder(path_) + "/" + DecodeUri(uri);
  }

  // An emissive texture's mean over the primitive (area-weighted, four points per triangle; the image's mean where
  // the primitive has no coordinates for it) folded into the Ke of material `base`: a copy of it per primitive, since
  // a light has one radiance.
  uint32_t EmissiveVariant(const tg::Primitive& primitive, const MaterialUse& use, uint32_t base,
                           const std::string& where, uint32_t first, const std::vector<std::array<uint32_t, 3>>& corners) {
    const size_t vertices = builder_.PositionCount() - first;
    std::optional<Accessor> uv = TexcoordAccessor(primitive, use.emissiveUv.texCoord, vertices, where);
    const Texture& texture = result_.scene.textures[size_t(use.emissiveTexture)];
    Material m = result_.scene.materials[base];
    Warn("emissive texture", where, "emissiveTexture is averaged over the primitive: a light has one radiance");
    m.name += " (emissive texture averaged)";
    if (!uv) {
      m.emission = m.emission * texture.Mean();
      return AppendMaterial(m);
    }
    Rgb sum;
    double area = 0;
    constexpr double kPoints[4][2] = {{1.0 / 3, 1.0 / 3}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}, {1.0 / 6, 1.0 / 6}};
    for (const std::array<uint32_t, 3>& c : corners) {
      const double a = TriangleArea(first + c[0], first + c[1], first + c[2]);
      for (const auto& b : kPoints) {
        const double w0 = 1 - b[0] - b[1];
        const double u = w0 * uv->Get(c[0], 0) + b[0] * uv->Get(c[1], 0) + b[1] * uv->Get(c[2], 0);
        const double v = w0 * uv->Get(c[0], 1) + b[0] * uv->Get(c[1], 1) + b[1] * uv->Get(c[2], 1);
        sum = sum + texture.Sample(use.emissiveUv.Apply(u, v)) * float(a / 4);
      }
      area += a;
    }
    m.emission = m.emission * (area > 0 ? sum * float(1 / area) : Rgb{});
    return AppendMaterial(m);
  }
  double TriangleArea(uint32_t a, uint32_t b, uint32_t c) const {
    const Position &p = builder_.position(a), &q = builder_.position(b), &r = builder_.position(c);
    const double e[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, f[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    const double x = e[1] * f[2] - e[2] * f[1], y = e[2] * f[0] - e[0] * f[2], z = e[0] * f[1] - e[1] * f[0];
    return 0.5 * std::sqrt(x * x + y * y + z * z);
  }

  std::string path_;
  LoadOptions options_;
  LoadedScene result_;
  SceneBuilder builder_;
  tg::Model model_;
  std::map<int, std::string> imageBytes_;
  WarningLog warnings_;
  std::vector<std::pair<AnalyticLight, Position>> lights_;  // KHR_lights_punctual, with world positions [m]
  std::string firstIgnored_;  // the first primitive of points or lines, for the message refusing an empty scene
  std::optional<uint32_t> defaultMaterial_;
  std::unordered_map<int, MaterialUse> materials_;           // glTF material -> ours
  std::unordered_map<int, std::optional<int>> textureOfImage_;  // glTF image -> Scene::textures index
  std::unordered_map<int, uint32_t> objectOfNode_;           // glTF node -> Scene::objectNames index
  std::unordered_map<uint32_t, uint32_t> untextured_;        // textured material -> UntexturedVariant
};

}  // namespace

LoadedScene LoadGltf(const std::string& path, const LoadOptions& options) { return GltfReader(path, options).Read(); }

}  // namespace pb
