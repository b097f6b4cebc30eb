// Reads Wavefront MTL material libraries into Materials (mesh/scene.h): dimensionless reflectances in [0, 1] per
// channel, emitted radiance Ke in W/(m^2 sr), and the albedo texture.
//
// Read: newmtl, Kd, Ke, Ks, Tf, Ni, d, Tr (= 1 - d), illum, map_Kd (a PNG, JPEG, TGA or BMP albedo, with its -s,
// -o and -clamp options). Everything else is ignored, with one warning per kind (counted, with its first
// file:line): Ka, Ns and the other statements a diffuse baker has no use for (a malformed value there is a
// warning too), the PBR extension (Pr, Pm, Ps, Pc, Pcr, aniso, anisor, norm), Kt, Km, sharpness, the other
// map_* and map_Kd options, extra values after a scalar ("Tr 0  illum 2"), and text before the first newmtl.
//
// The material class (mesh/scene.h) comes from illum:
//   0-2 (and 10, with a warning): diffuse Kd. A Phong highlight Ks under illum 2 is not used.
//   3, 5, 8: mirror: Kd plus an ideal mirror of reflectance Ks (default 1). When Kd + Ks > 1 in a channel, as
//            Blender writes for any metal (illum 3, Kd 0.8, Ks 0.5, rough or smooth), the mirror would create
//            energy: the material is baked as its diffuse part Kd, with a warning.
//   4, 6, 7, 9: glass: index Ni (default 1.5), transmittance Tf, or else 1 - d (default clear).
// Reflectance above 0.99 in any channel (Kd, or Kd + Ks for a mirror) is scaled down to 0.99 with a warning: a
// surface that absorbs nothing would never end a path in a closed scene.
//
// Textures: the file is found as exporters write its name (mesh/input_file.h, FindNamedFile: '\' separators,
// letter case, absolute paths from another machine); an image that several materials name is decoded once. A
// texture that cannot be found is a warning: the material keeps its Kd (grey 0.8 when it has none).
//
// Errors (InputError, "file:line: error: ..."), for what would make the light wrong: a malformed or non-finite
// number in Kd, Ke, Ks, Tf, Ni, d, Tr or illum; Kd outside [0, 1]; a negative Ke; glass with Ni outside (0, 10]
// or Tf, d outside [0, 1]; a material defined twice; a texture that exists but cannot be decoded.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "mesh/scene.h"
#include "mesh/text_lines.h"

namespace pb {

// The albedo of faces that have no material, or name one that no library defines: grey, as Blender shows them.
inline constexpr float kDefaultAlbedo = 0.8f;

// The materials read so far, which each library adds to.
struct MaterialTable {
  std::vector<Material>& materials;
  std::unordered_map<std::string, uint32_t>& byName;
  std::vector<Texture>& textures;
  WarningLog& warnings;
};

// Reads the MTL file at `path` into `table`. InputError as listed above; a file that cannot be opened too.
void LoadMtl(const std::string& path, MaterialTable table);

}  // namespace pb
