// Stage 3, where no kernel can follow the light: narrow gaps. Between two books 1 mm apart, under a book lying
// 1 mm above a table, behind a mirror 1 mm in front of its frame, the light changes across the gap's width,
// far below any bandwidth h the photons allow, and the photons' density estimate averages the bright mouth of
// the gap with its dark inside. At such a point this term takes the place of the photons' estimate: it gathers
// the light scattered at least once, E_s [W/m^2], by paths from the point that bounce on through the gap and end
// where they first meet a surface far enough away for the photons there to be read (estimators/irradiance_gather.h,
// ScatteredIrradiance; one level of final gathering, Jensen 1996).
//
// A point lies in a gap when, of `probes` cosine-distributed rays from it, at least a fraction `facing` meet,
// within `reach` x its surface's h, a surface within 60 degrees of parallel to its own (facing it or turned
// away). A floor meeting a wall sees the wall at right angles and is not a gap; its kernel, corrected at the
// boundary, follows the light there. With `smallArea` > 0, every point of a surface of area below smallArea h^2
// (smaller than its kernel: a book's face at a wide h) is gathered too: of such surfaces, the smallest first (by
// area, then index), as many as hold at most `smallShare` of the scene's triangles (the vertices' share, near
// enough, and the same whatever part of the scene --only estimates). With `edges`, every point on a planar
// surface's boundary (where RayStart steps it inward: a floor's line along a wall, a block's contact line, a
// wall's corner) is gathered too: there the scattered light turns in a concave corner closer than any h (the
// floor darkens into its corner with the wall), and the kernel's local linear fit reads the turn as a line,
// 0.5-1.3% high on the box's edge vertices on average and 2.4% RMS. A path's hit is read from the photons
// when it lies on a surface's front, at least that surface's h from the path's last vertex, and on a surface
// that is not smaller than its kernel.
//
// Only with --direct sampled, whose photons carry exactly the light scattered at least once. The points' random
// numbers come from their own streams (PointStream), so a point reads the same value on any thread.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "baker/3_gap_settings.h"
#include "baker/3_path_end_light.h"
#include "estimators/irradiance_gather.h"
#include "estimators/light_sampler.h"
#include "estimators/noisy_irradiance.h"
#include "mesh/split_mesh.h"

namespace pb {


class PhotonIrradiance;

class GapGather final : public ScatteredLightField {
 public:
  // All must outlive the gather.
  // `lights` samples the direct light at each diffuse bounce (the field's own, DirectIrradiance's); `guide`, when
  // given, draws the paths' first directions.
  GapGather(const PreparedScene& scene, const PhotonIrradiance& photons, const LightSampler& lights,
            const GapSettings& settings, uint64_t seed, const ImportanceCache* guide = nullptr);

  // Why p, whose rays start at `start` (RayStart), is gathered: on a surface smaller than its kernel, (with `edges`)
  // on a planar surface's boundary, or in a narrow gap; kNone when it is not.
  enum class Kind { kNone, kSmallSurface, kEdge, kNarrowGap };
  Kind KindOf(const SurfacePoint& p, const SurfacePoint& start) const;
  // Whether a point of this kind has its gathered light weighed against the photons' (baker/3_gap_weights.h): in a
  // narrow gap and on a surface smaller than its kernel; a boundary keeps the gathered light.
  static bool Weighed(Kind kind) { return kind == Kind::kNarrowGap || kind == Kind::kSmallSurface; }
  bool InGap(const SurfacePoint& p, const SurfacePoint& start) const { return KindOf(p, start) != Kind::kNone; }
  // E_s at p by `paths` gathered paths, and its relative noise; with `moments`, their moments added to it.
  NoisyIrradiance Gathered(const SurfacePoint& p, const SurfacePoint& start, IncidentMoments* moments = nullptr) const;

  std::optional<Rgb> ScatteredAt(const RayHit& hit, bool onFront) const override;

  // The surfaces smaller than their kernel that `smallShare` left to the photons, the smallest first.
  const std::vector<uint32_t>& SmallLeftOut() const { return leftOut_; }
  // Gathers at every point of such a surface s (SmallLeftOut), or no longer: with the time a bake's rounds left
  // (baker/photons/trace_and_estimate.h). The paths gathered elsewhere read its photons as before, so that no
  // other point's light changes. Not while the gather is read.
  void GatherAtPoints(uint32_t s, bool gathered);
  bool GatheredAtPoints(uint32_t s) const { return small_[s] == kGatheredAtPoints; }
  // The paths read the photons where they end directly, not from the tables (baker/3_path_end_light.h), or from
  // them again: a pilot over a few points would pay the tables' filling at nearly every end, and foretell the
  // whole estimate from that. Not while the gather is read.
  void ReadEndsDirectly(bool direct) { ends_.ReadDirectly(direct); }
  uint64_t RaysCast() const { return gatherer_.RaysCast(); }  // by the gathered paths so far

 private:
  const PreparedScene& scene_;
  const PhotonIrradiance& photons_;
  GapSettings settings_;
  uint64_t seed_;
  IrradianceGatherer gatherer_;
  PathEndLight ends_;  // the photons' light where the paths end
  // Per surface: kUnread, smaller than its kernel within smallShare (gathered at its points, never read); or
  // kGatheredAtPoints (GatherAtPoints: gathered at its points, read as before); else 0.
  static constexpr char kUnread = 1, kGatheredAtPoints = 2;
  std::vector<char> small_;
  std::vector<uint32_t> leftOut_;  // SmallLeftOut
};

}  // namespace pb
