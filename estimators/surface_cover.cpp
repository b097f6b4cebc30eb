#include "estimators/surface_cover.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>
#include <unordered_map>

#include "estimators/surface_region.h"
#include "estimators/warps.h"

namespace pb {
namespace {

constexpr int kBisections = 10;  // the contact line to s / 1024

// kCoverRays directions about +z, cosine-weighted on a golden-angle spiral: the same for every point.
std::array<Vector3, kCoverRays> HemisphereSpiral() {
  std::array<Vector3, kCoverRays> d;
  for (int k = 0; k < kCoverRays; ++k) d[k] = CosineSpiralDirection(k, kCoverRays);
  return d;
}

// The part of convex counter-clockwise `polygon` left of the line a -> b.
std::vector<Point2> ClipLeftOf(const std::vector<Point2>& polygon, Point2 a, Point2 b) {
  std::vector<Point2> out;
  const auto side = [&](Point2 p) {
    return (double(b.u) - a.u) * (double(p.v) - a.v) - (double(b.v) - a.v) * (double(p.u) - a.u);
  };
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Point2 p = polygon[i], q = polygon[(i + 1) % polygon.size()];
    const double sp = side(p), sq = side(q);
    if (sp >= 0) out.push_back(p);
    if ((sp < 0) != (sq < 0) && sp != 0 && sq != 0) {
      const double t = sp / (sp - sq);
      out.push_back({float(p.u + t * (double(q.u) - p.u)), float(p.v + t * (double(q.v) - p.v))});
    }
  }
  return out;
}

double TwiceSignedArea(const std::vector<Point2>& polygon) {
  double twice = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Point2 p = polygon[i], q = polygon[(i + 1) % polygon.size()];
    twice += double(p.u) * q.v - double(q.u) * p.v;
  }
  return twice;
}

}  // namespace

// Builds one surface's cover: classifies the lattice, bisects its changing edges, and cuts the covered cells'
// polygons to the surface's triangles.
class CoverBuilder {
 public:
  CoverBuilder(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t s,
               const CoverSettings& settings)
      : scene_(scene), surfaces_(surfaces), rays_(rays), surface_(surfaces.surfaces[s]), surfaceIndex_(s), settings_(settings),
        directions_(HemisphereSpiral()), whole_(ChartTriangles()) {}

  SurfaceCover Build() {
    const Bounds2& b = whole_.Bounds();
    const double su = double(b.hi.u) - b.lo.u, sv = double(b.hi.v) - b.lo.v;
    // A surface narrower than two lattice spacings holds at most a row of lattice points: too few to find a cover.
    if (!(std::min(su, sv) >= 2 * double(settings_.spacing))) return {};
    double spacing = settings_.spacing;
    while ((su / spacing + 3) * (sv / spacing + 3) > double(settings_.maxPointsPerSurface)) spacing *= 2;
    c_.spacing_ = float(spacing);
    c_.lo_ = {float(b.lo.u - spacing / 2), float(b.lo.v - spacing / 2)};
    c_.nu_ = int(std::ceil(su / spacing)) + 2;  // from half a spacing before the chart to at least half after
    c_.nv_ = int(std::ceil(sv / spacing)) + 2;
    const std::vector<uint64_t> band = BandPoints(MarkedCells());
    ClassifyLattice(band);
    if (c_.runs_.empty()) {
      SurfaceCover empty;
      empty.probed_ = band.size();
      return empty;
    }
    c_.probed_ = band.size();
    const std::vector<LatticeEdge> changing = ChangingEdges();
    FindCrossings(changing);
    FindCorners(changing);
    CutPieces();
    return std::move(c_);
  }

 private:
  std::vector<Triangle2> ChartTriangles() const {
    std::vector<Triangle2> triangles;
    for (uint32_t t : surface_.triangles) triangles.push_back(surfaces_.cornerUv[t]);
    return triangles;
  }

