// Direct irradiance at a surface point [W/m^2], by sampling the lights with shadow rays: the light that reaches
// the point straight from an emitter, with no scattering between (Shirley, Wang and Zimmerman 1996, "Monte Carlo
// techniques for direct lighting calculations", ACM TOG 15(1)). For area lights of radiance Ke leaving their
// front sides with a cosine distribution (mesh/lights.h),
//   E_d(x) = sum_i integral_{A_i} Ke_i V(x, y) cos(theta_x) cos(theta_y) / |x - y|^2 dA(y),
// with theta_x from x's normal and theta_y from the light's front normal; V is 1 when nothing blocks the segment.
// Glass and mirrors block it too: light that reaches x through them is scattered light, which the photons carry.
//
// Each of S samples picks light i with probability p_i, a point y uniform over its area (pdf 1 / A_i), and weighs
// Ke V cos cos / d^2 by A_i / p_i. Where the light is large and near (it subtends kSolidAngleFrom or more at x
// and has at most kSolidAngleTriangles triangles), the sample is a direction w uniform over the solid angle
// Omega_i that it subtends instead (estimators/warps.h, Arvo 1995: a triangle in proportion to its solid angle,
// then a direction in it), weighed Ke V cos(theta_x) Omega_i / p_i: the 1 / d^2 and cos(theta_y) factors, which
// vary most over a near light, leave the estimate. A point computes a light's spherical triangles once, the first
// time a sample picks it, and only for a light of at most
// S / 4 triangles (S samples; at least 4), so that this stays a small part of the point's cost: a path tracer's
// one sample per vertex would otherwise pay for every triangle of a gridded light (7x its time on the 25 mm box).
// A curved light sampled by area (a small sphere, far off) picks its triangle in proportion to the solid angle it
// projects to at x, w_t = A_t cos(theta_y) / d^2 at the triangle's centroid, then a point uniform over it (pdf
// w_t / (A_t sum w)), where it has at most max(kFacingTriangles, S / 4) triangles: the far half of a sphere faces
// away (w_t = 0; a triangle is flat, so cos(theta_y) has one sign over it) and took half the samples by area, each 0,
// and the rest weigh about alike (the atrium's sphere light needed 18,000 shadow rays a point for 0.8% by area). p_i is 90% in proportion to an unoccluded guess of the light's share at x
// (its power over the squared distance to its centroid, floored at its area), 10% uniform over the lights that
// can reach x, so that no light is starved by a poor guess. With kTreeLights area lights or more, p_i comes from a
// light tree instead (estimators/light_tree.h: power, distance and orientation bounds, O(log lights) per sample),
// so that thousands of lights stay cheap; every light that can reach x keeps p_i > 0. The S samples are stratified over the light choice
// (sample j's first number is (j + u) / S) and over the point on the light (a jittered grid on the unit square).
// Lights wholly behind x's plane, or with x wholly behind theirs, get no samples. The result is unbiased; its
// relative noise is the standard error that pairs of neighbouring strata predict (StratifiedMean), over the mean.
//
// Lights that are not surfaces (mesh/scene.h) add their part on top:
//   point, spot: I f cos(theta_x) / d^2 V, and sun: E cos(theta_x) V (V by one shadow ray toward the sun, which
//                must leave the scene), each computed exactly, with no noise;
//   sky:         pi L times the fraction of S cosine-distributed rays, stratified, that leave the scene toward the
//                sky, with its own stratified standard error; with an image or portals, per stratum one
//                cosine-distributed direction, one drawn by the image's luminance (with an image) and one toward a
//                point on a portal (with portals) (estimators/sky_sampling.h), each weighted by the balance
//                heuristic of multiple importance sampling (Veach and Guibas 1995): 2 or 3 S rays.
// Their noise adds to the area lights' in variance.
//
// Determinism: the point's random numbers come from a stream keyed by the caller (the surface point), so the same
// point reads the same value on any thread.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "estimators/incident_moments.h"
#include "estimators/light_tree.h"
#include "estimators/rng.h"
#include "estimators/warps.h"
#include "mesh/color.h"
#include "mesh/geometry.h"
#include "mesh/lights.h"
#include "mesh/ray_scene.h"
#include "estimators/noisy_irradiance.h"
#include "mesh/scene.h"

