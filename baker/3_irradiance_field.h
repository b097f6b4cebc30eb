// Stage 3: the irradiance field, what the estimate hands on. It answers, for any point of any surface
// (mesh/split_mesh.h, SurfacePoint), the light there:
//   H  irradiance [W/m^2] per unit surface area, the sum of the field's contributions;
//   R  diffuse reflectance (Kd, times its texture at the point), dimensionless;
//   Le emitted radiance [W/(m^2 sr)];
//   L = Le + R H / pi [W/(m^2 sr)], the radiance a viewer sees;
//   the predicted relative noise of H's luminance (sigma / mean, dimensionless; the smoothing bias is not in it).
// Vertices, refinement, maps, noise warnings and --target-noise all ask the field; nothing else converts a photon
// density in a chart to irradiance per unit surface area (PerSurfaceArea, baker/3_contributions.h).
//
// H is a sum of contributions, whose noises add in variance:
//   photons  the photons' density estimate on the point's own surface (kernel, histogram or k nearest;
//            estimators/density_estimator.h), with its own bandwidth h [m] per surface;
//   direct   with --direct sampled, the direct light computed at the point by shadow rays to the lights
//            (estimators/light_sampler.h); the photons then carry only the light scattered at least once;
//   reference with --reference SPP, all of H by SPP paths gathered at the point (estimators/irradiance_gather.h),
//            a path tracer's vertex bake; no photons are traced then.
// At a point inside a closed object (a baluster's end in its handrail) the photons' term is 0: no photon reaches
// it, though the kernel's photons lie a few centimetres away (baker/0_prepare_scene.h, enclosureByPoint).
// With --direct sampled, at a point in a narrow gap (or on a surface smaller than its kernel) the photons' term is
// replaced by the scattered light gathered there (baker/3_gap_gather.h); but for a surface's boundary, once the field
// has weighed its surface's gathered paths against the photons (WeighGaps, baker/3_gap_weights.h), by their mix.
//
// With --sh the field also says where the light at a point comes from: the moments of its incident radiance, the
// sum of every term's (estimators/incident_moments.h), each from the same samples (and photons) as its H.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "baker/2_bin_photons.h"
#include "baker/3_contributions.h"
#include "baker/3_gap_gather.h"
#include "baker/3_gap_weights.h"
#include "baker/baked_mesh.h"
#include "baker/runtime/progress.h"
#include "baker/runtime/stage_clock.h"
#include "mesh/split_mesh.h"

namespace pb {

class Distribution;

// The light at a point: H, R, Le and the relative noise of H (0 unless asked for).
struct SurfaceLight {
  Rgb irradiance, albedo, emitted;
  double relativeNoise = 0;
  double photonVarianceShare = 1;  // of relativeNoise^2: the photons'; the rest is the points' samples
  double gatheredVarianceShare = 0;  // of relativeNoise^2: the paths gathered in a gap (of the points' samples)
  double sampledShare = 0;         // of the irradiance's luminance: the points' samples'; the rest is the photons'
  double relativeBias = 0;         // the photons' predicted smoothing bias (their surface's RMS), relative to H's luminance
  GapPair gap;  // LightWithNoise in a narrow gap: the gathered and the photons' estimates, and the rest of H
  Rgb Radiance() const { return OutgoingRadiance(emitted, albedo, irradiance); }
};

// The work of the field's reads so far, counted over every thread: the samples drawn at the points (shadow rays, or
// --reference's paths) and the rays of the paths gathered in gaps (segments and light samples). What the rounds
// weigh each source's noise against (baker/photons/progressive.h, SharesByWork).
struct FieldWork {
  uint64_t pointSamples = 0, gatheredRays = 0;
  FieldWork operator-(const FieldWork& o) const { return {pointSamples - o.pointSamples, gatheredRays - o.gatheredRays}; }
};

class IrradianceField {
 public:
  // `scene` must outlive the field.
  IrradianceField(const PreparedScene& scene, std::unique_ptr<PhotonIrradiance> photons);
  // Adds a term of H after the photons'.
  void Add(std::unique_ptr<IrradianceContribution> contribution);
  // At points in narrow gaps, gathers the light the photons would have estimated (baker/3_gap_gather.h).
  void GatherGaps(std::unique_ptr<GapGather> gaps);
  // The importance maps that guide the gathered paths' first directions (--guide-photons), kept for the field's
  // life; null when none.
  const ImportanceCache* Guide(std::unique_ptr<ImportanceCache> guide);
  // From here on, mixes the gathered light at each surface's weighed points (narrow gaps, a surface smaller than its
  // kernel: GapGather::Weighed) with the photons' by its weight, learned from the points of it that `pairs` holds
  // (LearnGapWeights); a surface with none keeps the weight it had (before any, the gathered light alone).
  void WeighGaps(const std::vector<GapPair>& pairs);
  GapWeight GapWeightOf(uint32_t s) const { return s < gapWeights_.size() ? gapWeights_[s] : GapWeight{}; }
  // The surfaces smaller than their kernel that the gather's share left to the photons, the smallest first
  // (GapGather::SmallLeftOut); none without a gather.
  std::span<const uint32_t> SmallLeftOut() const;
  // Gathers at every point of such a surface, or no longer (GapGather::GatherAtPoints).
  void GatherAtPoints(uint32_t s, bool gathered) { gaps_->GatherAtPoints(s, gathered); }
  // Gathered paths read the photons where they end directly, not from their tables, or from them again
  // (GapGather::ReadEndsDirectly). Not while the field is read.
  void ReadPathEndsDirectly(bool direct) {
    if (gaps_) gaps_->ReadEndsDirectly(direct);
  }
  const std::vector<GapWeight>& GapWeights() const { return gapWeights_; }  // per surface; empty before WeighGaps
  FieldWork Work() const;
  // What the process that finishes a bake (rank 0 of a distributed one) gives the field after the vertices' estimate:
  // each surface's gap weight (WeighGaps) and which of the small surfaces left out the rounds' spare time gathered
  // (GatherAtPoints). As bytes of the same length on every process of a distributed bake, so that rank 0's can be
  // broadcast into the others' fields before they share the maps' texels.
  std::vector<std::byte> LateState() const;
  void SetLateState(std::span<const std::byte> bytes);
  // Rank 0's late state into this process's field (a broadcast: every process calls it), so that each estimates its
  // share of the maps' texels as rank 0 would.
  void TakeRankZerosLateState(const Distribution& distribution);

