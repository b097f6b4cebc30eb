#include "estimators/chart_clip.h"

#include <algorithm>

namespace pb {

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

std::vector<Point2> ClipToWindow(std::vector<Point2> polygon, const Bounds2& box) {
  const Point2 c[4] = {box.lo, {box.hi.u, box.lo.v}, box.hi, {box.lo.u, box.hi.v}};  // counter-clockwise
  if (SignedArea(polygon[0], polygon[1], polygon[2]) < 0) std::reverse(polygon.begin(), polygon.end());
  for (int k = 0; k < 4 && polygon.size() >= 2; ++k) polygon = ClipLeftOf(polygon, c[k], c[(k + 1) % 4]);
  return polygon;
}

bool ClipToBox(Point2& a, Point2& b, const Bounds2& box) {
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


}  // namespace pb
