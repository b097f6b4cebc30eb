#include "estimators/cover_band.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "estimators/chart_clip.h"

namespace pb {
namespace {

class BandMarker {
 public:
  BandMarker(const CoverSurface& in, const CoverLattice& lattice, const Bounds2& chartBox)
      : in_(in), surface_(in.surfaces.surfaces[in.index]), l_(lattice), chartBox_(chartBox) {}

  // CellsWhereTheCoverCanChange.
  std::vector<uint64_t> MarkedCells() const {
    tbb::enumerable_thread_specific<std::vector<uint64_t>> marked;
    const float reach = Reach(), side = TileSide();
    const std::vector<std::array<int, 2>> tiles = Tiles(side);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size()), [&](const tbb::blocked_range<size_t>& r) {
      std::vector<uint64_t>& cells = marked.local();
      std::vector<uint32_t> near;
      for (size_t k = r.begin(); k != r.end(); ++k) MarkNear(tiles[k], side, reach, near, cells);
    });
    std::vector<uint64_t> cells;
    for (const std::vector<uint64_t>& part : marked) cells.insert(cells.end(), part.begin(), part.end());
    for (const auto& [a, b] : BoundaryEdges()) MarkPolygon({a, b}, Whole(), cells);
    return cells;
  }

  // The side g [m] of the square tiles over which other triangles are looked for, one point query each: 16 lattice
  // cells, or the side of the surface's mean triangle where that is larger, so that there are at most about as
  // many tiles as triangles, and a query's sphere holds little beyond the slab.
  float TileSide() const {
    return std::max(16 * l_.spacing, float(std::sqrt(2 * surface_.area / double(surface_.triangles.size()))));
  }

  // The tiles (i, j), [i g, (i + 1) g] x [j g, (j + 1) g] in the chart, that meet one of the surface's triangles.
  std::vector<std::array<int, 2>> Tiles(float g) const {
    std::vector<std::array<int, 2>> tiles;
    for (uint32_t t : surface_.triangles) {
      std::array<Point2, 3> c = in_.surfaces.cornerUv[t];
      if (SignedArea(c[0], c[1], c[2]) < 0) std::swap(c[1], c[2]);
      Bounds2 b;
      for (const Point2& p : c) b.Extend(p);
      for (int j = int(std::floor(b.lo.v / g)); j <= int(std::floor(b.hi.v / g)); ++j)
        for (int i = int(std::floor(b.lo.u / g)); i <= int(std::floor(b.hi.u / g)); ++i)
          if (TileMeets({{float(i * g), float(j * g)}, {float((i + 1) * g), float((j + 1) * g)}}, c)) tiles.push_back({i, j});
    }
    std::sort(tiles.begin(), tiles.end());
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    return tiles;
  }

  // Whether the box meets counter-clockwise triangle c, given that their bounding boxes meet: no edge of c has the
  // whole box outside it (the separating axis test's remaining axes).
  static bool TileMeets(const Bounds2& box, const std::array<Point2, 3>& c) {
    const Point2 corners[4] = {box.lo, {box.hi.u, box.lo.v}, box.hi, {box.lo.u, box.hi.v}};
    for (int e = 0; e < 3; ++e) {
      bool allOutside = true;
      for (const Point2& q : corners) allOutside = allOutside && SignedArea(c[e], c[(e + 1) % 3], q) < 0;
      if (allOutside) return false;
    }
    return true;
  }

  // r: how far from the surface's mean plane [m] another triangle may pass and still bound a cover.
  float Reach() const {
    float deviation = 0;
    for (uint32_t t : surface_.triangles)
      for (uint32_t v : in_.scene.triangles[t].v)
        deviation = std::max(deviation, std::fabs(Dot(in_.scene.positions[v] - surface_.chart.origin, surface_.chart.frame.n)));
    return deviation + 2 * l_.spacing + 4 * in_.rays.SpawnOffset();
  }

