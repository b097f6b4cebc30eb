#include "estimators/surface_region.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "estimators/quadrature.h"

namespace pb {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr int kMaxCellsPerAxis = 1024;

double Cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }
double SignedArea(const Triangle2& t) { return pb::SignedArea(t[0], t[1], t[2]); }

// Counter-clockwise copies, with -0 made +0: one corner, one atan2 angle (KernelMass).
std::vector<Triangle2> CounterClockwise(std::span<const Triangle2> triangles) {
  std::vector<Triangle2> out;
  out.reserve(triangles.size());
  for (Triangle2 t : triangles) {
    for (Point2& p : t) p = {p.u + 0.0f, p.v + 0.0f};
    if (SignedArea(t) < 0) std::swap(t[1], t[2]);
    out.push_back(t);
  }
  return out;
}

// The least and greatest u of segment ab within the strip v0 <= v <= v1 (its ends' u where it runs along v).
std::pair<double, double> USpanInStrip(Point2 a, Point2 b, double v0, double v1) {
  if (a.v == b.v) return {std::min(a.u, b.u), std::max(a.u, b.u)};
  const double dv = double(b.v) - a.v, du = double(b.u) - a.u;
  const double ua = a.u + du * std::clamp((v0 - a.v) / dv, 0.0, 1.0), ub = a.u + du * std::clamp((v1 - a.v) / dv, 0.0, 1.0);
  return {std::min(ua, ub), std::max(ua, ub)};
}

uint64_t Bits(Point2 p) {
  const float c[2] = {p.u + 0.0f, p.v + 0.0f};  // + 0.0f maps -0 to +0
  uint64_t bits;
  std::memcpy(&bits, c, sizeof bits);
  return bits;
}

struct HalfEdgeKey {
  uint64_t a, b;
  bool operator==(const HalfEdgeKey&) const = default;
};
struct HalfEdgeHash {
  size_t operator()(const HalfEdgeKey& k) const { return std::hash<uint64_t>()(k.a * 0x9E3779B97F4A7C15ull ^ k.b); }
};

// The half-edges of counter-clockwise `triangles` whose reverse none of them has: the boundary of their union,
// with the union on the left, in triangle order. Interior edges cancel exactly; T-junctions leave collinear
// pieces that cancel numerically. By sorting the half-edges on their undirected key, not by a hash set: on a
// surface of 10^6 triangles the set's cache misses were a third of a bake's time, and grew faster than the
// triangles.
std::vector<std::array<Point2, 2>> Boundary(const std::vector<Triangle2>& triangles) {
  struct Half {
    uint64_t lo, hi;  // the corners' bits, smaller first
    uint32_t index;   // 3 t + k: the half-edge from corner k of triangle t
    bool forward;     // it runs from lo to hi
  };
  std::vector<Half> halves;
  halves.reserve(3 * triangles.size());
  for (uint32_t t = 0; t < triangles.size(); ++t)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint64_t a = Bits(triangles[t][k]), b = Bits(triangles[t][(k + 1) % 3]);
      halves.push_back({std::min(a, b), std::max(a, b), 3 * t + k, a < b});
    }
  std::sort(halves.begin(), halves.end(),
            [](const Half& x, const Half& y) { return x.lo != y.lo ? x.lo < y.lo : x.hi < y.hi; });
  // A group of half-edges on one undirected edge is boundary where all of them run the same way.
  std::vector<bool> onBoundary(halves.size(), false);
  for (size_t first = 0; first < halves.size();) {
    size_t end = first;
    bool forward = false, backward = false;
    for (; end < halves.size() && halves[end].lo == halves[first].lo && halves[end].hi == halves[first].hi; ++end)
      (halves[end].forward ? forward : backward) = true;
    if (forward != backward && halves[first].lo != halves[first].hi)  // a zero-length edge is its own reverse
      for (size_t i = first; i < end; ++i) onBoundary[halves[i].index] = true;
    first = end;
  }
  std::vector<std::array<Point2, 2>> boundary;
  for (uint32_t i = 0; i < onBoundary.size(); ++i)
    if (onBoundary[i]) boundary.push_back({triangles[i / 3][i % 3], triangles[i / 3][(i % 3 + 1) % 3]});
  return boundary;
}

using Segment = std::array<Point2, 2>;

