// Where a surface's cover can change (estimators/surface_cover.h, "Where the rays are cast"): the lattice cells that
// the slab's cut of every other triangle near the surface (one Embree point query per square tile of the chart),
// and the surface's own boundary edges, touch. The cover's builder casts its rays only at those cells' corners.
// Chart lengths [m]; the lattice's points are lo + (i, j) s, its cells [i, i + 1] x [j, j + 1] keyed j * nu + i.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/geometry.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

struct CoverLattice {
  Point2 lo;
  float spacing = 0;  // s
  int nu = 0, nv = 0;  // points per axis
  uint64_t Key(int i, int j) const { return uint64_t(j) * uint64_t(nu) + uint64_t(i); }
  Point2 Point(int i, int j) const { return {lo.u + float(i) * spacing, lo.v + float(j) * spacing}; }
};

// The surface whose cover is found (surfaces.surfaces[index]), and the scene around it.
struct CoverSurface {
  const Scene& scene;
  const SurfaceSet& surfaces;
  const RayScene& rays;
  uint32_t index;
};

// The cells of the surface's lattice where its cover can change; `chartBox` bounds its chart. Unsorted, with
// repeats.
std::vector<uint64_t> CellsWhereTheCoverCanChange(const CoverSurface& surface, const CoverLattice& lattice,
                                                  const Bounds2& chartBox);

}  // namespace pb
