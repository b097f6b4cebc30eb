// Stage 5: the baked mesh as one glTF 2.0 file (Khronos, "glTF 2.0 Specification"): a binary .glb, or a .gltf
// whose buffer is embedded as a data URI, so that the output is a single file and one transaction. Written by
// tinygltf (libtinygltf-dev), staged through OutputFiles like every output.
//
// Structure: a root node named after the scene, translated to the mesh's origin (SplitMesh::origin [m], in
// double), so that positions far from the world origin keep their float precision; under it one node per input
// object (its name), holding a mesh with one triangle primitive per input material. Per vertex:
//   POSITION    [m], relative to the root node;
//   NORMAL      unit;
//   COLOR_0     the display colour: Reinhard's x / (1 + x) of the display exposure times the radiance L, per
//               channel, linear in [0, 1) as glTF requires (viewers encode it for the screen). The PLY's uchar
//               colours are the same curve, sRGB-encoded;
//   _IRRADIANCE H [W/m^2], _RADIANCE L = Le + R H / pi [W/(m^2 sr)], _REFLECTANCE R (dimensionless): float VEC3,
//               the physical values, under glTF's prefix for an application's own attributes.
// Materials: one per input material, named after it, marked unlit (KHR_materials_unlit) with base colour 1, so
// that viewers show COLOR_0 as it is, adding no light of their own. The Khronos glTF Validator accepts the files
// with no error or warning (tests/baker/gltf_output_test.cpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "baker/files/atomic_file.h"
#include "baker/baked_mesh.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

// What the glTF keeps of the input's structure: each surface's object and material, by name.
struct SurfaceNames {
  std::string scene;                     // the scene file's name without its folder and extension
  std::vector<std::string> objects;      // Scene::objectNames
  std::vector<std::string> materials;    // Scene::materials' names
  std::vector<uint32_t> objectOfSurface, materialOfSurface;
};
SurfaceNames NamesOf(const Scene& scene, const SurfaceSet& surfaces);

// Writes `path` (binary when it ends in .glb, else .gltf text; mesh/scene_file.h's HasGltfExtension tells -o's
// glTF outputs from PLY) with the display colours at `exposure`.
void WriteGltf(OutputFiles& outputs, const std::string& path, const BakedMesh& baked, const SurfaceNames& names,
               float exposure);

}  // namespace pb