// The boundary of the triangles less the holes: the triangles' boundary edges, and the holes' reversed; where the
// two run along each other, they cancel.
std::vector<Segment> BoundaryLessHoles(const std::vector<Triangle2>& triangles, const std::vector<Triangle2>& holes) {
  std::vector<Segment> edges = Boundary(triangles);
  if (holes.empty()) return edges;
  std::unordered_map<HalfEdgeKey, size_t, HalfEdgeHash> outer;
  for (size_t e = 0; e < edges.size(); ++e) outer.emplace(HalfEdgeKey{Bits(edges[e][0]), Bits(edges[e][1])}, e);
  std::vector<uint8_t> cancelled(edges.size(), 0);
  std::vector<Segment> inner;
  for (const auto& [a, b] : Boundary(holes)) {
    const auto it = outer.find({Bits(a), Bits(b)});
    if (it != outer.end() && !cancelled[it->second]) cancelled[it->second] = 1;
    else inner.push_back({b, a});
  }
  std::vector<Segment> kept;
  for (size_t e = 0; e < edges.size(); ++e)
    if (!cancelled[e]) kept.push_back(edges[e]);
  kept.insert(kept.end(), inner.begin(), inner.end());
  return kept;
}

// Whether c lies ahead of s along the unit direction t and within `tolerance` [m] of the line through s along t.
bool AlongLine(Point2 s, std::array<double, 2> t, Point2 c, double tolerance) {
  const double cx = double(c.u) - s.u, cy = double(c.v) - s.v;
  return cx * t[0] + cy * t[1] > 0 && std::fabs(Cross(t[0], t[1], cx, cy)) <= tolerance;
}

std::array<double, 2> UnitDirection(const Segment& e) {
  const double x = double(e[1].u) - e[0].u, y = double(e[1].v) - e[0].v, l = std::hypot(x, y);
  return l > 0 ? std::array<double, 2>{x / l, y / l} : std::array<double, 2>{0, 0};
}

// The boundary with each straight run of edges joined into one edge: a run continues through a corner that ends
// one edge and starts one other, and while every corner stays within `tolerance` [m] of the line along the run's
// first edge. A face gridded at 2.5 cm has 160 boundary edges a 4 m side; the kernel's edge moments integrate
// every edge within h of a point, so without this a query's cost grew with h over the grid's cell (the moments
// were half of a bake of such a scene), and with it the cost is that of the region's true corners. Closed loops
// stay closed (the joined edges run between existing corners), so the telescoping angle sums still cancel.
std::vector<Segment> JoinStraightRuns(const std::vector<Segment>& edges, double tolerance) {
  constexpr uint32_t kNone = UINT32_MAX;
  // Each corner's outgoing and incoming edges, by sorting on the corner's bits (a hash map's misses cost more).
  std::vector<std::pair<uint64_t, uint32_t>> starts, ends;
  for (uint32_t e = 0; e < edges.size(); ++e) starts.emplace_back(Bits(edges[e][0]), e), ends.emplace_back(Bits(edges[e][1]), e);
  std::sort(starts.begin(), starts.end()), std::sort(ends.begin(), ends.end());
  const auto only = [](const std::vector<std::pair<uint64_t, uint32_t>>& sorted, uint64_t corner) {
    const auto lo = std::lower_bound(sorted.begin(), sorted.end(), std::pair{corner, 0u});
    return lo != sorted.end() && lo->first == corner && (lo + 1 == sorted.end() || (lo + 1)->first != corner) ? lo->second : kNone;
  };
  std::vector<uint32_t> next(edges.size(), kNone), previous(edges.size(), kNone);
  for (uint32_t e = 0; e < edges.size(); ++e) {
    const uint64_t corner = Bits(edges[e][1]);
    const uint32_t f = only(starts, corner);
    if (f != kNone && f != e && only(ends, corner) == e) next[e] = f, previous[f] = e;
  }
  std::vector<uint8_t> visited(edges.size(), 0);
  std::vector<Segment> joined;
  const auto walk = [&](uint32_t e) {  // from edge e, run after run, until an edge already joined or a dead end
    while (e != kNone && !visited[e]) {
      visited[e] = 1;
      const Point2 s = edges[e][0];
      const std::array<double, 2> t = UnitDirection(edges[e]);
      Point2 end = edges[e][1];
      uint32_t f = next[e];
      for (; f != kNone && !visited[f] && AlongLine(s, t, edges[f][1], tolerance); f = next[f]) visited[f] = 1, end = edges[f][1];
      joined.push_back({s, end});
      e = f;
    }
  };
  for (uint32_t e = 0; e < edges.size(); ++e) {  // first from each run's first edge
    const uint32_t p = previous[e];
    if (p == kNone || !AlongLine(edges[p][0], UnitDirection(edges[p]), edges[e][1], tolerance)) walk(e);
  }
  for (uint32_t e = 0; e < edges.size(); ++e) walk(e);  // loops with no corner (degenerate)
  return joined;
}