  // Marks the cells that the slab's cut of each other triangle near tile (i, j) of side g touches, within the
  // tile grown by two cells.
  void MarkNear(std::array<int, 2> tile, float g, float reach, std::vector<uint32_t>& near, std::vector<uint64_t>& cells) const {
    // The tile within the chart's box, grown by the margin.
    const float margin = 2 * l_.spacing;
    const Bounds2& chartBox = chartBox_;
    const Bounds2 window{{std::max(float(tile[0] * g), chartBox.lo.u) - margin, std::max(float(tile[1] * g), chartBox.lo.v) - margin},
                         {std::min(float((tile[0] + 1) * g), chartBox.hi.u) + margin, std::min(float((tile[1] + 1) * g), chartBox.hi.v) + margin}};
    const SurfaceChart& chart = surface_.chart;
    const float u = 0.5f * (window.lo.u + window.hi.u), v = 0.5f * (window.lo.v + window.hi.v);
    const Point3 centre = chart.origin + chart.frame.s * u + chart.frame.t * v;
    near.clear();
    in_.rays.TrianglesNear(centre, 0.5f * std::hypot(window.hi.u - window.lo.u, window.hi.v - window.lo.v) + reach, near);
    for (uint32_t other : near) {
      if (in_.surfaces.surfaceOfTriangle[other] == in_.index || !MeetsSlab(other, reach)) continue;
      const SlabPart cut = SlabCut(other, reach);
      if (cut.inPlane) {
        for (size_t k = 0; k < cut.uv.size(); ++k) MarkPolygon({cut.uv[k], cut.uv[(k + 1) % cut.uv.size()]}, window, cells);
      } else {
        MarkPolygon(cut.uv, window, cells);
      }
    }
  }