namespace pb {

// An irradiance sampled at a point, its noise, and the rays it took.
struct DirectSample : NoisyIrradiance {
  uint32_t samples = 0;  // shadow rays (or gathered paths) cast for it (the adaptive ones: the pilot's included)
};

// The mean of independent samples of an irradiance, and the standard error of its luminance; with each sample's
// moment vector (estimators/incident_moments.h, MomentVector), also the covariance of their mean.
class SampleMean {
 public:
  void Add(Rgb e) {
    sum_.Add(e);
    const double y = Luminance(e);
    luminance_ += y, squares_ += y * y, ++n_;
  }
  void Add(Rgb e, Vector3 v) {
    Add(e);
    vectorSum_[0] += v.x, vectorSum_[1] += v.y, vectorSum_[2] += v.z;
    outer_.AddOuter(v, 1);
  }
  DirectSample Result() const;
  Symmetric3 VectorCovariance() const;  // of the mean of the vectors; 0 below two samples

 private:
  RgbSum sum_;
  double luminance_ = 0, squares_ = 0;
  uint32_t n_ = 0;
  std::array<double, 3> vectorSum_{};
  Symmetric3 outer_;
};

// The mean of samples stratified on a side x side grid of cells (one sample per cell), and a standard error that
// the stratification earns: each three cells (a, b), (a + 1, b) and (a + 2, b) in a row are collapsed into a stratum
// of three samples, whose within-cell variance sigma^2 is estimated from the second difference d = f_1 - 2 f_2 + f_3, with
// E[d^2] = 6 sigma^2 where the cells' means change linearly along the row (Cochran, "Sampling Techniques", 5A.12,
// collapsed strata, with the trend taken out); the mean's variance is then the triples' mean d^2 / 6 over S. The
// triples overlap (side - 2 to a row), which steadies the estimate without biasing it. Pairs
// (f_1 - f_2)^2 / 2, as before 2026-12-05, also counted the light's gradient across two cells: 2.3 to 2.8 times the
// true error on a smooth light. Still conservative where the cells' means curve or a shadow's edge crosses a cell.
// Samples outside a triple count at the triples' rate; fewer than two triples (side under 3): the independent-
// sample error. The samples may be stratified along a second axis too, in the order they are added (the area
// lights': sample j picks its light and triangle from the j-th of S strata, and its point from a cell in random
// order), where neighbouring cells hold samples of unrelated triangles and their differences see the light's
// variation over its triangles, which the picks' own stratification removes: the same estimate from triples of
// samples consecutive in that order is taken where it is the smaller (each is an overestimate of the variance the
// other axis's trend leaves; on the box's light of many triangles the cells' alone predicted 7x the true error).
// With each sample's moment vector, the covariance of the vectors' mean alike, from the same triples.
class StratifiedMean {
 public:
  explicit StratifiedMean(uint32_t side) : side_(side), byCell_(size_t(side) * side, -1.0) {}
  void Add(uint32_t cell, Rgb e);
  void Add(uint32_t cell, Rgb e, Vector3 v);
  DirectSample Result() const;
  Symmetric3 VectorCovariance() const;

