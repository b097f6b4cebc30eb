#include "estimators/light_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "mesh/errors.h"

namespace pb {
namespace {

float AngleBetween(Vector3 a, Vector3 b) { return std::acos(std::clamp(Dot(a, b), -1.0f, 1.0f)); }

// cos(max(0, a - b)) for angles a, b in [0, pi] given by their cosines and sines, without trigonometry.
float CosOfExcess(float cosA, float sinA, float cosB, float sinB) {
  if (cosA >= cosB) return 1.0f;  // a <= b
  return cosA * cosB + sinA * sinB;
}

Point3 Min(Point3 a, Point3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
Point3 Max(Point3 a, Point3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
Point3 Centre(const LightBounds& b) { return {0.5f * (b.lo.x + b.hi.x), 0.5f * (b.lo.y + b.hi.y), 0.5f * (b.lo.z + b.hi.z)}; }
float Coordinate(Point3 p, int axis) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; }

LightBounds Union(const LightBounds& a, const LightBounds& b) {
  const NormalCone cone = UnionOfCones({a.axis, a.spread}, {b.axis, b.spread});
  return {Min(a.lo, b.lo), Max(a.hi, b.hi), cone.axis, cone.spread, a.power + b.power};
}

}  // namespace

NormalCone UnionOfCones(NormalCone a, NormalCone b) {
  if (a.spread >= kPi || b.spread >= kPi) return {a.axis, kPi};
  const float between = AngleBetween(a.axis, b.axis);
  if (std::min(between + b.spread, kPi) <= a.spread) return a;
  if (std::min(between + a.spread, kPi) <= b.spread) return b;
  const float spread = 0.5f * (a.spread + between + b.spread);
  if (spread >= kPi) return {a.axis, kPi};
  // Turn a's axis toward b's by the angle that centres the new cone.
  const float turn = spread - a.spread;
  const Vector3 across = b.axis - a.axis * Dot(a.axis, b.axis);
  const float length = Length(across);
  if (!(length > 1e-7f)) return {a.axis, spread};
  return {Normalize(a.axis * std::cos(turn) + across * (std::sin(turn) / length)), spread};
}

void LightBounds::Enclose(const std::vector<Point3>& points) {
  lo = hi = points.front();
  for (Point3 p : points) lo = Min(lo, p), hi = Max(hi, p);
}

LightTree::Compact LightTree::Compact::Of(const LightBounds& b) {
  return {Centre(b), 0.5f * Length(b.hi - b.lo), (b.hi - b.lo) * 0.5f, b.axis, std::cos(b.spread), std::sin(b.spread),
          b.power};
}

double LightTree::Compact::Importance(Point3 p, Normal3 n) const {
  const Vector3 v = p - centre;
  // How far the box reaches in front of p's plane: its support along n.
  const float inFront = -Dot(v, n) + std::fabs(half.x * n.x) + std::fabs(half.y * n.y) + std::fabs(half.z * n.z);
  if (!(inFront > 0)) return 0.0;
  const float d2 = LengthSquared(v);
  const double falloff = power / std::max(double(d2), double(radius) * radius);
  if (!(d2 > radius * radius)) return falloff;  // p inside the bounding sphere: every direction is possible
  const float d = std::sqrt(d2);
  const float sinU = radius / d, cosU = std::sqrt(std::max(0.0f, 1 - sinU * sinU));
  const Vector3 w = v * (1.0f / d);  // from the lights toward p
  // The emission angle less theta_o, then less theta_u.
  const float cosTheta = std::clamp(Dot(axis, w), -1.0f, 1.0f), sinTheta = std::sqrt(1 - cosTheta * cosTheta);
  float cosEmitted = 1, sinEmitted = 0;
  if (cosTheta < cosSpread) {
    cosEmitted = cosTheta * cosSpread + sinTheta * sinSpread;
    sinEmitted = std::max(0.0f, sinTheta * cosSpread - cosTheta * sinSpread);
  }
  const float emitted = CosOfExcess(cosEmitted, sinEmitted, cosU, sinU);
  if (emitted <= 0) return 0.0;
  const float cosI = std::clamp(-Dot(w, n), -1.0f, 1.0f), sinI = std::sqrt(1 - cosI * cosI);
  const float received = CosOfExcess(cosI, sinI, cosU, sinU);
  if (received <= 0) return 0.0;
  return falloff * emitted * received;
}

LightTree::LightTree(const std::vector<LightBounds>& lights) {
  PB_CHECK(!lights.empty(), "a light tree holds at least one light");
  std::vector<uint32_t> order(lights.size());
  std::iota(order.begin(), order.end(), 0u);
  leafOf_.assign(lights.size(), 0);
  nodes_.reserve(2 * lights.size() - 1);
  std::vector<Point3> centres;
  for (const LightBounds& b : lights) centres.push_back(Centre(b));
  LightBounds all;
  Build(lights, centres, order, 0, lights.size(), kInner, all);
}

// Splits at the median centre along the axis where the centres spread most (ties by light index, so that the
// tree is the same on every run).
uint32_t LightTree::Build(const std::vector<LightBounds>& lights, const std::vector<Point3>& centres,
                          std::vector<uint32_t>& order, size_t begin, size_t end, uint32_t parent,
                          LightBounds& bounds) {
  const auto self = uint32_t(nodes_.size());
  nodes_.push_back({});
  nodes_[self].parent = parent;
  if (end - begin == 1) {
    nodes_[self].bounds = Compact::Of(lights[order[begin]]);
    nodes_[self].light = order[begin];
    leafOf_[order[begin]] = self;
    bounds = lights[order[begin]];
    return self;
  }
  Point3 lo = centres[order[begin]], hi = lo;
  for (size_t i = begin; i < end; ++i) lo = Min(lo, centres[order[i]]), hi = Max(hi, centres[order[i]]);
  const Vector3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const size_t middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + long(begin), order.begin() + long(middle), order.begin() + long(end),
                   [&](uint32_t a, uint32_t b) {
                     const float ca = Coordinate(centres[a], axis), cb = Coordinate(centres[b], axis);
                     return ca < cb || (ca == cb && a < b);
                   });
  LightBounds merged;
  const uint32_t left = Build(lights, centres, order, begin, middle, self, merged);
  LightBounds rightBounds;
  const uint32_t right = Build(lights, centres, order, middle, end, self, rightBounds);
  merged = Union(merged, rightBounds);
  nodes_[self].left = left, nodes_[self].right = right;
  nodes_[self].bounds = Compact::Of(merged);
  bounds = merged;
  return self;
}

double LightTree::LeftShare(const Node& node, Point3 p, Normal3 n) const {
  const double left = nodes_[node.left].bounds.Importance(p, n);
  const double right = nodes_[node.right].bounds.Importance(p, n);
  return left + right > 0 ? left / (left + right) : -1.0;  // -1: neither child can reach p
}

bool LightTree::AnyCanReach(Point3 p, Normal3 n) const { return nodes_[0].bounds.Importance(p, n) > 0; }

std::optional<LightTree::Choice> LightTree::Choose(Point3 p, Normal3 n, float u) const {
  if (!AnyCanReach(p, n)) return std::nullopt;
  double pmf = 1, x = u;
  uint32_t at = 0;
  while (nodes_[at].light == kInner) {
    const Node& node = nodes_[at];
    const double share = LeftShare(node, p, n);
    if (share < 0) return std::nullopt;
    if (x < share) {
      x /= share, pmf *= share, at = node.left;
    } else {
      x = (x - share) / (1 - share), pmf *= 1 - share, at = node.right;
    }
    x = std::min(x, 0x1.fffffffffffffp-1);
  }
  if (!(pmf > 0)) return std::nullopt;
  return Choice{nodes_[at].light, pmf};
}

double LightTree::Pmf(Point3 p, Normal3 n, uint32_t light) const {
  if (!AnyCanReach(p, n)) return 0.0;
  double pmf = 1;
  for (uint32_t at = leafOf_[light]; nodes_[at].parent != kInner; at = nodes_[at].parent) {
    const Node& parent = nodes_[nodes_[at].parent];
    const double share = LeftShare(parent, p, n);
    if (share < 0) return 0.0;
    pmf *= parent.left == at ? share : 1 - share;
  }
  return pmf;
}

}  // namespace pb
