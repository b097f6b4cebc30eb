// Where other geometry covers a planar surface: the part of its (u,v) chart [m] that light cannot reach because
// the surface runs inside or under another object (a block standing on a floor, a book lying on a table, a wall
// through the floor, a cupboard pushed against a wall). That part is not in the surface's estimation domain: it
// is a domain of its own, lit only by the photons that land in it (none, under a closed block), so no kernel
// carries light across the contact line, and the boundary correction applies along it (baker/0_prepare_scene.h).
//
// A chart point is covered when all but one of kCoverRays (estimators/cover_probe.h) fixed directions over its front hemisphere (a
// cosine-weighted spiral, the lowest 10 degrees above the plane) first meet the back of a triangle: the point lies
// inside a closed object. A front that another triangle's back touches counts as that back (a cabinet's side flush
// with a wall; estimators/cover_probe.h). The one spared ray forgives a crack in the object's mesh; a one-sided table top over a
// floor lets its grazing rays out, so the floor under it stays open. The test is made on a square lattice of
// spacing s [m] over the chart; points off the surface are open, so a contact line that reaches the surface's edge
// ends there. On each lattice edge whose ends differ, the change is found by bisection to s / 1024, and each
// lattice cell's covered part is the convex polygon through its covered corners and those crossings (marching
// squares; a cell covered on one diagonal only takes the two corners as joined). A straight contact line is thus
// found to s / 1024 whatever s; covered features narrower than s can be missed. Where the contact line turns a
// corner inside a cell (a block's corner), marching squares alone would cut it off (up to s^2 / 2 of area, which
// the local linear fit at the corner reads as unlit floor): the line's direction at each of the cell's two
// crossings is found by a second bisection s / 4 further into the cell, and the two lines' intersection is
// inserted as the corner, when it lies in the cell, is covered, and keeps the cell's polygon convex (after
// Kobbelt et al. 2001, "Feature sensitive surface extraction from volume data", SIGGRAPH). A reflex corner of
// the cover (an open notch) stays cut.
//
// Where the rays are cast. A point can change from open to covered only where an object crosses the surface's
// plane or hangs close over it (it passes through the slab of half-thickness r about the plane: the surface's own
// deviation from its mean plane, plus 2 s: a lamp 1 cm under a ceiling covers the ceiling behind it) or at the
// surface's edge. So the lattice is classified by rays only in a band about
// those lines: the cells that the slab's cut of every other triangle near the surface touches (projected into the
// chart; only its edges when it lies in the plane itself; found by one Embree point query per square tile of the
// chart, of side 16 s or the surface's mean triangle side, whichever is larger), and the cells its own boundary edges
// touch, each grown by one cell. Every other lattice point takes the class of the band point beside it in its
// row (open where the row has none: it reaches the lattice's rim, off the surface). The cost is linear in the
// triangles near the surface and in the length of those lines over s, not in the surface's area over s^2; a planar
// surface with nothing on it and a simple outline costs its outline. The covered points are kept as runs per row,
// so a cover's memory grows with its outline too, and its pieces merge whole cells into rectangles. An object
// that covers a surface from farther than r (a box with no bottom hovering over a floor) is not seen: covers are
// where objects stand on, pass through or hang close over a surface.
//
// Only planar, non-emissive surfaces at least 2 s wide each way are tested; a curved surface, a light or a
// narrower surface has an empty cover.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <unordered_map>
#include <vector>

#include "mesh/geometry.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"
#include "mesh/work_progress.h"

namespace pb {

struct CoverSettings {
  float spacing = 0.025f;            // s [m], the lattice spacing; 0 tests nothing (every cover is empty)
  // And at most this share of the diagonal of the scene's bounding box, so that the lattice scales with the scene;
  // 0: no such bound.
  double maxSpacingPerDiagonal = 0;
  // A surface whose lattice would have more points gets a coarser one: the spacing doubled until it fits.
  uint64_t maxPointsPerSurface = 1u << 20;
};

class SurfaceCover {
 public:
  bool Empty() const { return pieces_.empty(); }
  // Whether chart point uv is in the covered part (the pieces' union, for uv on the surface).
  bool Covered(Point2 uv) const;
  // The covered part as chart triangles [m], inside the surface's own chart triangles.
  const std::vector<Triangle2>& Pieces() const { return pieces_; }
  double Area() const;
  float Spacing() const { return spacing_; }
  // Lattice points classified by rays [count]: the band's (see the top), however empty the cover.
  uint64_t ProbedPoints() const { return probed_; }

 private:
  friend class CoverBuilder;
  friend class CoverPieces;
  // The covered polygon of lattice cell (i, j), counter-clockwise; empty when none of its corners is covered.
  // With the corner its contact line turns (corners_, or `corner` when given).
  std::vector<Point2> CellPolygon(int i, int j, const Point2* corner = nullptr) const;
  // A cell's lattice edges counter-clockwise from (i, j): ends, whether each is covered, the unit normal into the
  // cell, and where the cover changes along it (when the ends differ).
  struct CellEdge {
    Point2 a, b;
    bool coveredA, coveredB;
    Point2 inward;
    Point2 crossing;
  };
  std::array<CellEdge, 4> EdgesOf(int i, int j) const;
  bool InCell(Point2 uv, int i, int j) const;  // strictly inside cell (i, j)
  Point2 Lattice(int i, int j) const { return {lo_.u + float(i) * spacing_, lo_.v + float(j) * spacing_}; }
  bool CoveredPoint(int i, int j) const;
  // A row's covered points i in [first, last].
  struct Run {
    int first, last;
  };
  std::span<const Run> RowRuns(int j) const;
  static size_t EdgeKey(size_t point, int axis) { return point * 2 + size_t(axis); }
  // Lattice cells [i, i + 1] x [j, j + 1] as keys j * nu + i, and lattice points (i, j) alike.
  uint64_t Key(int i, int j) const { return uint64_t(j) * uint64_t(nu_) + uint64_t(i); }

  Point2 lo_;
  float spacing_ = 0;
  int nu_ = 0, nv_ = 0;             // lattice points per axis
  int firstRow_ = 0;                // the rows [firstRow_, firstRow_ + rowStart_.size() - 1) hold covered points
  std::vector<uint32_t> rowStart_;  // row firstRow_ + k's runs are runs_[rowStart_[k], rowStart_[k + 1])
  std::vector<Run> runs_;           // the covered lattice points, row by row (v outer), ascending
  // Per lattice edge whose ends differ (EdgeKey of its first end, axis 0: +u, 1: +v): where along it the cover
  // changes, as a fraction from its first end.
  std::unordered_map<size_t, float> crossing_;
  std::unordered_map<size_t, Point2> corners_;  // per cell (j * nu + i) whose contact line turns a corner in it
  std::vector<Triangle2> pieces_;
  uint64_t probed_ = 0;
};

// One cover per surface of `surfaces`. `advance`, when given, is told after each tested surface its number of
// triangles, and the number of all tested surfaces' triangles [count].
std::vector<SurfaceCover> FindCovers(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays,
                                     const CoverSettings& settings, const WorkProgress& advance = {});

}  // namespace pb