  // Whether chart point uv is on the surface and all but one of the rays from it, over the surface's front, first
  // meet a triangle's back. Off the surface nothing is covered, so a contact line that reaches the surface's edge
  // ends there. The point is on the surface's mean plane, which a surface planar to within a degree can leave by
  // millimetres (the box's twisted red wall): a ray passes through the surface's own triangles.
  bool CoveredAt(Point2 uv) const {
    if (!whole_.Contains(uv)) return false;
    const SurfaceChart& chart = surface_.chart;
    const Point3 p = chart.origin + chart.frame.s * uv.u + chart.frame.t * uv.v;
    int open = 0;
    for (const Vector3& local : directions_) {
      const Vector3 d = chart.frame.ToWorld(local);
      if (!MeetsABack(rays_.SpawnPoint(p, chart.frame.n), d)) ++open;
      if (open > 1) return false;
    }
    return true;
  }

  // Whether the ray first meets the back of a triangle of another surface.
  bool MeetsABack(Point3 origin, Vector3 d) const {
    constexpr int kPassesThroughOwn = 4;
    for (int pass = 0; pass < kPassesThroughOwn; ++pass) {
      const std::optional<RayHit> hit = rays_.Intersect(origin, d);
      if (!hit) return false;
      const Vector3 area = scene_.AreaVector(hit->triangle);
      if (surfaces_.surfaceOfTriangle[hit->triangle] != surfaceIndex_) return Dot(area, d) > 0;
      origin = rays_.SpawnPoint(origin + d * hit->t, NormalFrom(Dot(area, d) > 0 ? area : area * -1.0f));
    }
    return false;
  }

  // Lattice cells [i, i + 1] x [j, j + 1] as keys j * nu + i, and lattice points (i, j) alike.
  uint64_t Key(int i, int j) const { return uint64_t(j) * uint64_t(c_.nu_) + uint64_t(i); }