 private:
  // Calls triple(a, b, c) for every three neighbouring cells of a row that all hold a sample, or byOrder for every
  // three samples added one after another; returns the samples.
  template <typename Triple>
  double ForEachTriple(bool byOrder, Triple triple) const;
  double TripleVariance(bool byOrder) const;
  // The smaller of the two triples' variances of the mean (-1 with too few of either), and whether the samples'
  // order gave it.
  struct Variance {
    double ofMean = -1;
    bool byOrder = false;
  };
  Variance SmallerVariance() const;
  uint32_t side_;
  SampleMean all_;
  std::vector<double> byCell_;   // each cell's sample luminance; -1 for none
  std::vector<uint32_t> order_;  // the cells in the order their samples were added
  std::vector<Vector3> vectors_;  // each cell's moment vector, once one is added
};

class LightSampler {
 public:
  // From this many area lights on, the light tree chooses them (below it, the exact guess over every light, which
  // costs O(lights) per point): the sports car's 374 LED lamps spent most of their direct light in the guess.
  static constexpr size_t kTreeLights = 64;
  // Lights of more triangles than this are tested in O(1) whether they can reach a point, conservatively (MayReach:
  // their box, planes and cone of normals); smaller ones triangle by triangle, exactly.
  static constexpr size_t kExactReachTriangles = 8;
  // Lights of at most max(this, samples / 4) triangles that subtend at least kSolidAngleFrom [sr] at a point are
  // sampled by solid angle there (see the top).
  static constexpr size_t kSolidAngleTriangles = 4;
  static constexpr double kSolidAngleFrom = 0.01;
  // A curved light (its front normals spread over more than kCurvedSpread [rad]) of at most max(this, samples / 4)
  // triangles that is sampled by area at a point picks its triangle there in proportion to the solid angle the
  // triangle projects to, A cos(theta_y) / d^2 at its centroid, instead of by area (see the top).
  static constexpr size_t kFacingTriangles = 256;
  static constexpr float kCurvedSpread = 0.01f;

  // All three must outlive the sampler. treeFrom: the number of area lights from which the tree chooses them;
  // solidAngleFrom: the solid angle [sr] from which a light is sampled by it (infinity: always by area);
  // curvedSpread: the spread of front normals [rad] above which a light is curved (infinity: none is).
  LightSampler(const Scene& scene, const std::vector<Light>& lights, const RayScene& rays,
               size_t treeFrom = kTreeLights, double solidAngleFrom = kSolidAngleFrom, float curvedSpread = kCurvedSpread);

  // E_d at point p (local coordinates [m]) with unit normal n, from `samples` shadow rays drawn from `rng`. With
  // `moments`, the same samples' moments (estimators/incident_moments.h) are added to it; E_d is the same bit for bit.
  DirectSample Irradiance(Point3 p, Normal3 n, uint32_t samples, Rng& rng, IncidentMoments* moments = nullptr) const;

  // E_d with as many shadow rays as reach relative standard error `target` at p: a pilot of kPilotSamples, from
  // a stream of its own, predicts the count S = kPilotSamples (r / target)^(1 / kStratifiedOrder) from its
  // relative error r: the error of stratified samples falls as S^-3/4 where a shadow's edge crosses the light
  // (Mitchell 1996, "Consequences of stratified sampling in graphics"), and faster where the light is smooth, so
  // S is conservative; independent samples' S^-1/2 would ask several times too many. Then E_d
  // comes from S fresh samples alone, S rounded up to a square (it fills the stratification grid) and clamped to
  // [kPilotSamples, maxSamples]. The pilot is not averaged in: the count
  // depends on it, and keeping it would bias E_d. Unbiased; the returned relative noise is the fresh samples'.
  // `moments` as Irradiance's, from the fresh samples.
  static constexpr uint32_t kPilotSamples = 16;
  static constexpr double kStratifiedOrder = 0.75;
  DirectSample AdaptiveIrradiance(Point3 p, Normal3 n, double target, uint32_t maxSamples, Rng& rng,
                                  IncidentMoments* moments = nullptr) const;
  // The count S it takes after the pilot, from an estimate of `relativeNoise` at `samples` rays (the pilot's, or
  // a whole bake's, which the rounds of --target-noise plan from).
  static uint32_t AdaptiveCount(double relativeNoise, uint32_t samples, double target, uint32_t maxSamples);