// Signed integral of K_h(|y - x|) over the fan triangle (x, a, b): positive when a -> b turns counter-clockwise
// about x. Parameterised by arc length s along the edge from the foot of the perpendicular from x.
double EdgeMass(Point2 a, Point2 b, Point2 x, Kernel kernel, double h) {
  const double px = double(a.u) - x.u, py = double(a.v) - x.v;
  const double ex = double(b.u) - a.u, ey = double(b.v) - a.v, length = std::hypot(ex, ey);
  if (length == 0) return 0;
  const double signedDistance = Cross(px, py, ex / length, ey / length);
  const double d = std::fabs(signedDistance);
  if (d <= 1e-12 * (length + std::hypot(px, py))) return 0;  // x on the edge's line: a degenerate fan
  const double sa = (px * ex + py * ey) / length, sb = sa + length;
  const double gMax = 1.0 / kTwoPi;
  const double angle = std::atan(sb / d) - std::atan(sa / d);
  double mass = gMax * angle;
  if (d < h) {  // the part of the edge inside the kernel's support: G(r/h) < G(1) there
    const double sh = std::sqrt(h * h - d * d), lo = std::max(sa, -sh), hi = std::min(sb, sh);
    if (lo < hi) {
      const auto integrand = [&](double s) { return d / (h * h) * KernelRadialMassOverSquare(kernel, std::hypot(d, s) / h); };
      double inner = 0;
      if (lo < 0) inner += GaussLegendre(integrand, lo, std::min(hi, 0.0));  // split at s = 0: the cone's kink
      if (hi > 0) inner += GaussLegendre(integrand, std::max(lo, 0.0), hi);
      mass += inner - gMax * (std::atan(hi / d) - std::atan(lo / d));
    }
  }
  return signedDistance > 0 ? mass : -mass;
}

// Six values integrated together (GaussLegendre): an edge's mass and moment integrands.
struct Six {
  std::array<double, 6> v{};
  Six operator+(const Six& o) const {
    Six r;
    for (int k = 0; k < 6; ++k) r.v[k] = v[k] + o.v[k];
    return r;
  }
  Six operator*(double c) const {
    Six r;
    for (int k = 0; k < 6; ++k) r.v[k] = v[k] * c;
    return r;
  }
  Six operator/(double c) const {
    Six r;
    for (int k = 0; k < 6; ++k) r.v[k] = v[k] / c;
    return r;
  }
  friend Six operator*(double c, const Six& s) { return s * c; }
};