  // The cells that the slab's cut of the other triangles near the surface, and the surface's own boundary edges,
  // touch (see the top): where the cover can change. Unsorted, with repeats.
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
    return std::max(16 * c_.spacing_, float(std::sqrt(2 * surface_.area / double(surface_.triangles.size()))));
  }

  // The tiles (i, j), [i g, (i + 1) g] x [j g, (j + 1) g] in the chart, that meet one of the surface's triangles.
  std::vector<std::array<int, 2>> Tiles(float g) const {
    std::vector<std::array<int, 2>> tiles;
    for (uint32_t t : surface_.triangles) {
      std::array<Point2, 3> c = surfaces_.cornerUv[t];
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
      for (uint32_t v : scene_.triangles[t].v)
        deviation = std::max(deviation, std::fabs(Dot(scene_.positions[v] - surface_.chart.origin, surface_.chart.frame.n)));
    return deviation + 2 * c_.spacing_ + 4 * rays_.SpawnOffset();
  }

  // Marks the cells that the slab's cut of each other triangle near tile (i, j) of side g touches, within the
  // tile grown by two cells.
  void MarkNear(std::array<int, 2> tile, float g, float reach, std::vector<uint32_t>& near, std::vector<uint64_t>& cells) const {
    // The tile within the chart's box, grown by the margin.
    const float margin = 2 * c_.spacing_;
    const Bounds2& chartBox = whole_.Bounds();
    const Bounds2 window{{std::max(float(tile[0] * g), chartBox.lo.u) - margin, std::max(float(tile[1] * g), chartBox.lo.v) - margin},
                         {std::min(float((tile[0] + 1) * g), chartBox.hi.u) + margin, std::min(float((tile[1] + 1) * g), chartBox.hi.v) + margin}};
    const SurfaceChart& chart = surface_.chart;
    const float u = 0.5f * (window.lo.u + window.hi.u), v = 0.5f * (window.lo.v + window.hi.v);
    const Point3 centre = chart.origin + chart.frame.s * u + chart.frame.t * v;
    near.clear();
    rays_.TrianglesNear(centre, 0.5f * std::hypot(window.hi.u - window.lo.u, window.hi.v - window.lo.v) + reach, near);
    for (uint32_t other : near) {
      if (surfaces_.surfaceOfTriangle[other] == surfaceIndex_ || !MeetsSlab(other, reach)) continue;
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
    for (uint32_t v : scene_.triangles[other].v) {
      const float d = Dot(scene_.positions[v] - surface_.chart.origin, surface_.chart.frame.n);
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
    for (uint32_t v : scene_.triangles[other].v) {
      polygon.push_back({scene_.positions[v], Dot(scene_.positions[v] - chart.origin, chart.frame.n)});
      part.inPlane = part.inPlane && std::fabs(polygon.back().d) <= reach - 2 * c_.spacing_;
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

  Bounds2 Whole() const {
    return {c_.lo_, c_.Lattice(c_.nu_ - 1, c_.nv_ - 1)};
  }

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
      const std::array<Point2, 3>& c = surfaces_.cornerUv[t];
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
    const double s = c_.spacing_;
    std::vector<std::array<double, 4>> edges;  // (x0, y0, x1, y1) in cells, cut to the window
    double yLo = INFINITY, yHi = -INFINITY;
    const std::vector<Point2> inside = corners.size() < 3 ? corners : ClipToWindow(corners, window);
    for (size_t k = 0; k < inside.size(); ++k) {
      Point2 a = inside[k], b = inside[(k + 1) % inside.size()];
      if (inside.size() == 2 && k == 1) break;
      if (!ClipToBox(a, b, window)) continue;
      edges.push_back({(a.u - c_.lo_.u) / s, (a.v - c_.lo_.v) / s, (b.u - c_.lo_.u) / s, (b.v - c_.lo_.v) / s});
      yLo = std::min({yLo, edges.back()[1], edges.back()[3]}), yHi = std::max({yHi, edges.back()[1], edges.back()[3]});
    }
    if (edges.empty()) return;
    const int lastCell = c_.nu_ - 2, lastRow = c_.nv_ - 2;
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
        cells.push_back(Key(i, j));
    }
  }

  // The part of convex polygon `corners` inside the box.
  static std::vector<Point2> ClipToWindow(std::vector<Point2> polygon, const Bounds2& box) {
    const Point2 c[4] = {box.lo, {box.hi.u, box.lo.v}, box.hi, {box.lo.u, box.hi.v}};  // counter-clockwise
    if (SignedArea(polygon[0], polygon[1], polygon[2]) < 0) std::reverse(polygon.begin(), polygon.end());
    for (int k = 0; k < 4 && polygon.size() >= 2; ++k) polygon = ClipLeftOf(polygon, c[k], c[(k + 1) % 4]);
    return polygon;
  }

  // Cuts segment a -> b to the box (Liang and Barsky); false when nothing of it is inside.
  static bool ClipToBox(Point2& a, Point2& b, const Bounds2& box) {
    double t0 = 0, t1 = 1;
    const double du = double(b.u) - a.u, dv = double(b.v) - a.v;
    const double p[4] = {-du, du, -dv, dv};
    const double q[4] = {double(a.u) - box.lo.u, double(box.hi.u) - a.u, double(a.v) - box.lo.v, double(box.hi.v) - a.v};
    for (int k = 0; k < 4; ++k) {
      if (p[k] == 0) {
        if (q[k] < 0) return false;
        continue;
      }
      const double t = q[k] / p[k];
      if (p[k] < 0) t0 = std::max(t0, t);
      else t1 = std::min(t1, t);
    }
    if (!(t0 <= t1)) return false;
    const Point2 from = a;
    a = {float(from.u + t0 * du), float(from.v + t0 * dv)};
    b = {float(from.u + t1 * du), float(from.v + t1 * dv)};
    return true;
  }

  // The band's lattice points: the corners of the marked cells, sorted. A point that is not one has no marked cell
  // about it; every lattice edge that a footprint touches is a side of a cell that MarkPolygon marks, so the edges
  // from such a point touch none, and its class is its neighbours'.
  std::vector<uint64_t> BandPoints(std::vector<uint64_t> marked) const {
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    std::vector<uint64_t> points;
    points.reserve(marked.size() * 4);
    for (uint64_t cell : marked) {
      const int i = int(cell % uint64_t(c_.nu_)), j = int(cell / uint64_t(c_.nu_));
      for (int dj = 0; dj <= 1; ++dj)
        for (int di = 0; di <= 1; ++di) points.push_back(Key(i + di, j + dj));  // cells stop one short of the rim
    }
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
    return points;
  }

  // Casts the rays at the band's points; every other point of a row takes the class of the band point before it
  // in the row (open before the first: the row's start is off the surface). Fills the cover's runs.
  void ClassifyLattice(const std::vector<uint64_t>& band) {
    std::vector<uint8_t> covered(band.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, band.size()), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k)
        covered[k] = CoveredAt(c_.Lattice(int(band[k] % uint64_t(c_.nu_)), int(band[k] / uint64_t(c_.nu_))));
    });
    std::vector<std::pair<int, SurfaceCover::Run>> runs;  // (row, run)
    for (size_t k = 0; k < band.size(); ++k) {
      if (!covered[k]) continue;
      const int i = int(band[k] % uint64_t(c_.nu_)), j = int(band[k] / uint64_t(c_.nu_));
      const bool nextInRow = k + 1 < band.size() && band[k + 1] / uint64_t(c_.nu_) == uint64_t(j);
      const int last = nextInRow ? int(band[k + 1] % uint64_t(c_.nu_)) - 1 : i;
      if (!runs.empty() && runs.back().first == j && runs.back().second.last + 1 == i) runs.back().second.last = last;
      else runs.push_back({j, {i, last}});
    }
    if (runs.empty()) return;
    c_.firstRow_ = runs.front().first;
    const int rows = runs.back().first - c_.firstRow_ + 1;
    c_.rowStart_.assign(size_t(rows) + 1, 0);
    for (const auto& [j, run] : runs) {
      ++c_.rowStart_[size_t(j - c_.firstRow_) + 1];
      c_.runs_.push_back(run);
    }
    for (size_t k = 1; k < c_.rowStart_.size(); ++k) c_.rowStart_[k] += c_.rowStart_[k - 1];
  }

  struct LatticeEdge {
    int i, j, axis;  // from point (i, j) along +u (axis 0) or +v (axis 1)
  };

  // The lattice edges whose ends differ: at each run's ends along its row, and where two neighbouring rows' runs
  // differ (their symmetric difference), found from the runs alone.
  std::vector<LatticeEdge> ChangingEdges() const {
    std::vector<LatticeEdge> edges;
    const int rows = int(c_.rowStart_.size()) - 1;
    for (int j = c_.firstRow_; j < c_.firstRow_ + rows; ++j)
      for (const SurfaceCover::Run& run : c_.RowRuns(j)) {
        if (run.first > 0) edges.push_back({run.first - 1, j, 0});
        if (run.last + 1 < c_.nu_) edges.push_back({run.last, j, 0});
      }
    for (int j = std::max(c_.firstRow_ - 1, 0); j < std::min(c_.firstRow_ + rows, c_.nv_ - 1); ++j) {
      std::vector<int> ends;  // half-open [first, last + 1) of both rows' runs; equal ends cancel
      for (int row : {j, j + 1})
        for (const SurfaceCover::Run& run : c_.RowRuns(row)) ends.push_back(run.first), ends.push_back(run.last + 1);
      std::sort(ends.begin(), ends.end());
      std::vector<int> toggles;
      for (int e : ends) {
        if (!toggles.empty() && toggles.back() == e) toggles.pop_back();
        else toggles.push_back(e);
      }
      for (size_t k = 0; k + 1 < toggles.size(); k += 2)
        for (int i = toggles[k]; i < toggles[k + 1]; ++i) edges.push_back({i, j, 1});
    }
    return edges;
  }

  // On each changing lattice edge, the fraction of the way from its first end where the cover changes.
  void FindCrossings(const std::vector<LatticeEdge>& edges) {
    std::vector<float> at(edges.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, edges.size()), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k) {
        const LatticeEdge& e = edges[k];
        const int i1 = e.i + (e.axis == 0), j1 = e.j + (e.axis == 1);
        at[k] = Bisect(c_.Lattice(e.i, e.j), c_.Lattice(i1, j1), c_.CoveredPoint(e.i, e.j));
      }
    });
    c_.crossing_.reserve(edges.size());
    for (size_t k = 0; k < edges.size(); ++k)
      c_.crossing_.emplace(SurfaceCover::EdgeKey(Key(edges[k].i, edges[k].j), edges[k].axis), at[k]);
  }

  // Where along a -> b the cover changes, to 1 / 2^kBisections, rounded toward the covered end.
  // Where the open end is off the surface, the cover usually runs up to the surface's edge (a face inside a
  // closed object): the edge is found by the containment test alone, and one ray test just inside it confirms
  // that the cover reaches it (else the rays decide every step).
  float Bisect(Point2 a, Point2 b, bool coveredAtA) const {
    if (!whole_.Contains(coveredAtA ? b : a)) {
      const float edge = BisectBy([&](Point2 m) { return whole_.Contains(m); }, a, b, coveredAtA);
      if (CoveredAt(Between(a, b, edge))) return edge;
    }
    return BisectBy([&](Point2 m) { return CoveredAt(m); }, a, b, coveredAtA);
  }

  template <typename Covered>
  static float BisectBy(const Covered& covered, Point2 a, Point2 b, bool coveredAtA) {
    float lo = 0, hi = 1;
    for (int k = 0; k < kBisections; ++k) {
      const float mid = 0.5f * (lo + hi);
      const Point2 m{a.u + mid * (b.u - a.u), a.v + mid * (b.v - a.v)};
      (covered(m) == coveredAtA ? lo : hi) = mid;
    }
    return coveredAtA ? lo : hi;  // on the covered side: no photon that reached the surface lands in the cover
  }

  // Cells whose polygon has one crossing where the cover ends and one where it begins again: where the contact
  // line turns a corner between them, the corner (SurfaceCover::corners_). Only cells beside a changing edge can.
  void FindCorners(const std::vector<LatticeEdge>& changing) {
    std::vector<uint64_t> cells;
    for (const LatticeEdge& e : changing) {
      const int i = e.i - (e.axis == 1), j = e.j - (e.axis == 0);  // the cell before the edge, then the one after
      for (const auto& [ci, cj] : {std::pair{i, j}, std::pair{e.i, e.j}})
        if (ci >= 0 && cj >= 0 && ci + 1 < c_.nu_ && cj + 1 < c_.nv_) cells.push_back(Key(ci, cj));
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    std::vector<std::optional<Point2>> corner(cells.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, cells.size()), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k)
        corner[k] = CornerIn(int(cells[k] % uint64_t(c_.nu_)), int(cells[k] / uint64_t(c_.nu_)));
    });
    for (size_t k = 0; k < cells.size(); ++k)
      if (corner[k]) c_.corners_.emplace(size_t(cells[k]), *corner[k]);
  }

  std::optional<Point2> CornerIn(int i, int j) const {
    const std::array<SurfaceCover::CellEdge, 4> edges = c_.EdgesOf(i, j);
    const SurfaceCover::CellEdge *exit = nullptr, *entry = nullptr;
    int changes = 0;
    for (const SurfaceCover::CellEdge& e : edges) {
      if (e.coveredA == e.coveredB) continue;
      ++changes;
      (e.coveredA ? exit : entry) = &e;
    }
    if (changes != 2) return std::nullopt;  // uniform, or a saddle
    const std::optional<Line2> out = ContactLineAt(*exit), in = ContactLineAt(*entry);
    if (!out || !in) return std::nullopt;
    const std::optional<Point2> x = Intersection(*out, *in);
    if (!x || !c_.InCell(*x, i, j)) return std::nullopt;
    if (!Convex(c_.CellPolygon(i, j, &*x))) return std::nullopt;
    const Point2 chordMiddle = Between(out->through, in->through, 0.5);
    if (!CoveredAt(Between(chordMiddle, *x, 0.5))) return std::nullopt;  // the turn is not where the lines say
    return x;
  }

  struct Line2 {
    Point2 through, second;  // two points on it
  };

  // The contact line through the crossing on lattice edge e, from a second crossing s / 4 into the cell along a
  // parallel segment whose ends are covered as e's are. None when the line turns within s / 4 of the edge.
  std::optional<Line2> ContactLineAt(const SurfaceCover::CellEdge& e) const {
    const float d = 0.25f * c_.spacing_;
    const Point2 a{e.a.u + d * e.inward.u, e.a.v + d * e.inward.v}, b{e.b.u + d * e.inward.u, e.b.v + d * e.inward.v};
    if (CoveredAt(a) != e.coveredA || CoveredAt(b) != e.coveredB) return std::nullopt;
    return Line2{e.crossing, Between(a, b, Bisect(a, b, e.coveredA))};
  }

  // Where two lines meet, unless they are within 10 degrees of parallel (a straight contact line: no corner).
  static std::optional<Point2> Intersection(const Line2& p, const Line2& q) {
    const double pu = double(p.second.u) - p.through.u, pv = double(p.second.v) - p.through.v;
    const double qu = double(q.second.u) - q.through.u, qv = double(q.second.v) - q.through.v;
    const double cross = pu * qv - pv * qu;
    if (!(std::fabs(cross) > std::sin(10 * M_PI / 180) * std::hypot(pu, pv) * std::hypot(qu, qv))) return std::nullopt;
    const double a = ((double(q.through.u) - p.through.u) * qv - (double(q.through.v) - p.through.v) * qu) / cross;
    return Point2{float(p.through.u + a * pu), float(p.through.v + a * pv)};
  }

  static Point2 Between(Point2 a, Point2 b, double t) {
    return {float(a.u + t * (double(b.u) - a.u)), float(a.v + t * (double(b.v) - a.v))};
  }

  static bool Convex(const std::vector<Point2>& polygon) {
    for (size_t k = 0; k < polygon.size(); ++k) {
      const size_t n = polygon.size();
      if (SignedArea(polygon[k], polygon[(k + 1) % n], polygon[(k + 2) % n]) < 0) return false;
    }
    return true;
  }

  // Each cell's covered polygon, cut to each surface triangle that its box meets, as triangles, in cell order.
  void CutPieces() {
    const std::vector<uint64_t> cells = CellsWithACoveredCorner();
    std::vector<std::vector<uint32_t>> trianglesOfCell(cells.size());
    const auto cellOf = [&](float c, float lo, int n) { return std::clamp(int(std::floor((c - lo) / c_.spacing_)), 0, n - 2); };
    for (uint32_t t : surface_.triangles) {
      Bounds2 tb;
      for (const Point2& p : surfaces_.cornerUv[t]) tb.Extend(p);
      const int i0 = cellOf(tb.lo.u, c_.lo_.u, c_.nu_), i1 = cellOf(tb.hi.u, c_.lo_.u, c_.nu_);
      for (int j = cellOf(tb.lo.v, c_.lo_.v, c_.nv_); j <= cellOf(tb.hi.v, c_.lo_.v, c_.nv_); ++j)
        for (auto c = std::lower_bound(cells.begin(), cells.end(), Key(i0, j)); c != cells.end() && *c <= Key(i1, j); ++c)
          trianglesOfCell[size_t(c - cells.begin())].push_back(t);
    }
    for (size_t k = 0; k < cells.size(); ++k) {
      const std::vector<Point2> polygon = c_.CellPolygon(int(cells[k] % uint64_t(c_.nu_)), int(cells[k] / uint64_t(c_.nu_)));
      for (uint32_t t : trianglesOfCell[k]) {
        std::array<Point2, 3> tri = surfaces_.cornerUv[t];
        if (SignedArea(tri[0], tri[1], tri[2]) < 0) std::swap(tri[1], tri[2]);
        std::vector<Point2> piece = polygon;
        for (int e = 0; e < 3 && piece.size() >= 3; ++e) piece = ClipLeftOf(piece, tri[e], tri[(e + 1) % 3]);
        if (piece.size() < 3 || !(TwiceSignedArea(piece) > 1e-12 * double(c_.spacing_) * c_.spacing_)) continue;
        for (size_t m = 1; m + 1 < piece.size(); ++m) c_.pieces_.push_back({piece[0], piece[m], piece[m + 1]});
      }
    }
  }

  // The cells with a covered corner, from the runs: each covered point's four cells. Sorted.
  std::vector<uint64_t> CellsWithACoveredCorner() const {
    std::vector<uint64_t> cells;
    const int rows = int(c_.rowStart_.size()) - 1;
    for (int j = c_.firstRow_; j < c_.firstRow_ + rows; ++j)
      for (const SurfaceCover::Run& run : c_.RowRuns(j))
        for (int cj = std::max(j - 1, 0); cj <= std::min(j, c_.nv_ - 2); ++cj)
          for (int ci = std::max(run.first - 1, 0); ci <= std::min(run.last, c_.nu_ - 2); ++ci) cells.push_back(Key(ci, cj));
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    return cells;
  }

  const Scene& scene_;
  const SurfaceSet& surfaces_;
  const RayScene& rays_;
  const Surface& surface_;
  uint32_t surfaceIndex_;
  CoverSettings settings_;
  std::array<Vector3, kCoverRays> directions_;
  SurfaceRegion whole_;  // the surface's chart triangles
  SurfaceCover c_;
};

