// Stages 1 to 3 as the bake runs them: each round's photons traced (on one process, or shared among the processes
// of a distribution) and binned (PhotonRounds, baker/photons/photon_rounds.h), the irradiance field built from
// them (stage 3), and the light at every vertex estimated with its noise [W/m^2], round after round until the
// rounds stop; where Ctrl-C or the time budget stops an estimate, the vertices left read the fewest samples (the
// first round) or the round before's light (a later one).
#pragma once

#include <optional>
#include <vector>

#include "baker/0_prepare_scene.h"
#include "baker/3_irradiance_field.h"
#include "baker/baked_mesh.h"
#include "baker/files/atomic_file.h"
#include "baker/photons/photon_rounds.h"
#include "baker/photons/progressive.h"
#include "baker/runtime/progress.h"
#include "baker/runtime/stage_clock.h"

namespace pb {

class Distribution;

// Stage 3 from a round's photons: the irradiance field they give, and the light at every vertex with its noise.
struct Lit {
  std::optional<IrradianceField> field;
  BakedMesh baked;
  double noise = 0;  // the bake's predicted noise (BakeNoise)
  BakeError error;   // and its predicted error of H (PredictedError)
  NoiseParts noiseParts;  // the noise of each source alone (BakeNoiseParts)
};

// The time the estimate took per vertex, over every round [s]: what a texel or a refined vertex costs.
double SecondsPerPoint(const Lit& lit, const PhotonRounds& rounds, const StageClock& clock);

// Stages 1 to 3 once with --photons, or in rounds until --target-noise (baker/photons/photon_rounds.h); then
// --save-photons. Ctrl-C ends the rounds: in the first round's tracing, the bake goes on with the photons it has;
// in the first round's estimate, the vertices left read the fewest samples; in a later round, that round's estimate
// stops (at once, when the Ctrl-C came while it traced) and the bake keeps the vertices of the round before. The
// rounds' deadline stops an estimate alike. `field`: stage 3's own settings, to which each round's plan adds its
// shadow rays, gathered paths and held h; `estimated`: one flag per surface whose vertices are estimated (empty:
// every surface).
Lit TraceAndEstimate(PhotonRounds& rounds, const PreparedScene& scene, const FieldSettings& field,
                     const std::vector<bool>& estimated, OutputFiles& outputs, const Distribution* distribution,
                     StageClock& clock, const Log& log);

}  // namespace pb
