#include "baker/3_path_end_light.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "baker/3_contributions.h"

namespace pb {

// A tabled surface's lattice: nodes lo + (i, j) spacing, i in [0, nu], j in [0, nv]; cell (i, j) has nodes (i, j)
// to (i + 1, j + 1).
struct PathEndLight::Lattice {
  Point2 lo{};
  float spacing = 0;
  int nu = 0, nv = 0;
  std::vector<uint8_t> whole;             // per cell: wholly on the surface
  std::vector<Rgb> nodes;                 // (nu + 1) x (nv + 1), row by row
  int tilesU = 0;
  std::unique_ptr<std::once_flag[]> filled;  // per tile
  int NodeRow() const { return nu + 1; }
  bool Whole(int i, int j) const { return i >= 0 && j >= 0 && i < nu && j < nv && whole[size_t(j) * nu + i]; }
};

// A pooled triangle's estimate at its corners.
struct PathEndLight::Corners {
  std::once_flag filled;
  std::array<Rgb, 3> light;
  bool interpolated = false;  // small enough against the pooled reach
};

PathEndLight::PathEndLight(const PreparedScene& scene, const PhotonIrradiance& photons)
    : scene_(scene), photons_(photons), smooth_(photons.KernelEstimates()),
      latticeOnce_(new std::once_flag[scene.surfaces.surfaces.size()]), lattices_(scene.surfaces.surfaces.size()),
      pooledSlot_(scene.surfaces.surfaceOfTriangle.size(), UINT32_MAX) {
  uint32_t pooled = 0;
  for (size_t t = 0; t < pooledSlot_.size(); ++t)
    if (photons.Pooled(scene.surfaces.surfaceOfTriangle[t])) pooledSlot_[t] = pooled++;
  corners_.reset(new Corners[pooled]);
  // The plan: the surfaces of fewest cells first (then by index) within kMaxTableCells.
  std::vector<std::pair<size_t, uint32_t>> cells;
  for (uint32_t s = 0; s < lattices_.size(); ++s)
    if (const Shape shape = ShapeOf(s); shape.nu > 0) cells.push_back({size_t(shape.nu) * size_t(shape.nv), s});
  std::sort(cells.begin(), cells.end());
  tabled_.assign(lattices_.size(), 0);
  size_t total = 0;
  for (const auto& [c, s] : cells) {
    if ((total += c) > kMaxTableCells) break;
    tabled_[s] = 1;
  }
}

PathEndLight::Shape PathEndLight::ShapeOf(uint32_t s) const {
  if (!smooth_ || photons_.Pooled(s)) return {};
  const Bounds2 b = scene_.regions[s]->Bounds();
  const float spacing = photons_.Bandwidth(s) / float(kNodesPerH);
  const double nu = std::ceil((double(b.hi.u) - b.lo.u) / spacing), nv = std::ceil((double(b.hi.v) - b.lo.v) / spacing);
  if (!(spacing > 0 && nu >= 1 && nv >= 1 && nu * nv <= double(kMaxCells))) return {};
  return {spacing, int(nu), int(nv)};
}

PathEndLight::~PathEndLight() = default;

// The lattice of h / kNodesPerH over a tabled surface's chart, and which of its cells lie wholly on the surface.
PathEndLight::Lattice& PathEndLight::LatticeOf(uint32_t s) const {
  std::call_once(latticeOnce_[s], [&] {
    auto lattice = std::make_unique<Lattice>();
    const SurfaceRegion& region = *scene_.regions[s];
    const Shape shape = ShapeOf(s);
    Lattice& l = *lattice;
    l.lo = region.Bounds().lo, l.spacing = shape.spacing, l.nu = shape.nu, l.nv = shape.nv;
    const std::vector<double> areas = region.GridOverlapAreas(l.lo, l.spacing, l.nu, l.nv);
    const double whole = 0.999 * double(l.spacing) * l.spacing;
    l.whole.resize(areas.size());
    std::transform(areas.begin(), areas.end(), l.whole.begin(), [&](double a) { return uint8_t(a >= whole); });
    l.nodes.resize(size_t(l.nu + 1) * size_t(l.nv + 1));
    l.tilesU = l.nu / kTile + 1;
    l.filled.reset(new std::once_flag[size_t(l.tilesU) * size_t(l.nv / kTile + 1)]);
    lattices_[s] = std::move(lattice);
  });
  return *lattices_[s];
}

// The nodes of tile (tu, tv) that are a corner of a cell wholly on the surface.
void PathEndLight::FillTile(Lattice& l, uint32_t s, int tu, int tv) const {
  for (int j = tv * kTile; j < std::min((tv + 1) * kTile, l.nv + 1); ++j)
    for (int i = tu * kTile; i < std::min((tu + 1) * kTile, l.nu + 1); ++i)
      if (l.Whole(i - 1, j - 1) || l.Whole(i, j - 1) || l.Whole(i - 1, j) || l.Whole(i, j))
        l.nodes[size_t(j) * l.NodeRow() + i] =
            photons_.ChartDensity(s, {l.lo.u + float(i) * l.spacing, l.lo.v + float(j) * l.spacing});
}

Rgb PathEndLight::Node(Lattice& l, uint32_t s, int i, int j) const {
  const int tu = i / kTile, tv = j / kTile;
  std::call_once(l.filled[size_t(tv) * l.tilesU + tu], [&] { FillTile(l, s, tu, tv); });
  return l.nodes[size_t(j) * l.NodeRow() + i];
}

Rgb PathEndLight::ChartDensity(uint32_t s, Point2 uv) const {
  if (direct_ || !tabled_[s]) return photons_.ChartDensity(s, uv);
  Lattice& l = LatticeOf(s);
  const float fu = (uv.u - l.lo.u) / l.spacing, fv = (uv.v - l.lo.v) / l.spacing;
  const int i = int(std::floor(fu)), j = int(std::floor(fv));
  if (!l.Whole(i, j)) return photons_.ChartDensity(s, uv);
  const float a = fu - float(i), b = fv - float(j);
  return Node(l, s, i, j) * ((1 - a) * (1 - b)) + Node(l, s, i + 1, j) * (a * (1 - b)) +
         Node(l, s, i, j + 1) * ((1 - a) * b) + Node(l, s, i + 1, j + 1) * (a * b);
}

Rgb PathEndLight::Pooled(uint32_t triangle, float b1, float b2) const {
  const Scene& mesh = scene_.scene;
  const Normal3 normal = mesh.FrontNormal(triangle);
  const auto at = [&](float u, float v) { return photons_.PooledAt(mesh.PointAt(triangle, u, v), normal).irradiance; };
  const uint32_t slot = pooledSlot_[triangle];
  if (slot == UINT32_MAX || direct_) return at(b1, b2);
  Corners& c = corners_[slot];
  std::call_once(c.filled, [&] {
    float longest = 0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, Length(mesh.Corner(triangle, (k + 1) % 3) - mesh.Corner(triangle, k)));
    c.interpolated = longest <= 0.5f * photons_.PooledRadius();
    if (c.interpolated)
      for (int k = 0; k < 3; ++k) c.light[size_t(k)] = photons_.PooledAt(mesh.Corner(triangle, k), normal).irradiance;
  });
  if (!c.interpolated) return at(b1, b2);
  return c.light[0] * (1 - b1 - b2) + c.light[1] * b1 + c.light[2] * b2;
}

}  // namespace pb