// An edge's contribution to the kernel's moments about x beyond what G_n(1) everywhere would give (surface_region.h,
// Moments): over the part of the edge inside the support, the integral of (G_n(t) - G_n(1)) times 1, u or u u^T
// over the angle it subtends (u the unit direction from x). G_n(t) vanishes like t^(n+2) at x, so G_n(t) d(theta) =
// G_n(t) d / r^2 ds is smooth along the edge; the G_n(1) part is subtracted in closed form. Zero for an edge
// outside the support or through x.
KernelMomentsAt EdgeMomentsInside(Point2 a, Point2 b, Point2 x, Kernel kernel, double h) {
  KernelMomentsAt m{0, {0, 0}, {0, 0, 0}};
  const double px = double(a.u) - x.u, py = double(a.v) - x.v;
  const double ex = double(b.u) - a.u, ey = double(b.v) - a.v, length = std::hypot(ex, ey);
  if (length == 0) return m;
  const double tx = ex / length, ty = ey / length, signedDistance = Cross(px, py, tx, ty), d = std::fabs(signedDistance);
  if (d <= 1e-12 * (length + std::hypot(px, py)) || d >= h) return m;
  const double sa = (px * ex + py * ey) / length, sb = sa + length;
  const double sh = std::sqrt(h * h - d * d), lo = std::max(sa, -sh), hi = std::min(sb, sh);
  if (!(lo < hi)) return m;
  const double sign = signedDistance > 0 ? 1 : -1, fx = px - sa * tx, fy = py - sa * ty;  // f: x to the foot
  const double g[3] = {KernelRadialMoment(kernel, 0, 1), KernelRadialMoment(kernel, 1, 1), KernelRadialMoment(kernel, 2, 1)};
  // All six integrands at once, at arc length s: G_n(t) u^(n) d / r^2 (the G_n(1) part comes after); each G_n
  // once per node.
  const auto at = [&](double s) {
    const double ux = fx + s * tx, uy = fy + s * ty, r2 = ux * ux + uy * uy, r = std::sqrt(r2), t = r / h;
    const double w = d / r2, g0 = KernelRadialMoment(kernel, 0, t), g1 = KernelRadialMoment(kernel, 1, t),
                 g2 = KernelRadialMoment(kernel, 2, t);
    return Six{{g0 * w, g1 * w * ux / r, g1 * w * uy / r, g2 * w * ux * ux / r2, g2 * w * ux * uy / r2, g2 * w * uy * uy / r2}};
  };
  Six sum{};
  if (lo < 0) sum = sum + GaussLegendre(at, lo, std::min(hi, 0.0));  // split at the foot: the cone's kink
  if (hi > 0) sum = sum + GaussLegendre(at, std::max(lo, 0.0), hi);
  const std::array<double, 6>& integral = sum.v;
  // The closed forms over the same angle: integral of 1, u and u u^T d(theta) from the direction at lo to hi.
  const double angle = std::atan(hi / d) - std::atan(lo / d);
  const double rl = std::hypot(d, lo), rh = std::hypot(d, hi);
  const double cl = (fx + lo * tx) / rl, sl = (fy + lo * ty) / rl, ch = (fx + hi * tx) / rh, shi = (fy + hi * ty) / rh;
  // Signed as the edge turns about x: d(theta) has the sign of signedDistance along increasing s.
  const double turn = sign * angle;
  const double first[2] = {shi - sl, cl - ch};  // integral of (cos, sin) d(theta) = (sin, -cos)
  const double sin2 = 2 * shi * ch - 2 * sl * cl, cos2 = (ch * ch - shi * shi) - (cl * cl - sl * sl);
  const double second[3] = {turn / 2 + sin2 / 4, -cos2 / 4, turn / 2 - sin2 / 4};
  m.mass = sign * integral[0] - g[0] * turn;
  m.first = {sign * integral[1] - g[1] * first[0], sign * integral[2] - g[1] * first[1]};
  m.second = {sign * integral[3] - g[2] * second[0], sign * integral[4] - g[2] * second[1], sign * integral[5] - g[2] * second[2]};
  return m;
}

// c - x, never -0: atan2 tells -0 from +0 (atan2(-0, -1) = -pi), and a corner on the cut must get the angle its
// classification as above the cut (offset >= 0) implies.
double Offset(float c, double x) { return (double(c) - x) + 0.0; }

double SegmentDistanceSquared(Point2 a, Point2 b, Point2 x) {
  const double ex = double(b.u) - a.u, ey = double(b.v) - a.v, px = double(x.u) - a.u, py = double(x.v) - a.v;
  const double l2 = ex * ex + ey * ey;
  const double t = l2 > 0 ? std::clamp((px * ex + py * ey) / l2, 0.0, 1.0) : 0.0;
  const double dx = px - t * ex, dy = py - t * ey;
  return dx * dx + dy * dy;
}

// Sutherland-Hodgman: keep the part of `polygon` where sign * (coordinate axis of p - bound) <= 0.
std::vector<Point2> ClipAgainst(const std::vector<Point2>& polygon, int axis, float bound, float sign) {
  std::vector<Point2> out;
  const auto value = [&](Point2 p) { return sign * ((axis == 0 ? p.u : p.v) - bound); };
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Point2 p = polygon[i], q = polygon[(i + 1) % polygon.size()];
    const float vp = value(p), vq = value(q);
    if (vp <= 0) out.push_back(p);
    if ((vp < 0) != (vq < 0) && vp != 0 && vq != 0) {
      const float t = vp / (vp - vq);
      out.push_back({p.u + t * (q.u - p.u), p.v + t * (q.v - p.v)});
    }
  }
  return out;
}

}  // namespace

