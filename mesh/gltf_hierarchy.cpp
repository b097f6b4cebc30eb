#include "mesh/gltf_hierarchy.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "mesh/errors.h"
#include "mesh/memory_budget.h"

namespace pb::gltf {
namespace {

namespace tg = tinygltf;

constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";
constexpr const char* kAttributes[] = {"TRANSLATION", "ROTATION", "SCALE"};

// The accessor index of instancing attribute `name`, or -1.
int AttributeAccessor(const tg::Node& n, const char* name) {
  const auto it = n.extensions.find(kInstancing);
  if (it == n.extensions.end() || !it->second.Has("attributes")) return -1;
  const tg::Value& attributes = it->second.Get("attributes");
  if (!attributes.IsObject() || !attributes.Has(name) || !attributes.Get(name).IsNumber()) return -1;
  return attributes.Get(name).GetNumberAsInt();
}

uint64_t AccessorCount(const tg::Model& model, int accessor) {
  return accessor >= 0 && size_t(accessor) < model.accessors.size() ? uint64_t(model.accessors[size_t(accessor)].count) : 0;
}

// Element i of an accessor as `components` doubles, each finite.
std::vector<double> Element(const Accessor& a, size_t i, int components, const std::string& where, const std::string& file) {
  std::vector<double> values(static_cast<size_t>(components));
  for (int k = 0; k < components; ++k) {
    values[size_t(k)] = a.Get(i, k);
    if (!std::isfinite(values[size_t(k)])) throw InputError(file, 0, fmt::format("{}: instance {} is not finite", where, i));
  }
  return values;
}

// What a triangle of the scene takes in a bake, all stages: a bake of a million-triangle gridded room at 200,000
// photons peaked at 387 MB, about 100 MB of it the process's own.
constexpr double kBakeBytesPerTriangle = 300;

// A scene that expands through instances and shared nodes past what this process may hold is refused before its
// triangles are built (mesh/memory_budget.h), naming the file and the figure: 66.6M triangles read from a 12 MB
// file exhausted the memory late.
void RequireSceneMemory(uint64_t triangles, const std::string& file) {
  RequireMemory(file, double(triangles) * kBakeBytesPerTriangle,
                fmt::format("the scene's {} triangles (after its instances and shared nodes, about {:.0f} bytes each in "
                            "a bake)", triangles, kBakeBytesPerTriangle));
}

[[noreturn]] void Fail(const std::string& file, const std::string& where, const std::string& message) {
  throw InputError(file, 0, where + ": " + message);
}

// The default scene's root nodes; with no scene, every node that is no other node's child.
std::vector<int> Roots(const tg::Model& model, const std::string& file) {
  if (!model.scenes.empty()) {
    const int s = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (size_t(s) >= model.scenes.size()) Fail(file, "/scene", fmt::format("scene {} does not exist", s));
    return model.scenes[size_t(s)].nodes;
  }
  std::vector<bool> child(model.nodes.size());
  for (const tg::Node& n : model.nodes)
    for (int c : n.children)
      if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = true;
  std::vector<int> roots;
  for (size_t i = 0; i < child.size(); ++i)
    if (!child[i]) roots.push_back(int(i));
  return roots;
}

Matrix LocalMatrix(const tg::Node& n, const std::string& file, const std::string& where) {
  Matrix m = kIdentity;
  if (n.matrix.size() == 16) {
    std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
  } else {
    m = FromTrs(n.translation, n.rotation, n.scale);
  }
  for (double x : m)
    if (!std::isfinite(x)) Fail(file, where, "the node's transform is not finite");
  return m;
}

}  // namespace

std::vector<std::pair<int, Matrix>> SceneNodes(const tg::Model& model, const std::string& file) {
  uint64_t visits = 0, triangles = 0;
  std::vector<std::pair<int, Matrix>> found;
  struct Visit {
    int node;
    Matrix parent;
    size_t depth;
  };
  std::vector<Visit> stack;
  const std::vector<int> roots = Roots(model, file);
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, kIdentity, 0});
  std::vector<int> path;                             // the nodes from the root to the current one
  std::vector<char> onPath(model.nodes.size(), 0);  // whether a node is on `path`: a chain 700,000 deep stays linear
  while (!stack.empty()) {
    const Visit v = stack.back();
    stack.pop_back();
    for (; path.size() > v.depth; path.pop_back()) onPath[size_t(path.back())] = 0;
    const std::string where = fmt::format("/nodes/{}", v.node);
    if (v.node < 0 || size_t(v.node) >= model.nodes.size())
      Fail(file, where, fmt::format("node {} does not exist ({} nodes)", v.node, model.nodes.size()));
    if (onPath[size_t(v.node)]) Fail(file, where, "the node is its own ancestor");
    path.push_back(v.node), onPath[size_t(v.node)] = 1;
    const tg::Node& n = model.nodes[size_t(v.node)];
    if (++visits > kMaxNodeVisits)
      Fail(file, where, fmt::format("the scene's hierarchy visits more than {} nodes (nodes shared by many parents)",
                                    kMaxNodeVisits));
    const uint64_t meshTriangles = MeshTriangles(model, n.mesh), instances = InstanceCount(model, n);
    if (instances != 0 && meshTriangles > (kMaxExpandedTriangles - triangles) / instances)
      Fail(file, where, fmt::format("the scene expands to more than {} triangles through shared nodes and instances",
                                    kMaxExpandedTriangles));
    triangles += meshTriangles * instances;
    const Matrix world = Multiply(v.parent, LocalMatrix(n, file, where));
    if (n.mesh >= 0 || n.extensions.count("KHR_lights_punctual")) found.emplace_back(v.node, world);
    for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) stack.push_back({*c, world, v.depth + 1});
  }
  RequireSceneMemory(triangles, file);
  return found;
}

