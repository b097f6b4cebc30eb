// The importance map of Jensen 1995, "Importance Driven Path Tracing using the Photon Map" (Rendering
// Techniques '95), as described in the particle-tracing paper: a (hemi)sphere of directions cut into regions,
// each holding the importance that photons arriving from its directions carry (power x BRDF), plus a uniform
// floor so that every direction stays possible. A direction is drawn with probability proportional to the
// region's importance, uniformly within the region.
//
// Directions are in a local frame whose z axis is the surface normal. The map is a rows x cols grid over the
// unit square (s, t) (Point2 u = s, v = t), phi = 2 pi t, and one of three domains (MapDomain):
//   kHemisphere:        cos(theta) = 1 - s; every region spans the same solid angle, 2 pi / n [sr];
//   kCosineHemisphere:  cos(theta)^2 = 1 - s; every region spans the same projected solid angle, pi / n [sr]
//                       (the measure cos(theta) d omega), and a point uniform in (s, t) is a direction drawn
//                       from the cosine lobe (Malley's method in polar form);
//   kSphere:            cos(theta) = 1 - 2 s; every region spans 4 pi / n [sr];
// with n = rows cols.
//
// The pdf of a direction in region k is P_k / M_r times cos(theta) in the cosine domain (else times 1) [1/sr],
// with P_k = I_k / I its share of the importance and M_r the region's measure. The weight of a sample, f cos /
// pdf, therefore carries the factor 1 / (P_k n): the paper's scale factor s = I / (I_k n), with n the number of
// regions. In the cosine domain the weight of a Lambertian BRDF is Kd / (P_k n) whatever the direction in the
// region, and a uniform map (or the floor) is exactly the BRDF's own sampling; the paper's equal-solid-angle
// regions leave a factor cos(theta) that varies within each region (4/3 across the first of four bands, without
// bound across the last), noise that cosine sampling does not have.
//
// Two warps pick the region and the point in it:
//   kInversion: the regions in row order as one array; a binary search of its CDF (the paper's linear scan picks
//               the same region for the same number).
//   kMipmap:    hierarchical warping (the paper's mip-map method; McCool and Harwood 1997): the grid is halved
//               along its longer side, level by level, and each coordinate is rescaled into the chosen half
//               in proportion to the halves' importance. Finish tabulates every node's split, as a complete
//               binary tree in one array (the children of node i are 2i + 1 and 2i + 2), so a draw reads one
//               number per level.
// Both warps have the same pdf; each has an exact Invert where the pdf is positive.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "mesh/geometry.h"

namespace pb {

enum class ImportanceWarp : uint8_t { kMipmap, kInversion };
enum class MapDomain : uint8_t { kHemisphere, kCosineHemisphere, kSphere };

struct ImportanceSample {
  Vector3 direction;  // unit, local frame
  float pdf = 0;      // [1/sr]
  uint32_t region = 0;
};

class ImportanceMap {
 public:
  // rows, cols >= 1; for kMipmap both must be powers of two.
  ImportanceMap(int rows, int cols, MapDomain domain = MapDomain::kHemisphere);

  int Rows() const { return rows_; }
  int Cols() const { return cols_; }
  int Regions() const { return rows_ * cols_; }
  MapDomain Domain() const { return domain_; }
  float RegionMeasure() const;  // solid angle [sr], or projected solid angle in the cosine domain

  // Accumulation. `importance` >= 0 [any consistent unit, e.g. W/sr]; directions below the domain are ignored.
  void Clear();
  void Add(Vector3 localDirection, float importance);
  // Mixes in the floor: I'_k = (1 - floor) I_k / I + floor / n, with floor in [0, 1]. With no importance at all
  // the map becomes uniform. Builds the tables that Sample and Pdf use; call once after the last Add.
  void Finish(float floorFraction);

  ImportanceSample Sample(Point2 u, ImportanceWarp warp) const;
  float Pdf(Vector3 localDirection) const;                   // [1/sr] (solid angle); 0 outside the domain
  std::optional<Point2> Invert(Vector3 localDirection, ImportanceWarp warp) const;  // none where pdf is 0
  float RegionProbability(uint32_t region) const { return probability_[region]; }
  std::optional<uint32_t> RegionOf(Vector3 localDirection) const;

 private:
  Point2 ToSquare(Vector3 localDirection) const;  // (s, t)
  Vector3 FromSquare(Point2 st) const;
  float PdfIn(uint32_t region, float cosTheta) const;  // [1/sr]
  // Hierarchical warping: a node of the grid, halved along its longer side into two children.
  struct Split {
    bool rows;     // the rows are halved (else the columns)
    int mid;       // first row (or column) of the second half
    double first;  // the first half's share of the node's probability
  };
  struct Node {
    int r0, r1, c0, c1;  // rows [r0, r1), cols [c0, c1)
    bool IsCell() const { return r1 - r0 == 1 && c1 - c0 == 1; }
    void Keep(const Split& s, bool second);  // narrows to one half
  };
  static Split Halving(const Node& n);                       // which side, and where; `first` unset
  Split TabulatedSplit(const Node& n, size_t index) const;  // from splits_
  struct SummedArea;
  void TabulateSplits(const Node& n, size_t index, const SummedArea& sums);
  Point2 SampleInversionSquare(Point2 u, uint32_t& region) const;
  Point2 SampleMipmapSquare(Point2 u, uint32_t& region) const;
  Point2 InvertInversionSquare(uint32_t region, Point2 local) const;
  Point2 InvertMipmapSquare(int row, int col, Point2 local) const;

  int rows_, cols_;
  MapDomain domain_;
  std::vector<double> importance_;   // accumulated, row-major
  std::vector<float> probability_;   // P_k after the floor
  std::vector<double> cdf_;          // inclusive prefix sums of probability_, back() == 1
  std::vector<double> splits_;       // mip-map nodes' first-half shares, heap order; empty unless powers of two
};

}  // namespace pb