double TriangleBoxOverlapArea(const Triangle2& triangle, const Bounds2& box) {
  std::vector<Point2> polygon(triangle.begin(), triangle.end());
  polygon = ClipAgainst(polygon, 0, box.hi.u, 1.0f);
  polygon = ClipAgainst(polygon, 0, box.lo.u, -1.0f);
  polygon = ClipAgainst(polygon, 1, box.hi.v, 1.0f);
  polygon = ClipAgainst(polygon, 1, box.lo.v, -1.0f);
  double twiceArea = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Point2 p = polygon[i], q = polygon[(i + 1) % polygon.size()];
    twiceArea += double(p.u) * q.v - double(q.u) * p.v;
  }
  return std::fabs(twiceArea) / 2;
}

SurfaceRegion::SurfaceRegion(std::span<const Triangle2> triangles, std::span<const Triangle2> holes)
    : triangles_(CounterClockwise(triangles)), holes_(CounterClockwise(holes)) {
  for (const Triangle2& t : triangles_) {
    area_ += SignedArea(t);
    for (const Point2& p : t) bounds_.Extend(p);
  }
  for (const Triangle2& t : holes_) area_ -= SignedArea(t);
  const double su = double(bounds_.hi.u) - bounds_.lo.u, sv = double(bounds_.hi.v) - bounds_.lo.v;
  // A millionth of the region's size: float corners on one straight side of a gridded face stray a few ulps.
  for (const auto& [a, b] : JoinStraightRuns(BoundaryLessHoles(triangles_, holes_), 1e-6 * std::max(su, sv)))
    edges_.push_back({a, b});
  if (edges_.empty()) return;

  cell_ = std::max({su, sv, 1e-30}) / std::clamp(int(std::ceil(std::sqrt(double(edges_.size())))), 1, kMaxCellsPerAxis);
  nu_ = std::clamp(int(su / cell_) + 1, 1, kMaxCellsPerAxis + 1);
  nv_ = std::clamp(int(sv / cell_) + 1, 1, kMaxCellsPerAxis + 1);
  std::vector<std::vector<uint32_t>> cells(size_t(nu_) * nv_);
  std::vector<std::vector<std::pair<int, uint32_t>>> ends(static_cast<size_t>(nv_));
  spanCrossings_.assign(size_t(nu_ + 1) * nv_, 0);
  // Each edge in the cells it passes through, row by row, and one either side for rounding: the cells of its
  // bounding box would be O(length^2 / cell^2) for a long slanted edge (a 65,536-corner star's spikes listed 10^8).
  for (uint32_t e = 0; e < edges_.size(); ++e) {
    const Edge& edge = edges_[e];
    const int v0 = CellOf(edge.a.u, std::min(edge.a.v, edge.b.v))[1];
    const int v1 = CellOf(edge.a.u, std::max(edge.a.v, edge.b.v))[1];
    for (int cv = v0; cv <= v1; ++cv) {
      const auto [ua, ub] = USpanInStrip(edge.a, edge.b, StripLow(cv), StripHigh(cv));
      const int u0 = std::max(CellOf(ua, edge.a.v)[0] - 1, 0), u1 = std::min(CellOf(ub, edge.a.v)[0] + 1, nu_ - 1);
      for (int cu = u0; cu <= u1; ++cu) cells[size_t(cv) * nu_ + cu].push_back(e);
      if (SpansStrip(edge, cv)) spanCrossings_[size_t(cv) * (nu_ + 1) + u1 + 1] += edge.a.v > edge.b.v ? 1 : -1;
      else ends[size_t(cv)].emplace_back(u0, e);
    }
  }
  cellStart_.push_back(0);
  for (const auto& c : cells) {
    cellEdges_.insert(cellEdges_.end(), c.begin(), c.end());
    cellStart_.push_back(uint32_t(cellEdges_.size()));
  }
  rowEndStart_.push_back(0);
  for (int cv = 0; cv < nv_; ++cv) {
    std::sort(ends[size_t(cv)].begin(), ends[size_t(cv)].end());
    rowEnds_.insert(rowEnds_.end(), ends[size_t(cv)].begin(), ends[size_t(cv)].end());
    rowEndStart_.push_back(uint32_t(rowEnds_.size()));
    int* row = &spanCrossings_[size_t(cv) * (nu_ + 1)];
    for (int k = 1; k <= nu_; ++k) row[k] += row[k - 1];
  }
}