  // The sky's radiance along a ray that leaves the scene in direction w [W/(m^2 sr)]: what a path that escapes
  // after a specular event sees.
  Rgb SkyRadiance(Vector3 w) const;

  // The solid angle that a light's triangles subtend at p, each triangle whose front faces p, with the CDF that
  // picks one in proportion to its part.
  struct Subtended {
    std::vector<SphericalTriangle> parts;
    std::vector<uint32_t> triangles;  // Scene::triangles indices
    std::vector<double> cdf;
    double total = 0;  // [sr]
  };
  // A curved light's triangles that face p, each with the probability density per unit area [1/m^2] of a point
  // drawn from it: its share of their projected solid angles over its area; with the CDF that picks one.
  struct Facing {
    std::vector<uint32_t> triangles;  // Scene::triangles indices
    std::vector<double> cdf, density;
  };

  // For a path tracer's next-event estimation with multiple importance sampling (Veach and Guibas 1995;
  // estimators/light_sampler_one.cpp): one sample of the area lights at (p, n), drawn as Irradiance draws one
  // (the light by the same probabilities, then a point by area or a direction by solid angle), with the pdf of its
  // direction; and the pdf with which such a sample would draw the direction from p toward a point y of a light's
  // triangle. Working memory is the caller's, so that nothing is allocated per call.
  struct OneSampleScratch {
    Subtended seen;
    Facing facing;
    std::vector<double> guesses;  // per area light, without a light tree
  };
  struct AreaSample {
    Rgb irradiance;  // Ke V cos(theta_x) / pdf [W/m^2]: 0 when the ray is blocked or no light can reach p
    Vector3 from;    // unit, toward the light
    float pdf = 0;   // of `from` [1/sr]
  };
  AreaSample SampleAreaLights(Point3 p, Normal3 n, Rng& rng, OneSampleScratch& scratch) const;
  // [1/sr]; 0 where `triangle` is not an area light's or cannot be drawn from p.
  float AreaLightPdf(Point3 p, Normal3 n, uint32_t triangle, Point3 y, OneSampleScratch& scratch) const;
  // One sample of the other lights' irradiance [W/m^2] (point, spot and sun exactly, the sky by one ray).
  Rgb OtherIrradiance(Point3 p, Normal3 n, Rng& rng) const;

