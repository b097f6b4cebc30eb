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

#include "estimators/chart_clip.h"
#include "estimators/cover_band.h"
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
    const std::vector<uint64_t> band = BandPoints(CellsWhereTheCoverCanChange(
        {scene_, surfaces_, rays_, surfaceIndex_}, {c_.lo_, c_.spacing_, c_.nu_, c_.nv_}, whole_.Bounds()));
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
