// The nodes a glTF scene places, and how far its hierarchy expands, found before any geometry is built: the walk
// from the default scene's roots (or every node that is no other node's child), each node's world transform (its
// matrix, or T R S, composed from the root; in the file's units), EXT_mesh_gpu_instancing's instances (each the
// node's mesh again, at the node's world transform times the instance's own translation, rotation and scale), and
// the triangles every mesh met brings, so that a small file whose shared nodes or instances multiply into billions
// of triangles is refused by its size, not by the memory it would fill. Faults are InputErrors naming the file and
// the JSON path ("/nodes/3: ...").
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mesh/gltf_accessor.h"

namespace pb::gltf {

// Every node under the scene's roots that carries a mesh or a KHR_lights_punctual light, with its world transform,
// in the order of a depth-first walk (children in their order). Iterative, so a deep hierarchy cannot overflow the
// stack. Refused: a node that does not exist, a node that is its own ancestor, a non-finite transform, a default
// scene that does not exist, and a walk past kMaxNodeVisits nodes or kMaxExpandedTriangles triangles.
std::vector<std::pair<int, Matrix>> SceneNodes(const tinygltf::Model& model, const std::string& file);

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