std::array<SurfaceCover::CellEdge, 4> SurfaceCover::EdgesOf(int i, int j) const {
  const std::array<std::array<int, 2>, 4> corner = {{{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}}};
  // Each edge's crossing is stored at its first end (the lower i or j) and computed from there, so the two cells
  // that share an edge share the point bit for bit.
  const std::array<std::array<int, 3>, 4> stored = {{{i, j, 0}, {i + 1, j, 1}, {i, j + 1, 0}, {i, j, 1}}};
  const std::array<Point2, 4> inward = {{{0, 1}, {-1, 0}, {0, -1}, {1, 0}}};
  std::array<CellEdge, 4> edges;
  for (int k = 0; k < 4; ++k) {
    const auto [ia, ja] = corner[k];
    const auto [ib, jb] = corner[(k + 1) % 4];
    CellEdge& e = edges[k];
    e = {Lattice(ia, ja), Lattice(ib, jb), CoveredPoint(ia, ja), CoveredPoint(ib, jb), inward[k], {}};
    if (e.coveredA == e.coveredB) continue;
    const auto [ei, ej, axis] = stored[k];
    const float t = crossing_.at(EdgeKey(size_t(ej) * nu_ + ei, axis));
    const Point2 p = Lattice(ei, ej), q = Lattice(ei + (axis == 0), ej + (axis == 1));
    e.crossing = {p.u + t * (q.u - p.u), p.v + t * (q.v - p.v)};
  }
  return edges;
}