std::array<int, 2> SurfaceRegion::CellOf(double u, double v) const {
  return {std::clamp(int(std::floor((u - bounds_.lo.u) / cell_)), 0, nu_ - 1),
          std::clamp(int(std::floor((v - bounds_.lo.v) / cell_)), 0, nv_ - 1)};
}

std::vector<uint32_t> SurfaceRegion::EdgesWithin(Point2 x, double radius) const {
  std::vector<uint32_t> near;
  if (edges_.empty()) return near;
  const auto [u0, v0] = CellOf(x.u - radius, x.v - radius);
  const auto [u1, v1] = CellOf(x.u + radius, x.v + radius);
  for (int cv = v0; cv <= v1; ++cv)
    for (int cu = u0; cu <= u1; ++cu) {
      const size_t c = size_t(cv) * nu_ + cu;
      for (uint32_t i = cellStart_[c]; i < cellStart_[c + 1]; ++i) {
        const Edge& e = edges_[cellEdges_[i]];
        if (SegmentDistanceSquared(e.a, e.b, x) < radius * radius) near.push_back(cellEdges_[i]);
      }
    }
  std::sort(near.begin(), near.end());
  near.erase(std::unique(near.begin(), near.end()), near.end());  // an edge is listed in every cell it spans
  return near;
}

namespace {

// Where edge a -> b crosses the line v = y (u clamped to the edge's own span against round-off), and how: +1
// downward (a at or above y, b below), -1 upward, 0 when it does not cross.
struct LineCrossing {
  double u = 0;
  int sign = 0;
};
LineCrossing CrossingOf(Point2 a, Point2 b, double y) {
  const bool aAbove = Offset(a.v, y) >= 0, bAbove = Offset(b.v, y) >= 0;
  if (aAbove == bAbove) return {};
  const double t = (y - a.v) / (double(b.v) - a.v);
  return {std::clamp(a.u + t * (double(b.u) - a.u), double(std::min(a.u, b.u)), double(std::max(a.u, b.u))),
          aAbove ? 1 : -1};
}

// Edge a -> b's signed crossing of the ray from x toward -u, or 0.
int CutCrossing(Point2 a, Point2 b, Point2 x) {
  const LineCrossing c = CrossingOf(a, b, x.v);
  return c.u < x.u ? c.sign : 0;
}

}  // namespace

int SurfaceRegion::CutCrossings(Point2 x) const {
  if (edges_.empty()) return 0;
  const auto [last, row] = CellOf(x.u, x.v);
  if (!(x.v >= StripLow(row) && x.v < StripHigh(row))) return CutCrossingsScanningRow(x);
  // The spanning edges left of x's cell cross left of x; those listed in its cell are tested; the rest lie right.
  int crossings = spanCrossings_[size_t(row) * (nu_ + 1) + last];
  const size_t c = size_t(row) * nu_ + last;
  for (uint32_t i = cellStart_[c]; i < cellStart_[c + 1]; ++i) {
    const Edge& e = edges_[cellEdges_[i]];
    if (SpansStrip(e, row)) crossings += CutCrossing(e.a, e.b, x);
  }
  for (uint32_t i = rowEndStart_[row]; i < rowEndStart_[row + 1] && rowEnds_[i].first <= last; ++i) {
    const Edge& e = edges_[rowEnds_[i].second];
    crossings += CutCrossing(e.a, e.b, x);
  }
  return crossings;
}

int SurfaceRegion::CutCrossingsBeyond(Point2 x, std::span<const uint32_t> near) const {
  int crossings = CutCrossings(x);
  for (uint32_t i : near) crossings -= CutCrossing(edges_[i].a, edges_[i].b, x);
  return crossings;
}

