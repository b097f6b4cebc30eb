#include "baker/5_write_gltf.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

#include "baker/files/gltf_buffers.h"
#include "baker/tone_map.h"
#include "mesh/errors.h"

namespace pb {
namespace {

namespace tg = tinygltf;

// The triangles of one (object, material) pair, with their own vertex numbering.
struct Group {
  uint32_t object = 0, material = 0;
  std::vector<uint32_t> vertices;              // baked mesh vertices, in order of first use
  std::vector<std::array<uint32_t, 3>> faces;  // indices into `vertices`
};

std::vector<Group> GroupFaces(const BakedMesh& baked, const SurfaceNames& names) {
  std::vector<Group> groups;
  std::map<std::pair<uint32_t, uint32_t>, size_t> groupOf;
  std::vector<uint32_t> local(baked.mesh.VertexCount(), ~0u);
  for (const std::array<uint32_t, 3>& f : baked.mesh.faces) {
    const uint32_t s = baked.mesh.surface[f[0]];
    const auto key = std::pair{names.objectOfSurface[s], names.materialOfSurface[s]};
    const auto [it, isNew] = groupOf.emplace(key, groups.size());
    if (isNew) groups.push_back({key.first, key.second, {}, {}});
    Group& g = groups[it->second];
    std::array<uint32_t, 3> corners{};
    for (int k = 0; k < 3; ++k) {
      if (local[f[k]] == ~0u) {  // a vertex belongs to one surface, so to one group
        local[f[k]] = uint32_t(g.vertices.size());
        g.vertices.push_back(f[k]);
      }
      corners[k] = local[f[k]];
    }
    g.faces.push_back(corners);
  }
  return groups;
}

std::array<float, 3> Array(Rgb c) { return {c.r, c.g, c.b}; }

// With --sh: _SH_R, _SH_G, _SH_B, each VEC4 (L00, L1x, L1y, L1z) of its channel (estimators/incident_moments.h).
void AddShAttributes(GltfBufferWriter& buffers, const BakedMesh& baked, const Group& g, tg::Primitive& primitive) {
  std::array<std::vector<std::array<float, 4>>, 3> channels;
  for (uint32_t v : g.vertices) {
    const ShL1& sh = baked.sh[v];
    channels[0].push_back({sh.c[0].r, sh.c[1].r, sh.c[2].r, sh.c[3].r});
    channels[1].push_back({sh.c[0].g, sh.c[1].g, sh.c[2].g, sh.c[3].g});
    channels[2].push_back({sh.c[0].b, sh.c[1].b, sh.c[2].b, sh.c[3].b});
  }
  primitive.attributes["_SH_R"] = buffers.Vec4(channels[0]);
  primitive.attributes["_SH_G"] = buffers.Vec4(channels[1]);
  primitive.attributes["_SH_B"] = buffers.Vec4(channels[2]);
}

tg::Primitive Primitive(GltfBufferWriter& buffers, const BakedMesh& baked, const Group& g, float exposure) {
  std::vector<std::array<float, 3>> position, normal, colour, irradiance, radiance, reflectance;
  for (uint32_t v : g.vertices) {
    const Point3 p = baked.mesh.positions[v];
    const Normal3 n = baked.mesh.normals[v];
    const float length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    position.push_back({p.x, p.y, p.z});
    normal.push_back(length > 0 ? std::array<float, 3>{n.x / length, n.y / length, n.z / length}
                                : std::array<float, 3>{0, 0, 1});
    const Rgb L = baked.Radiance(v);
    colour.push_back(Array(ToneMapLinear(L, exposure)));
    irradiance.push_back(Array(baked.irradiance[v]));
    radiance.push_back(Array(L));
    reflectance.push_back(Array(baked.albedo[v]));
  }
  tg::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.material = int(g.material);
  primitive.attributes["POSITION"] = buffers.Vec3(position, true);
  primitive.attributes["NORMAL"] = buffers.Vec3(normal, false);
  primitive.attributes["COLOR_0"] = buffers.Vec3(colour, false);
  primitive.attributes["_IRRADIANCE"] = buffers.Vec3(irradiance, false);
  primitive.attributes["_RADIANCE"] = buffers.Vec3(radiance, false);
  primitive.attributes["_REFLECTANCE"] = buffers.Vec3(reflectance, false);
  if (!baked.sh.empty()) AddShAttributes(buffers, baked, g, primitive);
  primitive.indices = buffers.Indices(g.faces);
  return primitive;
}

tg::Material UnlitMaterial(const std::string& name) {
  tg::Material m;
  m.name = name;
  m.pbrMetallicRoughness.baseColorFactor = {1, 1, 1, 1};
  m.pbrMetallicRoughness.metallicFactor = 0;
  m.pbrMetallicRoughness.roughnessFactor = 1;
  m.extensions["KHR_materials_unlit"] = tg::Value(tg::Value::Object());
  return m;
}

tg::Model BuildModel(const BakedMesh& baked, const SurfaceNames& names, float exposure) {
  tg::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "photonbake " PB_VERSION;
  model.extensionsUsed = {"KHR_materials_unlit"};
  for (const std::string& name : names.materials) model.materials.push_back(UnlitMaterial(name));
  tg::Node root;
  root.name = names.scene;
  const std::array<double, 3>& o = baked.mesh.origin;
  if (o[0] != 0 || o[1] != 0 || o[2] != 0) root.translation = {o[0], o[1], o[2]};
  GltfBufferWriter buffers(model);
  std::map<uint32_t, int> meshOfObject;
  for (const Group& g : GroupFaces(baked, names)) {
    const auto [it, isNew] = meshOfObject.emplace(g.object, int(model.meshes.size()));
    if (isNew) {
      tg::Mesh mesh;
      mesh.name = names.objects[g.object];
      model.meshes.push_back(mesh);
      tg::Node node;
      node.name = mesh.name;
      node.mesh = it->second;
      root.children.push_back(int(model.nodes.size()));
      model.nodes.push_back(node);
    }
    model.meshes[size_t(it->second)].primitives.push_back(Primitive(buffers, baked, g, exposure));
  }
  model.nodes.push_back(root);
  tg::Scene scene;
  scene.name = names.scene;
  scene.nodes = {int(model.nodes.size() - 1)};
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  return model;
}

std::string BaseName(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const size_t dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

}  // namespace

SurfaceNames NamesOf(const Scene& scene, const SurfaceSet& surfaces) {
  SurfaceNames names{BaseName(scene.path), scene.objectNames, {}, {}, {}};
  for (const Material& m : scene.materials) names.materials.push_back(m.name);
  for (const Surface& s : surfaces.surfaces) {
    names.objectOfSurface.push_back(scene.triangles[s.triangles.front()].object);
    names.materialOfSurface.push_back(s.material);
  }
  for (std::string& object : names.objects)
    if (object.empty()) object = names.scene;  // OBJ faces before any 'o'
  return names;
}

void WriteGltf(OutputFiles& outputs, const std::string& path, const BakedMesh& baked, const SurfaceNames& names,
               float exposure) {
  WriteGltfModel(outputs, path, BuildModel(baked, names, exposure));
}

}  // namespace pb