std::vector<Point2> SurfaceCover::CellPolygon(int i, int j, const Point2* corner) const {
  if (corner == nullptr) {
    const auto found = corners_.find(size_t(j) * nu_ + i);
    if (found != corners_.end()) corner = &found->second;
  }
  std::vector<Point2> polygon;
  for (const CellEdge& e : EdgesOf(i, j)) {
    if (e.coveredA) polygon.push_back(e.a);
    if (e.coveredA == e.coveredB) continue;
    polygon.push_back(e.crossing);
    if (e.coveredA && corner != nullptr) polygon.push_back(*corner);  // the line turns before it re-enters
  }
  return polygon;
}

std::span<const SurfaceCover::Run> SurfaceCover::RowRuns(int j) const {
  const int k = j - firstRow_;
  if (k < 0 || k + 1 >= int(rowStart_.size())) return {};
  return {runs_.data() + rowStart_[size_t(k)], runs_.data() + rowStart_[size_t(k) + 1]};
}

bool SurfaceCover::CoveredPoint(int i, int j) const {
  const std::span<const Run> row = RowRuns(j);
  const auto after = std::upper_bound(row.begin(), row.end(), i, [](int x, const Run& run) { return x < run.first; });
  return after != row.begin() && i <= std::prev(after)->last;
}