int SurfaceRegion::CutCrossingsScanningRow(Point2 x) const {
  const auto [last, row] = CellOf(x.u, x.v);
  int crossings = 0;
  for (int cu = 0; cu <= last; ++cu) {
    const size_t c = size_t(row) * nu_ + cu;
    for (uint32_t i = cellStart_[c]; i < cellStart_[c + 1]; ++i) {
      const Edge& e = edges_[cellEdges_[i]];
      const LineCrossing c = CrossingOf(e.a, e.b, x.v);
      if (c.u < x.u && CellOf(c.u, x.v)[0] == cu) crossings += c.sign;  // counted in its own cell alone
    }
  }
  return crossings;
}

// Only the edges within h are integrated. Every other edge lies where G(r/h) = G(1) = 1/(2 pi), so together they
// add the angle they subtend over 2 pi. With theta = atan2 about x at each corner, an edge's angle is its turn
// theta_b - theta_a plus 2 pi for each crossing of atan2's cut (the ray from x toward -u), in the sense it
// crosses. The turns of all boundary edges add to zero, since every corner is left as often as it is reached;
// so the far edges' turns are minus the near edges' turns, and their cut crossings are all the cut's crossings
// (CutCrossings: one cell and the row's sums) less the near edges'. The cost is that of the edges near x and of
// the edges that end in x's row, however long the boundary is.
double SurfaceRegion::KernelMass(Point2 x, Kernel kernel, double h) const {
  const std::vector<uint32_t> near = EdgesWithin(x, h);
  if (near.empty()) return 1.0;
  const auto theta = [&](Point2 p) { return std::atan2(Offset(p.v, x.v), Offset(p.u, x.u)); };
  double mass = 0, nearTurn = 0;
  for (uint32_t i : near) {
    const Edge& e = edges_[i];
    mass += EdgeMass(e.a, e.b, x, kernel, h);
    nearTurn += theta(e.b) - theta(e.a);
  }
  const double farAngle = -nearTurn + kTwoPi * CutCrossingsBeyond(x, near);
  return std::clamp(mass + farAngle / kTwoPi, 0.0, 1.0);
}

// As KernelMass, the far boundary enters through closed forms: with G_n(1) everywhere, the boundary's integrals of
// u d(theta) and of the sin 2theta, cos 2theta parts of u u^T d(theta) telescope to zero round its closed loops
// (sin and cos of each corner's angle are single-valued), and its theta / 2 part is half the angle A it subtends.
// An edge through x subtends nothing, so its share of the telescoped sums is taken back out.
KernelMomentsAt SurfaceRegion::Moments(Point2 x, Kernel kernel, double h) const {
  const double g0 = KernelRadialMoment(kernel, 0, 1), g1 = KernelRadialMoment(kernel, 1, 1), g2 = KernelRadialMoment(kernel, 2, 1);
  const std::vector<uint32_t> near = EdgesWithin(x, h);
  if (near.empty()) return {1.0, {0, 0}, {kTwoPi / 2 * g2, 0, kTwoPi / 2 * g2}};
  const auto direction = [&](Point2 p) { return std::atan2(Offset(p.v, x.v), Offset(p.u, x.u)); };
  KernelMomentsAt inside{0, {0, 0}, {0, 0, 0}};  // the near edges' parts within the support, beyond G_n(1)
  double through[5] = {0, 0, 0, 0, 0};           // the telescoped shares of edges through x: u, then sin 2t, cos 2t
  double nearTurn = 0, nearAngle = 0;
  for (uint32_t i : near) {
    const Edge& e = edges_[i];
    const double ta = direction(e.a), tb = direction(e.b);
    nearTurn += tb - ta;
    const double angle = EdgeMass(e.a, e.b, x, Kernel::kUniform, 0) * kTwoPi;  // its signed angle; 0 through x
    nearAngle += angle;
    if (angle == 0) {
      through[0] += std::sin(tb) - std::sin(ta);
      through[1] += std::cos(ta) - std::cos(tb);
      through[2] += std::sin(2 * tb) - std::sin(2 * ta);
      through[3] += std::cos(2 * tb) - std::cos(2 * ta);
    }
    const KernelMomentsAt m = EdgeMomentsInside(e.a, e.b, x, kernel, h);
    inside.mass += m.mass;
    for (int k = 0; k < 2; ++k) inside.first[k] += m.first[k];
    for (int k = 0; k < 3; ++k) inside.second[k] += m.second[k];
  }
  const double angle = nearAngle - nearTurn + kTwoPi * CutCrossingsBeyond(x, near);
  return {g0 * angle + inside.mass,
          {inside.first[0] - g1 * through[0], inside.first[1] - g1 * through[1]},
          {g2 * (angle / 2 - through[2] / 4) + inside.second[0], g2 * through[3] / 4 + inside.second[1],
           g2 * (angle / 2 + through[2] / 4) + inside.second[2]}};
}

