// Ear clipping after Eberly, "Triangulation by Ear Clipping" (Geometric Tools, 2002).
#include "mesh/polygon.h"

#include <cmath>

#include "mesh/errors.h"
#include "mesh/polygon_cdt.h"

namespace pb {
namespace {

// Ear clipping tests every remaining reflex corner for every ear: O(n^2), and O(n^3) when edges cross. Above this
// many corners a simple polygon is cut by constrained Delaunay triangulation in O(n log n) instead; one that is not
// simple (it touches or crosses itself) is ear-clipped up to kMostCornersToClip corners, and cut as a fan beyond: a
// random self-crossing polygon of 256 corners is clipped in a few milliseconds, one of 2,048 took 1.8 s.
constexpr uint32_t kMostCornersToClipFirst = 64;
constexpr uint32_t kMostCornersToClip = 256;

struct Point2d {
  double x, y;
};

double Cross(Point2d o, Point2d a, Point2d b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// The corners in an orthonormal frame of the plane whose normal is `n`, so that a polygon counter-clockwise about
// n is counter-clockwise in the frame.
std::vector<Point2d> InPlane(const std::vector<PolygonCorner>& corners, const PolygonCorner& n) {
  // The axis of n's smallest component gives a well-conditioned first tangent.
  const int k = std::abs(n[0]) <= std::abs(n[1]) && std::abs(n[0]) <= std::abs(n[2]) ? 0
                : std::abs(n[1]) <= std::abs(n[2])                                  ? 1
                                                                                    : 2;
  PolygonCorner axis{0, 0, 0};
  axis[size_t(k)] = 1;
  // t = axis x n, b = n x t (both scaled by |n|, which does not change signs).
  const PolygonCorner t{axis[1] * n[2] - axis[2] * n[1], axis[2] * n[0] - axis[0] * n[2],
                        axis[0] * n[1] - axis[1] * n[0]};
  const PolygonCorner b{n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
  std::vector<Point2d> out;
  out.reserve(corners.size());
  for (const PolygonCorner& p : corners)
    out.push_back({p[0] * t[0] + p[1] * t[1] + p[2] * t[2], p[0] * b[0] + p[1] * b[1] + p[2] * b[2]});
  return out;
}

// How far a turn must bend to count as reflex: corners on a line (up to rounding) are not reflex.
double TurnTolerance(Point2d a, Point2d o, Point2d b) {
  const double ea = std::hypot(a.x - o.x, a.y - o.y), eb = std::hypot(b.x - o.x, b.y - o.y);
  return 1e-12 * ea * eb;
}

bool IsReflex(const std::vector<Point2d>& p, uint32_t prev, uint32_t i, uint32_t next) {
  return Cross(p[prev], p[i], p[next]) < -TurnTolerance(p[prev], p[i], p[next]);
}

// Whether q lies in the closed triangle (a, b, c), counter-clockwise.
bool InTriangle(Point2d q, Point2d a, Point2d b, Point2d c) {
  return Cross(a, b, q) >= 0 && Cross(b, c, q) >= 0 && Cross(c, a, q) >= 0;
}

class EarClipper {
 public:
  explicit EarClipper(std::vector<Point2d> points) : p_(std::move(points)), prev_(p_.size()), next_(p_.size()) {
    const uint32_t n = uint32_t(p_.size());
    for (uint32_t i = 0; i < n; ++i) prev_[i] = (i + n - 1) % n, next_[i] = (i + 1) % n;
  }

  PolygonTriangulation Run() {
    PolygonTriangulation out{{}, true, false};
    uint32_t remaining = uint32_t(p_.size()), i = 0, tried = 0;
    while (remaining > 3) {
      if (IsEar(i)) {
        Clip(i, out);
        --remaining;
        i = next_[i];
        tried = 0;
      } else if (++tried > remaining) {  // a full turn without an ear: the polygon crosses itself
        out.irregular = true;
        Clip(i, out);
        --remaining;
        i = next_[i];
        tried = 0;
      } else {
        i = next_[i];
      }
    }
    out.triangles.push_back({prev_[i], i, next_[i]});
    return out;
  }

 private:
  bool IsEar(uint32_t i) const {
    const uint32_t a = prev_[i], c = next_[i];
    if (IsReflex(p_, a, i, c)) return false;
    // No other remaining corner may lie in the ear (only reflex corners can, but testing all is as simple and
    // keeps polygons that touch themselves correct).
    for (uint32_t j = next_[c]; j != a; j = next_[j]) {
      const Point2d q = p_[j];
      const bool atCorner = (q.x == p_[a].x && q.y == p_[a].y) || (q.x == p_[i].x && q.y == p_[i].y) ||
                            (q.x == p_[c].x && q.y == p_[c].y);
      if (!atCorner && IsReflex(p_, prev_[j], j, next_[j]) && InTriangle(q, p_[a], p_[i], p_[c])) return false;
    }
    return true;
  }

  void Clip(uint32_t i, PolygonTriangulation& out) {
    out.triangles.push_back({prev_[i], i, next_[i]});
    next_[prev_[i]] = next_[i];
    prev_[next_[i]] = prev_[i];
  }

  std::vector<Point2d> p_;
  std::vector<uint32_t> prev_, next_;
};

PolygonTriangulation CutConcave(const std::vector<Point2d>& points, PolygonTriangulation fan) {
  const size_t n = points.size();
  if (n <= kMostCornersToClipFirst) return EarClipper(points).Run();
  std::vector<std::array<double, 2>> plane(n);
  for (size_t i = 0; i < n; ++i) plane[i] = {points[i].x, points[i].y};
  if (auto triangles = TriangulateSimplePolygon(plane)) return {std::move(*triangles), true, false};
  if (n <= kMostCornersToClip) return EarClipper(points).Run();
  fan.concave = fan.irregular = true;
  return fan;
}

}  // namespace

PolygonCorner PolygonAreaVector(const std::vector<PolygonCorner>& c) {
  PolygonCorner n{0, 0, 0};
  // About the first corner, so that far-off polygons keep their precision.
  for (size_t i = 1; i + 1 < c.size(); ++i) {
    const double ax = c[i][0] - c[0][0], ay = c[i][1] - c[0][1], az = c[i][2] - c[0][2];
    const double bx = c[i + 1][0] - c[0][0], by = c[i + 1][1] - c[0][1], bz = c[i + 1][2] - c[0][2];
    n[0] += 0.5 * (ay * bz - az * by);
    n[1] += 0.5 * (az * bx - ax * bz);
    n[2] += 0.5 * (ax * by - ay * bx);
  }
  return n;
}

PolygonTriangulation TriangulatePolygon(const std::vector<PolygonCorner>& corners) {
  PB_CHECK(corners.size() >= 3, "a polygon has at least three corners");
  const uint32_t n = uint32_t(corners.size());
  PolygonTriangulation fan;
  for (uint32_t i = 1; i + 1 < n; ++i) fan.triangles.push_back({0, i, i + 1});
  const PolygonCorner normal = PolygonAreaVector(corners);
  if (n == 3 || (normal[0] == 0 && normal[1] == 0 && normal[2] == 0)) return fan;  // no plane: nothing to keep
  std::vector<PolygonCorner> local(corners);
  for (PolygonCorner& p : local)
    for (int k = 0; k < 3; ++k) p[size_t(k)] -= corners[0][size_t(k)];
  const std::vector<Point2d> points = InPlane(local, normal);
  for (uint32_t i = 0; i < n; ++i)
    if (IsReflex(points, (i + n - 1) % n, i, (i + 1) % n)) return CutConcave(points, std::move(fan));
  return fan;
}

}  // namespace pb
