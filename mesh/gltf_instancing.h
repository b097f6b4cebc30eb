// How far a glTF node hierarchy expands before any of it is built: EXT_mesh_gpu_instancing's instances (each the
// node's mesh again, at the node's world transform times the instance's own translation [m, the node's space],
// rotation and scale), and the triangles of every mesh a walk meets, so that a small file whose shared nodes or
// instances multiply into billions of triangles is refused by its size, not by the memory it would fill.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/gltf_accessor.h"

namespace pb::gltf {

// The most triangles a glTF scene may expand to through shared nodes and instances (about 20 GB of bake).
inline constexpr uint64_t kMaxExpandedTriangles = uint64_t(1) << 26;
// The most nodes a walk of the hierarchy may visit (a node shared by two parents is visited twice).
inline constexpr uint64_t kMaxNodeVisits = uint64_t(1) << 20;

// How many times node n draws its mesh: 1 without EXT_mesh_gpu_instancing, else its attributes' element count
// (the largest, unchecked here: InstanceTransforms checks them).
uint64_t InstanceCount(const tinygltf::Model& model, const tinygltf::Node& n);

// The transforms of node n's instances relative to the node: T R S per instance, or the identity alone without the
// extension. A non-finite value, attributes of different counts, or no attribute at all is an InputError at `where`.
std::vector<Matrix> InstanceTransforms(const tinygltf::Model& model, const tinygltf::Node& n, const std::string& where,
                                       const std::string& file);

// The triangles mesh `mesh` declares (its indices' or positions' count: n / 3 for lists, n - 2 for strips and
// fans), read from the accessors' counts without touching their data; 0 for a mesh that does not exist.
uint64_t MeshTriangles(const tinygltf::Model& model, int mesh);

}  // namespace pb::gltf
