// --preview FILE.png: the baked mesh as a viewer shows it, with no further lighting. Seen through the scene's
// pinhole camera (mesh/camera.h), each pixel shows the display colours of the PLY's vertices (8-bit sRGB, the
// tone curve of baker/tone_map.h at the bake's exposure) interpolated across the triangle under it, as MeshLab or
// Blender interpolate vertex colours; both sides of a face show its colours. 2 x 2 samples per pixel, averaged in
// the encoded values as a viewer's multisampling does. Pixels that see no surface are black.
#pragma once

#include <string>

#include "baker/files/atomic_file.h"
#include "baker/baked_mesh.h"
#include "baker/runtime/progress.h"
#include "mesh/camera.h"

namespace pb {

struct PreviewSettings {
  Camera camera;         // in world coordinates [m]
  int width = 640;       // pixels; range [1, 8192]
  int height = 480;
  float exposure = 1;    // the PLY's display exposure
};

// Stages the PNG at `path` in `outputs`. Rays are traced against the baked mesh itself (its own Embree scene).
void WritePreview(OutputFiles& outputs, const std::string& path, const BakedMesh& baked, const PreviewSettings& settings,
                  const Log& log);

}  // namespace pb