  // Whether triangle `other` has points within `reach` of the surface's plane: its corners' distances straddle
  // or touch [-reach, reach].
  bool MeetsSlab(uint32_t other, float reach) const {
    float lo = INFINITY, hi = -INFINITY;
    for (uint32_t v : in_.scene.triangles[other].v) {
      const float d = Dot(in_.scene.positions[v] - surface_.chart.origin, surface_.chart.frame.n);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    return lo <= reach && hi >= -reach;
  }

  // The part of triangle `other` within `reach` of the surface's plane, projected into the chart: a convex polygon
  // (empty when it stays out of the slab). In the plane when every corner is as near it as the surface's own
  // (the surface's deviation, `reach` less 2 s): rays from the surface cannot meet it, and only its edges,
  // where a neighbour's outline may run, count.
  struct SlabPart {
    std::vector<Point2> uv;
    bool inPlane = true;
  };
  SlabPart SlabCut(uint32_t other, float reach) const {
    const SurfaceChart& chart = surface_.chart;
    struct Corner {
      Point3 p;
      float d;  // signed distance from the plane [m]
    };
    std::vector<Corner> polygon;
    SlabPart part;
    for (uint32_t v : in_.scene.triangles[other].v) {
      polygon.push_back({in_.scene.positions[v], Dot(in_.scene.positions[v] - chart.origin, chart.frame.n)});
      part.inPlane = part.inPlane && std::fabs(polygon.back().d) <= reach - 2 * l_.spacing;
    }
    for (const float side : {1.0f, -1.0f}) {  // keep side * d <= reach
      std::vector<Corner> kept;
      for (size_t k = 0; k < polygon.size(); ++k) {
        const Corner a = polygon[k], b = polygon[(k + 1) % polygon.size()];
        const bool inA = side * a.d <= reach, inB = side * b.d <= reach;
        if (inA) kept.push_back(a);
        if (inA != inB) {
          const float t = (side * reach - a.d) / (b.d - a.d);
          kept.push_back({a.p + (b.p - a.p) * t, side * reach});
        }
      }
      polygon = std::move(kept);
      if (polygon.empty()) return {};
    }
    for (const Corner& c : polygon) part.uv.push_back(chart.ToUv(c.p));
    return part;
  }

  // The lattice's box.
  Bounds2 Whole() const { return {l_.lo, l_.Point(l_.nu - 1, l_.nv - 1)}; }

  // The surface's chart edges that only one of its triangles has (its outline, holes included).
  std::vector<std::array<Point2, 2>> BoundaryEdges() const {
    struct Edge {
      std::array<uint64_t, 2> key;  // the ends' bits, the smaller first
      Point2 a, b;
    };
    const auto bits = [](Point2 p) {
      uint32_t u, v;
      std::memcpy(&u, &p.u, 4), std::memcpy(&v, &p.v, 4);
      return uint64_t(u) << 32 | v;
    };
    std::vector<Edge> edges;
    for (uint32_t t : surface_.triangles) {
      const std::array<Point2, 3>& c = in_.surfaces.cornerUv[t];
      for (int k = 0; k < 3; ++k) {
        const Point2 a = c[k], b = c[(k + 1) % 3];
        const uint64_t ka = bits(a), kb = bits(b);
        edges.push_back({{std::min(ka, kb), std::max(ka, kb)}, a, b});
      }
    }
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key < y.key; });
    std::vector<std::array<Point2, 2>> boundary;
    for (size_t k = 0; k < edges.size();) {
      size_t end = k + 1;
      while (end < edges.size() && edges[end].key == edges[k].key) ++end;
      if (end - k == 1) boundary.push_back({edges[k].a, edges[k].b});
      k = end;
    }
    return boundary;
  }

  // Marks every lattice cell that convex polygon `corners` [m] (two corners: a segment), cut to `window`, touches
  // (its closed square): row by row, the span between the leftmost and rightmost points of its edges' parts in
  // the row.
  void MarkPolygon(const std::vector<Point2>& corners, const Bounds2& window, std::vector<uint64_t>& cells) const {
    const double s = l_.spacing;
    std::vector<std::array<double, 4>> edges;  // (x0, y0, x1, y1) in cells, cut to the window
    double yLo = INFINITY, yHi = -INFINITY;
    const std::vector<Point2> inside = corners.size() < 3 ? corners : ClipToWindow(corners, window);
    for (size_t k = 0; k < inside.size(); ++k) {
      Point2 a = inside[k], b = inside[(k + 1) % inside.size()];
      if (inside.size() == 2 && k == 1) break;
      if (!ClipToBox(a, b, window)) continue;
      edges.push_back({(a.u - l_.lo.u) / s, (a.v - l_.lo.v) / s, (b.u - l_.lo.u) / s, (b.v - l_.lo.v) / s});
      yLo = std::min({yLo, edges.back()[1], edges.back()[3]}), yHi = std::max({yHi, edges.back()[1], edges.back()[3]});
    }
    if (edges.empty()) return;
    const int lastCell = l_.nu - 2, lastRow = l_.nv - 2;
    for (int j = std::clamp(int(std::floor(yLo)), 0, lastRow); j <= std::clamp(int(std::floor(yHi)), 0, lastRow); ++j) {
      double xLo = INFINITY, xHi = -INFINITY;
      for (const auto& [x0, y0, x1, y1] : edges) {
        // The edge's part with y in [j, j + 1] (the first and last rows take all below or above them).
        const double lo = j == 0 ? -INFINITY : double(j), hi = j == lastRow ? INFINITY : double(j + 1);
        double t0 = 0, t1 = 1;
        if (y1 != y0) {
          const double ta = (lo - y0) / (y1 - y0), tb = (hi - y0) / (y1 - y0);
          t0 = std::max(t0, std::min(ta, tb)), t1 = std::min(t1, std::max(ta, tb));
        } else if (y0 < lo || y0 > hi) {
          continue;
        }
        if (!(t0 <= t1)) continue;
        for (const double t : {t0, t1}) {
          const double x = x0 + t * (x1 - x0);
          xLo = std::min(xLo, x), xHi = std::max(xHi, x);
        }
      }
      if (!(xLo <= xHi)) continue;
      for (int i = std::clamp(int(std::floor(xLo)), 0, lastCell); i <= std::clamp(int(std::floor(xHi)), 0, lastCell); ++i)
        cells.push_back(l_.Key(i, j));
    }
  }

 private:
  const CoverSurface& in_;
  const Surface& surface_;
  CoverLattice l_;
  Bounds2 chartBox_;
};

}  // namespace

std::vector<uint64_t> CellsWhereTheCoverCanChange(const CoverSurface& surface, const CoverLattice& lattice,
                                                  const Bounds2& chartBox) {
  return BandMarker(surface, lattice, chartBox).MarkedCells();
}

}  // namespace pb
