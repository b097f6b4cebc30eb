#include "baker/5_write_preview.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <memory>
#include <optional>

#include "baker/files/image_io.h"
#include "baker/tone_map.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"

namespace pb {
namespace {

// The baked mesh as a Scene of one material, so that RayScene can trace it.
Scene MeshScene(const SplitMesh& mesh) {
  Scene scene;
  scene.origin = mesh.origin;
  scene.positions = mesh.positions;
  scene.materials.push_back(Material{"preview"});
  scene.objectNames.push_back("");
  for (const auto& f : mesh.faces) scene.triangles.push_back(Triangle{f, {kNoTexcoord, kNoTexcoord, kNoTexcoord}, 0, 0, 0});
  return scene;
}

// Each vertex's display colour, as the encoded 8-bit values of the PLY, in floats for interpolation.
std::vector<std::array<float, 3>> DisplayColours(const BakedMesh& baked, float exposure) {
  std::vector<std::array<float, 3>> colours(baked.mesh.VertexCount());
  for (size_t v = 0; v < colours.size(); ++v) {
    const std::array<uint8_t, 3> c = ToneMap(baked.Radiance(v), exposure);
    colours[v] = {float(c[0]), float(c[1]), float(c[2])};
  }
  return colours;
}

}  // namespace

void WritePreview(OutputFiles& outputs, const std::string& path, const BakedMesh& baked, const PreviewSettings& s,
                  const Log& log) {
  const Scene scene = MeshScene(baked.mesh);
  const std::vector<std::array<float, 3>> colours = DisplayColours(baked, s.exposure);
  std::vector<uint8_t> rgb(size_t(s.width) * size_t(s.height) * 3, 0);
  if (!scene.triangles.empty()) {
    std::unique_ptr<Progress> build;  // a million triangles take a second or more
    const RayScene rays(scene, ShowProgress(&log, "preview bvh (thousandths)", build));
    build.reset();
    Progress rows(log, "preview (rows)", uint64_t(s.height));
    Camera local = s.camera;  // the mesh is traced in its local frame (mesh/scene.h, origin)
    local.position = scene.ToLocal(s.camera.position.x, s.camera.position.y, s.camera.position.z);
    local.lookAt = scene.ToLocal(s.camera.lookAt.x, s.camera.lookAt.y, s.camera.lookAt.z);
    const PinholeCamera camera(local, s.width, s.height);
    tbb::parallel_for(0, s.height, [&](int y) {
      for (int x = 0; x < s.width; ++x) {
        std::array<float, 3> sum{0, 0, 0};
        for (int k = 0; k < 4; ++k) {
          const float px = float(x) + 0.25f + 0.5f * float(k % 2), py = float(y) + 0.25f + 0.5f * float(k / 2);
          const std::optional<RayHit> hit = rays.Intersect(camera.Origin(), camera.Direction(px, py));
          if (!hit) continue;
          const auto& f = baked.mesh.faces[hit->triangle];
          const float b0 = 1 - hit->b1 - hit->b2;
          for (int c = 0; c < 3; ++c)
            sum[size_t(c)] += b0 * colours[f[0]][size_t(c)] + hit->b1 * colours[f[1]][size_t(c)] +
                              hit->b2 * colours[f[2]][size_t(c)];
        }
        for (int c = 0; c < 3; ++c)
          rgb[(size_t(y) * size_t(s.width) + size_t(x)) * 3 + size_t(c)] =
              uint8_t(std::clamp(std::lround(sum[size_t(c)] / 4), 0l, 255l));
      }
      rows.Advance(1);
    });
  }
  WritePngRgb8(outputs, path, s.width, s.height, rgb);
}

}  // namespace pb