  Rgb Irradiance(const SurfacePoint& p) const;
  SurfaceLight Light(const SurfacePoint& p) const;
  // The same light, bit for bit, with the noise of H.
  SurfaceLight LightWithNoise(const SurfacePoint& p) const;
  // R and Le at p with H given (refinement's cached irradiance grid).
  SurfaceLight LightWith(const SurfacePoint& p, Rgb irradiance) const;
  // H and its noise at a vertex in a narrow gap from its two estimates (SurfaceLight::gap) and its surface's weight:
  // LightWithNoise's bit for bit, with R and Le left as `light` has them.
  void Remix(SurfaceLight& light) const;
  // Builds the estimators of the photons' moments from `bins` (the field's own, with directions: --sh), with their
  // progress on `log`; once, before Moments.
  void PrepareMoments(const SurfaceBins& bins, const Log* log = nullptr) { photons_->BuildMoments(*scene_, bins, log); }
  // The moments of the light arriving at p.
  IncidentMoments Moments(const SurfacePoint& p) const;

  const PhotonIrradiance& Photons() const { return *photons_; }
  // The photons' term, taken out of the field, which is left empty: for a field of other terms at the points
  // (WithSampledTerms).
  std::unique_ptr<PhotonIrradiance> TakePhotons() &&;
  // The scale below which H has no detail, on surface s [m]: its photon bandwidth.
  float Bandwidth(uint32_t s) const { return photons_->Bandwidth(s); }
  const PreparedScene& Prepared() const { return *scene_; }

 private:
  // The gathered term that replaces the photons' at p, if p lies in a gap: in a narrow gap, mixed with the photons'
  // by its surface's weight, with the two estimates it was mixed from.
  struct GapTerm {
    BlendedGap blended;
    std::optional<std::pair<NoisyIrradiance, NoisyIrradiance>> estimates;  // narrow gap: gathered, photons
  };
  // Where p's rays start (RayStart), when the field casts any there: for a gap's probes and paths, or to test
  // whether p lies inside a closed object (PreparedScene::enclosureByPoint); else none.
  std::optional<SurfacePoint> RaysStart(const SurfacePoint& p) const;
  // Whether p, whose rays start at `start`, lies inside a closed object: there every term is 0 (no photon, gathered
  // path or shadow ray reaches it). Tested by rays where the surface has no cover lattice
  // (PreparedScene::enclosureByPoint); at a point of the surface's outline beside its cover (AtItsCoversRim), by rays
  // and for being pressed face to face against another surface (PressedAt: its rays would start behind that face);
  // at a covered point, for being pressed. (A point query at every point of the unlatticed surfaces, for their being
  // pressed, cost the conference room's estimate 13 s of 21.)
  bool Enclosed(const SurfacePoint& p, const std::optional<SurfacePoint>& start) const;
  // Whether p lies within 1/64 of its surface's cover spacing of the cover (along u, v or a diagonal), outside it:
  // where a cover runs to the surface's outline (a floor under a bath in the room's corner, a face covered whole),
  // the cover's bisection leaves the outline itself a step outside it, in the open domain.
  bool AtItsCoversRim(const SurfacePoint& p) const;
  // What takes the photons' term's place at p, from one RayStart: 0 inside a closed object (enclosed), or, if p
  // lies in a gap, its gathered light (in a narrow gap mixed with the photons' by its surface's weight, with the two
  // estimates it was mixed from); neither: the photons' own.
  struct Replacement {
    bool enclosed = false;
    std::optional<GapTerm> gap;
  };
  Replacement ReplacedAt(const SurfacePoint& p) const;
  // H's noise and its split from the first term (the photons', or the gap's) and the sum of all terms.
  void SetNoise(SurfaceLight& light, uint32_t surface, float areaRatio, const GapTerm* gap,
                const NoisyIrradiance& first, const IndependentSum& sum) const;

