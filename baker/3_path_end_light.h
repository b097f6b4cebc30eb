// Stage 3: the photons' light where gathered paths end (baker/3_gap_gather.h), read from tables filled as the
// paths first reach them, so that a path's last hit costs a lookup rather than a density estimate. On the
// staircase at the defaults the estimates at paths' ends took a third of the estimate stage and three fifths of
// the small surfaces gathered after the rounds.
//   - On a surface with its own kernel estimate: H per unit (u,v) area [W/m^2 of (u,v)] at the nodes of a lattice
//     of h / kNodesPerH over the surface's chart, computed a tile of kTile x kTile nodes at a time, the first time a
//     path needs one. A hit in a lattice cell that lies wholly on the surface (SurfaceRegion::GridOverlapAreas)
//     reads the bilinear interpolation of the cell's four nodes: the estimate is a kernel average, smooth on the
//     scale of h, so the interpolation's error is second order in h / kNodesPerH. A hit in any other cell (at the
//     surface's outline, within a cell of it) reads the estimate itself.
//   - On a pooled surface (estimators/pooled_estimator.h): the pooled estimate [W/m^2] at the hit triangle's three
//     corners, with its front normal, interpolated by the hit's barycentric coordinates, where the triangle's
//     longest edge is at most half the pooled reach; elsewhere the estimate itself.
// Each table entry is a pure function of the photons and the scene, computed once (std::call_once), so a hit reads
// the same value whichever thread filled the entry and in whatever order: the bake's bytes do not depend on the
// threads. The lattices are planned when the tables are made, the surfaces of fewest cells first, so that all of
// them together hold at most kMaxTableCells cells (about 110 MB, whichever surfaces the paths reach): a surface
// past that, or whose own lattice would pass kMaxCells cells, is read directly, as are the histogram and
// nearest-neighbour estimators (not smooth).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "mesh/color.h"
#include "mesh/geometry.h"

namespace pb {

class PhotonIrradiance;

class PathEndLight {
 public:
  static constexpr int kNodesPerH = 4;   // lattice nodes per h
  static constexpr int kTile = 8;        // nodes on a tile's side
  static constexpr size_t kMaxCells = size_t(1) << 18;       // a surface's: 3 MB of nodes
  static constexpr size_t kMaxTableCells = size_t(1) << 23;  // all surfaces'

  // Both must outlive this.
  PathEndLight(const PreparedScene& scene, const PhotonIrradiance& photons);
  ~PathEndLight();
  PathEndLight(const PathEndLight&) = delete;
  PathEndLight& operator=(const PathEndLight&) = delete;

  // The photons' estimate on surface s (not pooled) at chart point uv [W/m^2 of (u,v)].
  Rgb ChartDensity(uint32_t s, Point2 uv) const;
  // The pooled estimate on `triangle` (of a pooled surface) at barycentric (b1, b2) [W/m^2].
  Rgb Pooled(uint32_t triangle, float b1, float b2) const;
  // Both read the estimate itself, as without tables, or the tables again. Not while they are read.
  void ReadDirectly(bool direct) { direct_ = direct; }

 private:
  struct Lattice;
  struct Corners;
  // Surface s's lattice spacing [m] and cells, or none (nu = 0) where it is read directly whatever the plan.
  struct Shape {
    float spacing = 0;
    int nu = 0, nv = 0;
  };
  Shape ShapeOf(uint32_t s) const;
  Lattice& LatticeOf(uint32_t s) const;
  void FillTile(Lattice& lattice, uint32_t s, int tu, int tv) const;
  Rgb Node(Lattice& lattice, uint32_t s, int i, int j) const;

  const PreparedScene& scene_;
  const PhotonIrradiance& photons_;
  bool smooth_;  // the photons' estimate is a kernel's
  bool direct_ = false;
  std::vector<uint8_t> tabled_;  // per surface: within the plan
  // Per tabled surface, made the first time a path ends on it.
  std::unique_ptr<std::once_flag[]> latticeOnce_;
  mutable std::vector<std::unique_ptr<Lattice>> lattices_;
  std::vector<uint32_t> pooledSlot_;                 // per triangle: its Corners, or UINT32_MAX
  std::unique_ptr<Corners[]> corners_;
};

}  // namespace pb
