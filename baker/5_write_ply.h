// Stage 5: the baked mesh as a PLY file that MeshLab opens (DESIGN.md, "The output contract").
// Per vertex: x y z [m], nx ny nz, red green blue (uchar, tone-mapped radiance for display),
// irradiance_r/g/b [W/m^2], radiance_r/g/b [W/(m^2 sr)] = Le + R H / pi, quality (luminance of H [W/m^2]).
// Faces: the triangles, counter-clockwise seen from the front. Binary little-endian, or ASCII.
// (Stage 4, mesh refinement, sits between estimation and writing in a later issue.)
#pragma once

#include <optional>
#include <string>

#include "baker/files/atomic_file.h"
#include "baker/baked_mesh.h"

namespace pb {

struct PlyOptions {
  bool ascii = false;
  std::optional<float> exposure;  // display exposure; unset = AutoExposure
};

// The display exposure: the user's, or AutoExposure of the vertices' radiance.
float DisplayExposure(const BakedMesh& baked, std::optional<float> user);

// Returns the exposure used. Written atomically (baker/files/atomic_file.h).
float WritePly(OutputFiles& outputs, const std::string& path, const BakedMesh& baked, const PlyOptions& options);

}  // namespace pb
