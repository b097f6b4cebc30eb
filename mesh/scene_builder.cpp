#include "mesh/scene_builder.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "mesh/errors.h"

namespace pb {
namespace {

bool IsDegenerate(const Position& a, const Position& b, const Position& c) {
  // In double, so that slivers of aspect ratio up to ~1e9 are kept and only zero-area faces are dropped.
  const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
  const double twiceArea = std::sqrt(cx * cx + cy * cy + cz * cz);
  const double longest2 = std::max({e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2],
                                    e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]});
  return !(twiceArea > 1e-18 * longest2) || twiceArea == 0.0;
}

}  // namespace

size_t SceneBuilder::KeyHash::operator()(const Key& k) const {
  size_t h = 0;
  for (const Position& p : k)
    for (double c : p) h = h * 1000003u ^ std::hash<double>()(c);
  return h;
}

// The triangle's corner positions, rotated so that the smallest comes first: equal for the same triangle facing
// the same way, whatever its vertex indices or starting corner; a back-to-back copy differs.
SceneBuilder::Key SceneBuilder::FaceKey(const Triangle& t) const {
  Key k{positions_[t.v[0]], positions_[t.v[1]], positions_[t.v[2]]};
  std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
  return k;
}

SceneBuilder::Outcome SceneBuilder::AddTriangle(const Triangle& t, uint32_t tag) {
  if (IsDegenerate(positions_[t.v[0]], positions_[t.v[1]], positions_[t.v[2]])) {
    ++scene_.degenerateTrianglesSkipped;
    return {Skipped::kZeroArea};
  }
  if (const auto [it, isNew] = kept_.emplace(FaceKey(t), tag); !isNew) {
    ++scene_.duplicateTrianglesSkipped;
    return {Skipped::kRepeat, it->second};
  }
  scene_.triangles.push_back(t);
  return {};
}

void SceneBuilder::StorePositions(const std::string& path) {
  Position lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Position& p : positions_)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  double size = 0, distance = 0;
  Position centre{};
  for (int k = 0; k < 3; ++k) {
    centre[k] = 0.5 * (lo[k] + hi[k]);
    size = std::max(size, hi[k] - lo[k]);
    distance = std::max(distance, std::abs(centre[k]));
  }
  if (size > kMaxSceneSize)
    throw InputError(path, 0, fmt::format("the scene is {:.3g} m across, more than the {:.0e} m within which its areas "
                                          "stay finite in float; bake it with --scale", size, kMaxSceneSize));
  if (distance > size) scene_.origin = centre;
  scene_.positions.reserve(positions_.size());
  for (const Position& p : positions_) scene_.positions.push_back(scene_.ToLocal(p[0], p[1], p[2]));
  kept_.clear();
  DropTrianglesWithoutAFloatNormal();
}

// Its corners in float may meet (a triangle of 1e-6 m 1 km from the origin) or its area vector's squared length
// underflow (below 1e-19 m^2 of area): its normal would be NaN, so it is dropped as zero-area, as in double.
void SceneBuilder::DropTrianglesWithoutAFloatNormal() {
  size_t kept = 0;
  for (size_t t = 0; t < scene_.triangles.size(); ++t) {
    const float squared = LengthSquared(scene_.AreaVector(uint32_t(t)));
    if (std::isnormal(squared)) scene_.triangles[kept++] = scene_.triangles[t];
  }
  scene_.degenerateTrianglesSkipped += uint32_t(scene_.triangles.size() - kept);
  scene_.triangles.resize(kept);
}

}  // namespace pb