uint64_t InstanceCount(const tg::Model& model, const tg::Node& n) {
  if (!n.extensions.count(kInstancing)) return 1;
  uint64_t count = 0;
  for (const char* name : kAttributes) count = std::max(count, AccessorCount(model, AttributeAccessor(n, name)));
  return count;
}

std::vector<Matrix> InstanceTransforms(const tg::Model& model, const tg::Node& n, const std::string& where,
                                       const std::string& file) {
  if (!n.extensions.count(kInstancing)) return {kIdentity};
  const std::string self = where + "/extensions/" + kInstancing + "/attributes";
  std::vector<std::optional<Accessor>> attributes;
  size_t count = 0;
  for (const char* name : kAttributes) {
    const int index = AttributeAccessor(n, name);
    if (index < 0) {
      attributes.emplace_back();
      continue;
    }
    const bool rotation = std::string(name) == "ROTATION";
    attributes.emplace_back(Accessor(model, index, rotation ? 4 : 3,
                                     rotation ? std::initializer_list<int>{TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                                          TINYGLTF_COMPONENT_TYPE_BYTE,
                                                                          TINYGLTF_COMPONENT_TYPE_SHORT}
                                              : std::initializer_list<int>{TINYGLTF_COMPONENT_TYPE_FLOAT},
                                     self + "/" + name, file));
    if (count != 0 && attributes.back()->count() != count)
      throw InputError(file, 0, fmt::format("{}: {} has {} instances where the others have {}", self, name,
                                            attributes.back()->count(), count));
    count = attributes.back()->count();
  }
  if (count == 0) throw InputError(file, 0, self + ": no TRANSLATION, ROTATION or SCALE with any instance");
  std::vector<Matrix> transforms;
  transforms.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    std::vector<double> trs[3];
    for (int a = 0; a < 3; ++a)
      if (attributes[size_t(a)]) trs[a] = Element(*attributes[size_t(a)], i, a == 1 ? 4 : 3, self, file);
    transforms.push_back(FromTrs(trs[0], trs[1], trs[2]));
  }
  return transforms;
}

uint64_t MeshTriangles(const tg::Model& model, int mesh) {
  if (mesh < 0 || size_t(mesh) >= model.meshes.size()) return 0;
  uint64_t triangles = 0;
  for (const tg::Primitive& p : model.meshes[size_t(mesh)].primitives) {
    const auto position = p.attributes.find("POSITION");
    const uint64_t corners = AccessorCount(model, p.indices >= 0 ? p.indices : position == p.attributes.end() ? -1 : position->second);
    triangles += p.mode == TINYGLTF_MODE_TRIANGLES ? corners / 3 : corners > 2 ? corners - 2 : 0;
  }
  return triangles;
}

}  // namespace pb::gltf