  const PreparedScene* scene_;
  PhotonIrradiance* photons_;
  std::vector<std::unique_ptr<IrradianceContribution>> contributions_;  // photons first
  std::unique_ptr<GapGather> gaps_;                                     // or null
  std::unique_ptr<ImportanceCache> guide_;                              // or null
  std::vector<GapWeight> gapWeights_;                                   // per surface, or empty: alpha 1
};

// What the field is made of: the photons' estimator, and the terms computed at the points.
struct FieldSettings {
  EstimatorSettings estimator;  // its bandwidth none: --h auto
  // h per surface [m], when given: instead of the above (the rounds of --target-noise hold the first round's
  // --h auto, so that their noise falls as 1 / sqrt(photons); baker/photons/progressive.h).
  std::vector<float> heldBandwidths;
  // --direct sampled adds DirectIrradiance. Photons, by default, as TraceSettings stores the first hits by default
  // (storeDirect): the two must agree, or the direct light is counted twice or not at all. Bake() sets both from
  // --direct, whose default is sampled.
  DirectSettings direct{DirectLight::kPhotons};
  uint32_t referencePaths = 0;      // --reference SPP: ReferenceIrradiance instead of direct light (0: none)
  uint64_t seed = 1;                // of the point streams
  GapSettings gaps;                 // with --direct sampled: the gathering in narrow gaps (paths 0: none)
  // --guide-photons: photons traced (apart from the bake's, scattered light only) for the importance maps that
  // guide the first direction of --reference's and the gap gather's paths; 0: cosine directions.
  uint64_t guidePhotons = 0;
  // The sparse surfaces estimated from their photons pooled (PhotonIrradiance; with --h auto).
  bool pool = false;
};

// The field of the photons in `bins`: bandwidths ("bandwidth") and estimators ("estimators") timed on `clock`,
// with the terms computed at the points that `settings` asks for; their progress on `log` when given.
IrradianceField BuildIrradianceField(const PreparedScene& scene, const SurfaceBins& bins, const FieldSettings& settings,
                                     StageClock& clock, const Log* log = nullptr);

// `field`'s photons' term (its bandwidths and estimators, as built) with the terms at the points that `settings`
// asks for, built anew: what the rounds' cuts of the shadow rays and gathered paths build, at the cost of those
// terms alone (the staircase's estimators take 2.3 s).
IrradianceField WithSampledTerms(IrradianceField field, const PreparedScene& scene, const FieldSettings& settings,
                                 StageClock& clock);

// Vertex v of `baked` reads `light`: its H, R and Le, and its noise and their parts where baked holds them.
void SetVertexLight(BakedMesh& baked, size_t v, const SurfaceLight& light);

// Vertices are estimated in chunks of this many, in parallel.
inline constexpr size_t kVertexChunk = 1024;

// H, R and Le at every vertex of `mesh`; with `withNoise`, also each vertex's relative noise
// (BakedMesh::irradianceNoise), from the same queries: H is the same bit for bit either way. With `owns`, only the
// chunks c of vertices [c kVertexChunk, (c + 1) kVertexChunk) for which owns(c) is true (a distributed bake shares
// them out, baker/distribution.h); the others read 0.
BakedMesh EstimateIrradiance(const IrradianceField& field, SplitMesh mesh, const Log& log, bool withNoise = false,
                             const std::function<bool(size_t)>& owns = {});

// Learns each surface's weight of its weighed points' gathered paths (GapGather::Weighed) from `baked`'s vertices (their GapPairs, which it
// empties), gives the field the weights, and mixes those vertices' light by them (IrradianceField::Remix): the bake's
// vertices then read what the field says at the same points. Deterministic: the vertices are summed in order.
void WeighGatheredPaths(IrradianceField& field, BakedMesh& baked);

// The L1 SH of the light at every vertex of `baked` (BakedMesh::sh), each with its component along the vertex's
// normal set to the vertex's H (ShProjection), and the noise of its direction (BakedMesh::directionNoise), in
// parallel, with its progress on `log`.
void EstimateDirections(const IrradianceField& field, BakedMesh& baked, const Log& log);

}  // namespace pb