 private:
  struct LightShape {
    Point3 centroid;
    double power = 0;  // luminance of Ke times the area [W/sr]
    float radius = 0;  // of the sphere about the centroid that holds every corner [m]
    std::vector<Point3> corners;
    Vector3 axis{0, 0, 1};  // the cone that holds every triangle's front normal (BoundsOf's)
    float spread = 0;       // its half-angle [rad]
    Point3 lo, hi;          // the box that holds every corner [m]
    float nearest = 0;      // the least dot(corner, axis) over the corners [m]
  };
  // Light selection probabilities at p (summing to 1), as a CDF; empty when no light can reach p.
  std::vector<double> SelectionCdf(Point3 p, Normal3 n) const;
  bool CanReach(const LightShape& light, const Light& area, Point3 p, Normal3 n) const;
  static bool MayReach(const LightShape& light, Point3 p, Normal3 n);
  // Fills `seen`; false where the light is sampled by area at p: more than `triangles` triangles, or too small a
  // solid angle.
  bool SubtendedAt(size_t area, Point3 p, size_t triangles, Subtended& seen) const;
  // Fills `facing`; false where the light is flat or has more than `triangles` triangles.
  bool FacingAt(size_t area, Point3 p, size_t triangles, Facing& facing) const;
  // Area lights (indices into areas_) seen from p, each computed at most once per point, when a sample first picks
  // it: by solid angle, by projected solid angle (a curved light), or neither (by area).
  struct Seen {
    std::optional<Subtended> subtended;
    std::optional<Facing> facing;
  };
  struct SubtendedCache {
    size_t triangles = kSolidAngleTriangles;  // the most a light sampled by solid angle may have
    std::unordered_map<uint32_t, Seen> lights;  // by area light, once it is first picked
  };
  // An irradiance sample [W/m^2], the unit direction it arrives from, and that direction's pdf [1/sr] once the
  // light is chosen.
  struct Arrival {
    Rgb irradiance;
    Vector3 from;
    float pdf = 0;
  };
  Arrival SampleOne(size_t area, Point3 p, Normal3 n, Point2 u, SubtendedCache& cache) const;
  Arrival SampleByArea(const Light& light, Point3 p, Normal3 n, Point2 u) const;
  Arrival SampleBySolidAngle(const Light& light, const Subtended& seen, Point3 p, Normal3 n, Point2 u) const;
  Arrival SampleByFacing(const Light& light, const Facing& facing, Point3 p, Normal3 n, Point2 u) const;
  // Ke V cos(theta_x) for the point y of a light: the shadow ray, which both samplers share.
  Rgb Unoccluded(const Light& light, Point3 p, Normal3 n, Point3 y) const;
  struct Pick {
    uint32_t area;  // index into areas_
    double pmf;
  };
  // The light that u picks: from the tree, or else from `cdf` (SelectionCdf's).
  std::optional<Pick> PickLight(const std::vector<double>& cdf, Point3 p, Normal3 n, float u) const;
  // The same choice and probabilities with nothing allocated (the guesses in the scratch).
  std::optional<Pick> PickOne(Point3 p, Normal3 n, float u, OneSampleScratch& scratch) const;
  double PmfOf(uint32_t area, Point3 p, Normal3 n, OneSampleScratch& scratch) const;
  struct Selection;
  Selection SelectionAt(Point3 p, Normal3 n, OneSampleScratch& scratch) const;
  // SelectionCdf's unoccluded guess of a light's share at p, before normalising; < 0 where it cannot reach p.
  double Guess(size_t area, Point3 p, Normal3 n) const;
  // A light's probability before normalising, from its guess g > 0, the guesses' total and the lights that can
  // reach the point: 1 - kUniformShare of the choice by the guess, kUniformShare evenly.
  static constexpr double kUniformShare = 0.1;
  static double Share(double g, double total, size_t reachable) {
    return (1 - kUniformShare) * g / total + kUniformShare / double(reachable);
  }
  DirectSample AreaIrradiance(Point3 p, Normal3 n, uint32_t samples, Rng& rng, IncidentMoments* moments) const;
  LightBounds BoundsOf(const LightShape& shape, const Light& light) const;
  Rgb DeltaIrradiance(const AnalyticLight& light, Point3 p, Normal3 n, IncidentMoments* moments) const;
  Arrival DeltaArrival(const AnalyticLight& light, Point3 p, Normal3 n) const;
  DirectSample SkyIrradiance(const AnalyticLight& sky, Point3 p, Normal3 n, uint32_t samples, Rng& rng,
                             IncidentMoments* moments) const;
  DirectSample AimedSkyIrradiance(const Light& sky, Point3 p, Normal3 n, uint32_t samples, Rng& rng,
                                  IncidentMoments* moments) const;
  bool Escapes(Point3 origin, Vector3 w) const;

  const Scene& scene_;
  const std::vector<Light>& lights_;
  const RayScene& rays_;
  std::vector<uint32_t> areas_;     // the area lights, as indices into lights_
  std::vector<LightShape> shapes_;  // per area light, in the order of areas_
  std::vector<uint32_t> others_;    // the other lights
  std::optional<LightTree> tree_;   // over areas_, from kTreeLights of them
  std::unordered_map<uint32_t, uint32_t> areaOfTriangle_;  // an area light's triangle -> its index in areas_
  double solidAngleFrom_;
  float curvedSpread_;
};

}  // namespace pb
