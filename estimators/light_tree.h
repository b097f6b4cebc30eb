// A bounding tree over area lights that chooses, at a receiving point, one light in proportion to a conservative
// guess of its contribution there, in O(log lights) per choice instead of O(lights) (Conty Estevez and Kulla 2018,
// "Importance sampling of many lights with adaptive tree splitting", Proc. ACM Comput. Graph. Interact. Tech. 1(2);
// the orientation bounds and the importance are theirs, the adaptive splitting is not used).
//
// Each node bounds its lights by an axis-aligned box, their total power (a relative weight: the luminance of Ke
// times the area [W/sr]) and a cone holding their front normals (unit axis, half-angle theta_o [rad]); area lights
// emit over their front hemisphere (theta_e = pi/2). At a point p with unit normal n, a node's importance is
//   I = power cos(theta') cos(theta_i') / max(d^2, r^2),
// with c and r the centre and half-diagonal of the box, d = |p - c|, theta_u = asin(r / d) the angle that the
// box's bounding sphere subtends from p (pi when p is inside it), theta' = max(0, angle(axis, p - c) - theta_o -
// theta_u), theta_i' = max(0, angle(n, c - p) - theta_u), and I = 0 when either angle reaches pi/2. The bounds are
// conservative: a light with a point in front of p that p is in front of has I > 0 at its leaf and every node above
// it, so every light that can contribute can be chosen and the choice is unbiased.
//
// A choice descends from the root, taking each child with probability I_child / (I_left + I_right) and rescaling
// the one number u into that child's share, so that stratified u's stay stratified over the lights. Its pmf is the
// product of the probabilities taken; Pmf(light) gives the same for any light.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "mesh/geometry.h"

namespace pb {

// What the tree knows of one light, or of a node's lights together.
struct LightBounds {
  Point3 lo{0, 0, 0}, hi{0, 0, 0};  // axis-aligned box [m]
  Vector3 axis{0, 0, 1};            // unit axis of the cone of front normals
  float spread = 0;                 // theta_o [rad], in [0, pi]; pi: any direction
  double power = 0;                 // relative weight, > 0
  // The box of `points` (at least one); axis, spread and power are left as they are.
  void Enclose(const std::vector<Point3>& points);
};

// The smallest cone (of the two candidates the union rule gives) holding both cones of directions.
struct NormalCone {
  Vector3 axis;
  float spread;
};
NormalCone UnionOfCones(NormalCone a, NormalCone b);

class LightTree {
 public:
  // lights[i] is light i; at least one, each of positive power.
  explicit LightTree(const std::vector<LightBounds>& lights);

  struct Choice {
    uint32_t light;
    double pmf;  // > 0
  };
  // The light that u in [0, 1) picks at (p, n); none when no light can reach p.
  std::optional<Choice> Choose(Point3 p, Normal3 n, float u) const;
  // The probability that Choose picks `light` at (p, n), for u uniform on [0, 1).
  double Pmf(Point3 p, Normal3 n, uint32_t light) const;
  // Whether any light can reach (p, n): the root's importance is positive.
  bool AnyCanReach(Point3 p, Normal3 n) const;

 private:
 public:
  // A node's bounds as the importance reads them: centre and radius of the box's bounding sphere, the box's
  // half extents, the cone's cosine and sine. Importance(p, n) is I above; 0 when no light inside can reach p,
  // and 0 when the whole box lies on or behind p's tangent plane (which the sphere alone cannot tell: lamps in
  // the plane of a point among them, an LED ceiling's own vertices, would each be visited to find nothing).
  struct Compact {
    Point3 centre;
    float radius;
    Vector3 half;
    Vector3 axis;
    float cosSpread, sinSpread;
    double power;
    static Compact Of(const LightBounds& b);
    double Importance(Point3 p, Normal3 n) const;
  };

 private:
  static constexpr uint32_t kInner = UINT32_MAX;
  struct Node {
    Compact bounds;
    uint32_t left = 0, right = 0;  // children (inner nodes)
    uint32_t light = kInner;       // the light (leaves)
    uint32_t parent = kInner;      // kInner at the root
  };
  // Builds the node over lights order[begin, end); returns it, and its bounds in `bounds`.
  // `centres` are the lights' box centres, along which the nodes split.
  uint32_t Build(const std::vector<LightBounds>& lights, const std::vector<Point3>& centres,
                 std::vector<uint32_t>& order, size_t begin, size_t end, uint32_t parent, LightBounds& bounds);
  // The probability of taking an inner node's left child at (p, n); -1 when neither child can reach p.
  double LeftShare(const Node& node, Point3 p, Normal3 n) const;

  std::vector<Node> nodes_;       // root first
  std::vector<uint32_t> leafOf_;  // node of each light
};

}  // namespace pb
