#include "estimators/surface_cover.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "estimators/surface_region.h"

namespace pb {
namespace {

constexpr int kBisections = 10;  // the contact line to s / 1024

// kCoverRays directions about +z, cosine-weighted on a golden-angle spiral: the same for every point.
std::array<Vector3, kCoverRays> HemisphereSpiral() {
  std::array<Vector3, kCoverRays> d;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < kCoverRays; ++k) {
    const double u = (k + 0.5) / kCoverRays, r = std::sqrt(u), phi = k * golden;
    d[k] = {float(r * std::cos(phi)), float(r * std::sin(phi)), float(std::sqrt(1.0 - u))};
  }
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
    double spacing = settings_.spacing;
    while ((su / spacing + 3) * (sv / spacing + 3) > double(settings_.maxPointsPerSurface)) spacing *= 2;
    c_.spacing_ = float(spacing);
    c_.lo_ = {float(b.lo.u - spacing / 2), float(b.lo.v - spacing / 2)};
    c_.nu_ = int(std::ceil(su / spacing)) + 2;  // from half a spacing before the chart to at least half after
    c_.nv_ = int(std::ceil(sv / spacing)) + 2;
    ClassifyLattice();
    if (std::find(c_.covered_.begin(), c_.covered_.end(), 1) == c_.covered_.end()) return {};
    FindCrossings();
    FindCorners();
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

  void ClassifyLattice() {
    c_.covered_.assign(size_t(c_.nu_) * c_.nv_, 0);
    tbb::parallel_for(0, c_.nv_, [&](int j) {
      for (int i = 0; i < c_.nu_; ++i) c_.covered_[size_t(j) * c_.nu_ + i] = CoveredAt(c_.Lattice(i, j));
    });
  }

  // On each lattice edge whose ends differ, the fraction of the way from its first end where the cover changes.
  void FindCrossings() {
    c_.crossing_.assign(size_t(c_.nu_) * c_.nv_ * 2, NAN);
    tbb::parallel_for(0, c_.nv_, [&](int j) {
      for (int i = 0; i < c_.nu_; ++i)
        for (int axis = 0; axis < 2; ++axis) {
          const int i1 = i + (axis == 0), j1 = j + (axis == 1);
          if (i1 >= c_.nu_ || j1 >= c_.nv_ || c_.CoveredPoint(i, j) == c_.CoveredPoint(i1, j1)) continue;
          c_.crossing_[(size_t(j) * c_.nu_ + i) * 2 + axis] = Bisect(c_.Lattice(i, j), c_.Lattice(i1, j1), c_.CoveredPoint(i, j));
        }
    });
  }

  // Where along a -> b the cover changes, to 1 / 2^kBisections, rounded toward the covered end.
  float Bisect(Point2 a, Point2 b, bool coveredAtA) const {
    float lo = 0, hi = 1;
    for (int k = 0; k < kBisections; ++k) {
      const float mid = 0.5f * (lo + hi);
      const Point2 m{a.u + mid * (b.u - a.u), a.v + mid * (b.v - a.v)};
      (CoveredAt(m) == coveredAtA ? lo : hi) = mid;
    }
    return coveredAtA ? lo : hi;  // on the covered side: no photon that reached the surface lands in the cover
  }

  // Cells whose polygon has one crossing where the cover ends and one where it begins again: where the contact
  // line turns a corner between them, the corner (SurfaceCover::corners_).
  void FindCorners() {
    std::vector<std::optional<Point2>> corner(size_t(c_.nu_) * c_.nv_);
    tbb::parallel_for(0, c_.nv_ - 1, [&](int j) {
      for (int i = 0; i + 1 < c_.nu_; ++i) corner[size_t(j) * c_.nu_ + i] = CornerIn(i, j);
    });
    for (size_t cell = 0; cell < corner.size(); ++cell)
      if (corner[cell]) c_.corners_.emplace(cell, *corner[cell]);
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

  // Each cell's covered polygon, cut to each surface triangle that its box meets, as triangles.
  void CutPieces() {
    std::unordered_map<size_t, std::vector<uint32_t>> trianglesOfCell;
    const auto cellOf = [&](float c, float lo, int n) { return std::clamp(int(std::floor((c - lo) / c_.spacing_)), 0, n - 2); };
    for (uint32_t t : surface_.triangles) {
      Bounds2 tb;
      for (const Point2& p : surfaces_.cornerUv[t]) tb.Extend(p);
      for (int j = cellOf(tb.lo.v, c_.lo_.v, c_.nv_); j <= cellOf(tb.hi.v, c_.lo_.v, c_.nv_); ++j)
        for (int i = cellOf(tb.lo.u, c_.lo_.u, c_.nu_); i <= cellOf(tb.hi.u, c_.lo_.u, c_.nu_); ++i)
          if (AnyCornerCovered(i, j)) trianglesOfCell[size_t(j) * c_.nu_ + i].push_back(t);
    }
    std::vector<size_t> cells;
    for (const auto& [cell, triangles] : trianglesOfCell) cells.push_back(cell);
    std::sort(cells.begin(), cells.end());  // pieces in lattice order, whatever the hash map's
    for (size_t cell : cells) {
      const std::vector<Point2> polygon = c_.CellPolygon(int(cell % c_.nu_), int(cell / c_.nu_));
      for (uint32_t t : trianglesOfCell[cell]) {
        std::array<Point2, 3> tri = surfaces_.cornerUv[t];
        if (SignedArea(tri[0], tri[1], tri[2]) < 0) std::swap(tri[1], tri[2]);
        std::vector<Point2> piece = polygon;
        for (int k = 0; k < 3 && piece.size() >= 3; ++k) piece = ClipLeftOf(piece, tri[k], tri[(k + 1) % 3]);
        if (piece.size() < 3 || !(TwiceSignedArea(piece) > 1e-12 * double(c_.spacing_) * c_.spacing_)) continue;
        for (size_t k = 1; k + 1 < piece.size(); ++k) c_.pieces_.push_back({piece[0], piece[k], piece[k + 1]});
      }
    }
  }

  bool AnyCornerCovered(int i, int j) const {
    return c_.CoveredPoint(i, j) || c_.CoveredPoint(i + 1, j) || c_.CoveredPoint(i + 1, j + 1) || c_.CoveredPoint(i, j + 1);
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
    const float t = crossing_[(size_t(ej) * nu_ + ei) * 2 + axis];
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
                                     const CoverSettings& settings) {
  std::vector<SurfaceCover> covers(surfaces.surfaces.size());
  if (!(settings.spacing > 0)) return covers;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const Surface& surface = surfaces.surfaces[s];
    if (!surface.planar || scene.materials[surface.material].IsEmissive()) continue;
    covers[s] = CoverBuilder(scene, surfaces, rays, s, settings).Build();
  }
  return covers;
}

}  // namespace pb
