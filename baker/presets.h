// The defaults policy: what bake (and bake-mpi) choose for the options the user did not give, so that a bake
// suits a scene of any size at no option but the scene and -o: h per surface from the photons, rounds to a noise
// target within the time budget, gathering on the smallest surfaces; and the --quality presets, each a target and
// a first round. Options given explicitly always win. docs/bake.md ("Quality presets", "Target error") has what
// each reaches on the box and the office.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "baker/options.h"

namespace pb {

// --quality: a name for a target and the first round's photons (--photons): the predicted error of H
// (--target-error) for draft, high and production, the defaults' noise target (--target-noise) for medium. h is
// chosen per surface from the photons (--h auto) and the shadow rays and gathered paths by the rounds, so a preset
// suits a scene of any size; options given explicitly win (docs/bake.md, "Quality presets", has what each reaches
// on the box and the office).
//   draft       error 8%, first round   160,000 photons, 32 shadow rays and 32 gathered paths a point
//   medium      noise 3%, first round 1,000,000 photons (the defaults)
//   high        error 3%, first round 2,000,000 photons
//   production  error 2%, first round 2,000,000 photons, and the edges gathered (--gap-edges, 1,024 paths to start)
struct QualityPreset {
  float target;       // --target-noise, or with `error` --target-error (baker/photons/progressive.h)
  uint64_t photons;   // the first round's, over all lights
  bool error = false;  // the target is the predicted error of H, not the noise's 95th percentile
  bool gatherEdges = false;  // --gap-edges (baker/3_gap_gather.h)
  // The first round's --direct-samples and --gap-paths per point; 0: the defaults' (DirectSettings, GapSettings).
  uint32_t shadowRays = 0, gapPaths = 0;
};
// "draft", "medium", "high" or "production"; nullopt for any other name.
std::optional<QualityPreset> ParseQuality(std::string_view name);
std::string QualityNames();  // comma-separated, for --help and error messages

// The noise the defaults aim at: the 95th percentile of the displayed light's predicted relative error at 3%
// (baker/photons/progressive.h; docs/bake.md, "Defaults that suit the scene").
constexpr float kDefaultTargetNoise = 0.03f;
// The defaults gather on surfaces smaller than 6 h^2 (--gap-small-area), the smallest first, while they hold at
// most a tenth of the triangles (GapSettings::smallShare; docs/bake.md, "Narrow gaps").
constexpr float kDefaultSmallArea = 6, kDefaultSmallShare = 0.1f;

// Which of the options that the defaults choose were given on the command line (or, for photons, by --quality).
struct GivenOptions {
  bool bandwidth = false;   // --h
  bool photons = false;     // --photons
  bool shadowRays = false;  // --direct-samples or --direct-noise
  bool gapPaths = false;    // --gap-paths
  bool smallArea = false;   // --gap-small-area
};
// The first round's photons for --target-error `target`, from a first round of `photons` that suits target `at`:
// photons (at / target)^2, within [250,000, 32,000,000]. h is chosen from the first round and held, so a first
// round sized for the target gives the h that suits about the photons the target needs (the box at 1%: 1.24% net
// from 2M photons, 0.91% from 8M, in about the same time; docs/bake.md, "Target error").
uint64_t FirstRoundForError(float target, uint64_t photons, float at);
// The first round of --target-error, sized for it from a first round of `photons` photons, o's shadow rays and o's
// gathered paths that suits target `at`, for what was not given: the photons by FirstRoundForError, the shadow
// rays by (at / target)^(1 / LightSampler::kStratifiedOrder) (their noise falls as S^-0.75; a square, within
// [16, 4,096]) and the paths by (at / target)^2 (within [16, 65,536]), so that a round can meet the target on its
// own: the box at --quality production --target-error 0.01 reads 0.97% net in one round of 676 rays and 4,096
// paths in 4.7 s, where raising them in a second round took 6.3 s.
void SizeFirstRoundForError(BakeOptions& o, const GivenOptions& given, uint64_t photons, float at);
// `bake`'s defaults that suit the scene, for what was not given: h chosen per surface from its photons (--h auto),
// and photons and shadow rays raised in rounds to kDefaultTargetNoise within --max-seconds (--target-noise), or,
// with --target-error, from a first round sized for it (SizeFirstRoundForError, from the defaults' first round at 3%). The
// kernel and histogram estimators only (knn has no h, and its noise is set by k); not with --reference (no
// photons) or --resume (which continues to --photons).
void ApplySceneDefaults(BakeOptions& o, const GivenOptions& given);
// bake's and bake-mpi's gathering on the smallest surfaces (kDefaultSmallArea, kDefaultSmallShare) unless
// --gap-small-area is given (which then gathers on every surface it names small); not with knn, which has no h.
void ApplyGapDefaults(BakeOptions& o, const GivenOptions& given);
// --quality NAME, for what was not given: its target (unless --target-noise is given, or the bake has no rounds:
// --reference, knn), its first round's photons, shadow rays and gathered paths (for a --target-error given in
// place of an error preset's, SizeFirstRoundForError from the preset's) and its gathered edges. Before
// ApplySceneDefaults, whose `given.photons` it then implies. An InputError naming --quality for an unknown name.
void ApplyQuality(std::string_view name, const GivenOptions& given, BakeOptions& o);
// All that bake's (and bake-mpi's) command line applies for what was not given, in order: --quality `quality`
// (when not empty), the scene's defaults and the gathering's.
void ApplyDefaults(BakeOptions& o, GivenOptions given, std::string_view quality);

}  // namespace pb