namespace {

// The least and greatest u of triangle t within the strip v0 <= v <= v1: of its corners inside the strip and
// its edges' crossings of the strip's sides. The triangle's own u extent `box` when the strip misses it (the
// cells then test as outside, as before).
std::pair<float, float> ExtentInStrip(const Triangle2& t, float v0, float v1, const Bounds2& box) {
  double u0 = INFINITY, u1 = -INFINITY;
  const auto extend = [&](double u) { u0 = std::min(u0, u), u1 = std::max(u1, u); };
  for (int e = 0; e < 3; ++e) {
    const Point2 a = t[e], b = t[(e + 1) % 3];
    for (const Point2& p : {a, b})
      if (p.v >= v0 && p.v <= v1) extend(p.u);
    if (a.v == b.v) continue;
    for (const float side : {v0, v1}) {
      const double f = (double(side) - a.v) / (double(b.v) - a.v);
      if (f > 0 && f < 1) extend(a.u + f * (double(b.u) - a.u));
    }
  }
  if (!(u0 <= u1)) return {box.lo.u, box.hi.u};
  return {float(u0), float(u1)};
}

}  // namespace

std::vector<double> SurfaceRegion::GridOverlapAreas(Point2 lo, float side, int nu, int nv) const {
  std::vector<double> area(size_t(nu) * nv, 0.0);
  const auto cell = [&](float c, float origin, int n) { return std::clamp(int(std::floor((c - origin) / side)), 0, n - 1); };
  // Only cells that a triangle's edge crosses are clipped: one wholly inside it adds its own area, one wholly
  // outside an edge nothing (the triangles are counter-clockwise). A fine grid under large triangles (the binned
  // kernel's coverage mask) is mostly the first kind.
  // Row by row, only the cells within the triangle's extent in that row, and one either side for rounding: a
  // sliver of a 20,000-corner disc's fan spans its whole box in rows of one or two cells.
  const auto add = [&](const Triangle2& t, double sign) {
    Bounds2 tb;
    for (const Point2& p : t) tb.Extend(p);
    for (int iv = cell(tb.lo.v, lo.v, nv); iv <= cell(tb.hi.v, lo.v, nv); ++iv) {
      const auto [u0, u1] = ExtentInStrip(t, lo.v + iv * side, lo.v + (iv + 1) * side, tb);
      for (int iu = std::max(cell(u0, lo.u, nu) - 1, 0); iu <= std::min(cell(u1, lo.u, nu) + 1, nu - 1); ++iu) {
        const Bounds2 box{{lo.u + iu * side, lo.v + iv * side}, {lo.u + (iu + 1) * side, lo.v + (iv + 1) * side}};
        const std::array<Point2, 4> corners = {box.lo, Point2{box.hi.u, box.lo.v}, box.hi, Point2{box.lo.u, box.hi.v}};
        bool inside = true, outside = false;
        for (int e = 0; e < 3 && !outside; ++e) {
          int in = 0;
          for (const Point2& q : corners) in += SignedArea(t[e], t[(e + 1) % 3], q) >= 0;
          inside &= in == 4, outside |= in == 0;
        }
        if (outside) continue;
        const double overlap = inside ? (double(box.hi.u) - box.lo.u) * (double(box.hi.v) - box.lo.v)
                                      : TriangleBoxOverlapArea(t, box);
        area[size_t(iv) * nu + iu] += sign * overlap;
      }
    }
  };
  for (const Triangle2& t : triangles_) add(t, 1);
  for (const Triangle2& t : holes_) add(t, -1);
  if (!holes_.empty())
    for (double& a : area) a = std::max(a, 0.0);  // a hole's clipped area can exceed its cell's by rounding
  return area;
}

double SurfaceRegion::OverlapArea(const Bounds2& box) const {
  double area = 0;
  for (const Triangle2& t : triangles_) area += TriangleBoxOverlapArea(t, box);
  for (const Triangle2& t : holes_) area -= TriangleBoxOverlapArea(t, box);
  return area;
}

}  // namespace pb
