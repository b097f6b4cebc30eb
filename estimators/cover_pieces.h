// The covered part of a surface's cover (estimators/surface_cover.h) as chart triangles [m], from its lattice's
// classified points and the crossings on its changing edges: marching squares per cell, with the corner inserted
// where the contact line turns inside a cell (after Kobbelt et al. 2001, "Feature sensitive surface extraction from
// volume data", SIGGRAPH), each cell's polygon cut to the surface triangles its box meets.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "estimators/cover_probe.h"
#include "estimators/surface_cover.h"

namespace pb {

// A lattice edge from point (i, j) along +u (axis 0) or +v (axis 1).
struct LatticeEdge {
  int i, j, axis;
};

class CoverPieces {
 public:
  // Writes into `cover`, whose lattice, runs and crossings are found; `probe` is its surface's.
  CoverPieces(SurfaceCover& cover, const CoverProbe& probe, const SurfaceSet& surfaces, uint32_t surface)
      : c_(cover), probe_(probe), surfaces_(surfaces), surface_(surfaces.surfaces[surface]) {}

  // Cells whose polygon has one crossing where the cover ends and one where it begins again: where the contact
  // line turns a corner between them, the corner (SurfaceCover::corners_). Only cells beside a changing edge can.
  void FindCorners(std::span<const LatticeEdge> changing);
  // Each cell's covered polygon, cut to each surface triangle that its box meets, as triangles, in cell order.
  void CutPieces();

 private:
  struct Line2 {
    Point2 through, second;  // two points on it
  };
  std::optional<Point2> CornerIn(int i, int j) const;
  std::optional<Line2> ContactLineAt(const SurfaceCover::CellEdge& e) const;
  std::vector<uint64_t> CellsWithACoveredCorner() const;

  SurfaceCover& c_;
  const CoverProbe& probe_;
  const SurfaceSet& surfaces_;
  const Surface& surface_;
};

}  // namespace pb
