// The region Omega that one surface covers in its (u,v) chart [m]: a union of triangles. Answers the two
// questions boundary-corrected density estimation asks of it (Jones 1993, "Simple boundary correction for
// kernel density estimation", Statistics and Computing 3, for the renormalisation this serves):
//   KernelMass(x, K, h) = integral over Omega of K_h(|y - x|) dy, in [0, 1]: the fraction of a kernel centred
//                         at x that lies on the surface (1 inside, 1/2 on a straight edge, 1/4 at a square
//                         corner, when h is small against the surface);
//   OverlapArea(box)    = area of box intersected with Omega [m^2], for histogram buckets.
// Omega is a union of triangles, less any holes (triangles inside it): its boundary edges are the triangles' and,
// reversed, the holes'.
//
// KernelMass is exact up to round-off: by the divergence theorem in polar coordinates about x, the integral
// over Omega is a signed sum over Omega's boundary edges e of integral_e G(r/h) dtheta, with G the kernel's
// radial mass (estimators/kernels.h). Along an edge at distance d from x, dtheta = d ds / r^2, so the
// integrand d G(t)/(h^2 t^2) is smooth in s and Gauss-Legendre integrates it exactly for polynomial kernels.
// Interior edges, shared by two triangles, cancel and are dropped; T-junction edges cancel numerically; straight
// runs of boundary edges (a gridded face's sides) are joined into one edge each, so a query's cost is that of the
// region's true corners, not of the grid it was cut on. Edges
// farther than h from x are not integrated one by one: together they add the angle they subtend, which is found
// from the near edges and the crossings of one ray, read from per-row sums of a grid (surface_region.cpp), so a
// query costs what the edges within h cost, not the whole boundary.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "estimators/kernels.h"
#include "mesh/geometry.h"

namespace pb {

// The kernel's mass, first and second moments over Omega about x, offsets in units of h (dimensionless):
//   mass = integral over Omega of K_h(|y - x|) dy                         (KernelMass, unclamped)
//   first = integral of K_h (y - x) / h dy                                 (u, v)
//   second = integral of K_h (y - x)(y - x)^T / h^2 dy                     (uu, uv, vv)
// Local linear density estimation needs all three (estimators/kernel_estimator.h).
struct KernelMomentsAt {
  double mass = 0;
  std::array<double, 2> first{};
  std::array<double, 3> second{};
};

class SurfaceRegion {
 public:
  // Triangles in chart coordinates [m]; orientation does not matter (each is used counter-clockwise). Omega is
  // their union less the union of `holes`, triangles that lie inside it (the part other geometry covers,
  // estimators/surface_cover.h).
  explicit SurfaceRegion(std::span<const Triangle2> triangles, std::span<const Triangle2> holes = {});

  // For x in Omega (closure included). Points outside Omega far from its boundary also return 1.
  double KernelMass(Point2 x, Kernel kernel, double h) const;
  // The mass and moments together (KernelMomentsAt), by the same boundary integral, each edge's moments along it.
  KernelMomentsAt Moments(Point2 x, Kernel kernel, double h) const;
  double OverlapArea(const Bounds2& box) const;
  // Whether x lies in Omega (its winding number about Omega's boundary is positive); either on the boundary.
  bool Contains(Point2 x) const { return CutCrossings(x) > 0; }
  // Area on the surface [m^2] of each cell of the nu x nv grid of squares of side `side` from corner `lo`,
  // row-major (v outer); each triangle is clipped only against the cells its bounding box touches.
  std::vector<double> GridOverlapAreas(Point2 lo, float side, int nu, int nv) const;

  double Area() const { return area_; }
  const Bounds2& Bounds() const { return bounds_; }
  std::span<const Triangle2> Triangles() const { return triangles_; }
  size_t BoundaryEdgeCount() const { return edges_.size(); }

 private:
  struct Edge {
    Point2 a, b;  // Omega lies to the left of a -> b
  };
  // Indices of the boundary edges closer to x than `radius`, each once.
  std::vector<uint32_t> EdgesWithin(Point2 x, double radius) const;
  // The signed count of boundary edges that cross the ray from x toward -u (the cut): +1 for each crossing
  // downward (from v >= x.v to v < x.v), -1 for each upward. Its cost is that of one cell and of the edges that
  // end in x's row of the grid, however many edges span the row.
  int CutCrossings(Point2 x) const;
  // The same, for the edges other than `near` (indices of edges_).
  int CutCrossingsBeyond(Point2 x, std::span<const uint32_t> near) const;
  // The same over every edge listed in x's row: for a point outside its row's strip (beyond the grid).
  int CutCrossingsScanningRow(Point2 x) const;
  std::array<int, 2> CellOf(double u, double v) const;
  double StripLow(int row) const { return bounds_.lo.v + row * cell_; }  // the v range of a row of the grid
  double StripHigh(int row) const { return bounds_.lo.v + (row + 1) * cell_; }
  // Whether edge e spans row's strip from below its low side to at or above its high side: it then crosses the cut
  // of every point in the strip.
  bool SpansStrip(const Edge& e, int row) const {
    return std::min(e.a.v, e.b.v) < StripLow(row) && std::max(e.a.v, e.b.v) >= StripHigh(row);
  }

  std::vector<Triangle2> triangles_, holes_;
  std::vector<Edge> edges_;
  double area_ = 0;
  Bounds2 bounds_;
  // Uniform grid over the boundary edges' bounding boxes: edge indices of cell c are
  // cellEdges_[cellStart_[c] .. cellStart_[c+1]).
  double cell_ = 1;
  int nu_ = 1, nv_ = 1;
  std::vector<uint32_t> cellStart_, cellEdges_;
  // Per row: spanCrossings_[row * (nu_ + 1) + k] is the signed crossing (+1 when a is its upper end) summed over
  // the edges that span the row's strip and are listed only in cells left of k, which cross left of any point of
  // cell k; the row's other edges (an end within the strip) are rowEnds_[rowEndStart_[row] ..
  // rowEndStart_[row + 1]), as (first cell listed, edge), by first cell.
  std::vector<int> spanCrossings_;
  std::vector<uint32_t> rowEndStart_;
  std::vector<std::pair<int, uint32_t>> rowEnds_;
};

// Area [m^2] of a triangle clipped to an axis-aligned box.
double TriangleBoxOverlapArea(const Triangle2& triangle, const Bounds2& box);

}  // namespace pb