bool SurfaceCover::InCell(Point2 uv, int i, int j) const {
  const Point2 lo = Lattice(i, j), hi = Lattice(i + 1, j + 1);
  return uv.u > lo.u && uv.u < hi.u && uv.v > lo.v && uv.v < hi.v;
}

bool SurfaceCover::Covered(Point2 uv) const {
  if (pieces_.empty()) return false;
  const float fu = (uv.u - lo_.u) / spacing_, fv = (uv.v - lo_.v) / spacing_;
  if (!(fu >= 0 && fv >= 0 && fu <= float(nu_ - 1) && fv <= float(nv_ - 1))) return false;
  const int i = std::min(int(fu), nu_ - 2), j = std::min(int(fv), nv_ - 2);
  const std::vector<Point2> polygon = CellPolygon(i, j);
  if (polygon.size() < 3) return false;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Point2 a = polygon[k], b = polygon[(k + 1) % polygon.size()];
    if ((double(b.u) - a.u) * (double(uv.v) - a.v) - (double(b.v) - a.v) * (double(uv.u) - a.u) < 0) return false;
  }
  return true;
}

double SurfaceCover::Area() const {
  double area = 0;
  for (const Triangle2& t : pieces_) area += SignedArea(t[0], t[1], t[2]);
  return area;
}

std::vector<SurfaceCover> FindCovers(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays,
                                     const CoverSettings& settings, const WorkProgress& advance) {
  std::vector<SurfaceCover> covers(surfaces.surfaces.size());
  if (!(settings.spacing > 0)) return covers;
  CoverSettings scaled = settings;
  if (settings.maxSpacingPerDiagonal > 0) {
    const double diagonal = scene.Diagonal();
    if (diagonal > 0) scaled.spacing = float(std::min(double(settings.spacing), settings.maxSpacingPerDiagonal * diagonal));
  }
  if (!(scaled.spacing < FLT_MAX)) return covers;  // a scene of no extent, whose spacing only the diagonal set
  const auto tested = [&](const Surface& surface) {
    return surface.planar && !scene.materials[surface.material].IsEmissive();
  };
  uint64_t total = 0;
  for (const Surface& surface : surfaces.surfaces) total += tested(surface) ? surface.triangles.size() : 0;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const Surface& surface = surfaces.surfaces[s];
    if (!tested(surface)) continue;
    covers[s] = CoverBuilder(scene, surfaces, rays, s, scaled).Build();
    if (advance) advance(surface.triangles.size(), total);
  }
  return covers;
}

}  // namespace pb
