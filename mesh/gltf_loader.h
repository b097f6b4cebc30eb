// Loads a triangle Scene from glTF 2.0 (Khronos, "glTF 2.0 Specification"): a .gltf with its buffers and images
// (external files or data URIs), or a binary .glb; told apart by the file's first bytes. Parsed by tinygltf
// (libtinygltf-dev 2.7), through our own file reading (mesh/input_file.h) and image decoding (mesh/texture.h);
// every accessor is bounds-checked here, since tinygltf does not.
//
// Geometry. The default scene's node hierarchy (every root node when the file has no scene); each node's matrix,
// or its translation, rotation and scale, composed from the root. glTF's unit is the metre; positions are then
// multiplied by LoadOptions::scale. Under a transform of negative determinant (a mirrored node) the triangles'
// winding is reversed, so their front side stays the side glTF means. Primitives of mode TRIANGLES,
// TRIANGLE_STRIP and TRIANGLE_FAN are read (POSITION, indices, TEXCOORD_n where a texture needs it); points and
// lines are skipped with a warning, and so are skins and morph targets (the mesh is baked as stored). Objects are
// named after their node (else their mesh, else "node N"). Zero-area and repeated triangles are dropped as for
// OBJ (mesh/scene_builder.h).
//
// Materials, onto the classes of mesh/scene.h (every factor linear, every texture sRGB-decoded to linear):
//   - diffuse: Kd = baseColorFactor x baseColorTexture (alpha ignored);
//   - mirror: metallicFactor m > 0 and roughnessFactor <= 0.1: Ks = m x baseColorFactor and Kd = (1 - m) x base
//     colour. A rough metal is diffuse with Kd = base colour, with a warning: the paper's materials have no glossy
//     lobe, and a diffuse Kd keeps the energy it reflects;
//   - glass: KHR_materials_transmission with transmissionFactor t > 0: Tf = t x baseColorFactor, Ni =
//     KHR_materials_ior's ior (1.5 when absent); a rough one is read as smooth, with a warning;
//   - emission: Ke = emissiveFactor x KHR_materials_emissive_strength [W/(m^2 sr)] (glTF gives emission no unit;
//     this is the one OBJ's Ke has), times emissiveTexture's mean over the primitive, with a warning (a light has
//     one radiance);
//   - KHR_texture_transform (offset, rotation, scale, texCoord) is applied to the texture coordinates as they are
//     read. Wrap modes REPEAT and CLAMP_TO_EDGE (on both axes) are honoured; others are read as REPEAT, with a
//     warning. Note that glTF's v runs down the image: a glTF (u, v) is our (s, t) = (u, 1 - v).
//   - ignored, with a warning: normal, occlusion and metallic-roughness textures, alpha (BLEND, MASK),
//     KHR_materials_unlit (read as diffuse), and any other material extension.
// Lights (KHR_lights_punctual): a node's point, spot or directional light sits at the node's origin and points
// along its -z axis; intensity (candela for point and spot, lux for directional) times color is divided by
// LoadOptions::luminousEfficacy [lm/W] into I [W/sr] or E [W/m^2] (mesh/scene.h). range is ignored, with a
// warning (our lights fall off with the inverse square everywhere); a spot's cone angles must satisfy
// 0 <= inner < outer <= pi/2.
// A primitive without a material is grey Kd 0.8 (kDefaultAlbedo), as in the OBJ loader. An image that cannot be
// found is a warning (its material keeps its factor); one that cannot be decoded is an error.
//
// Errors (InputError, "file: error: JSON-path: ..."): a file tinygltf cannot parse, an extension the file
// requires that is not read here (Draco, meshopt, quantized meshes), an index out of range, an accessor of the
// wrong type or beyond its buffer view, a buffer view beyond its buffer, a sparse accessor, a non-finite position
// or transform, a node that is its own ancestor, and a scene with no triangle.
#pragma once

#include <string>

#include "mesh/scene_file.h"

namespace pb {

LoadedScene LoadGltf(const std::string& path, const LoadOptions& options = {});

}  // namespace pb
