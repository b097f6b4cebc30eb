// Stage 0: which light transport a scene calls for, decided from its materials and lights before any photon is
// traced, so that a bake never pays for an effect its scene does not have (the user's "simulate only the effects
// a scene calls for"). The tracer (stage 1) compiles one photon loop per combination and runs the one chosen here:
//   direct light       always;
//   interreflection    when some surface has Kd > 0; otherwise photons stop at the first surface they reach;
//   reflection         ideal mirror (Ks) and Fresnel reflection, when a mirror or glass material exists;
//   refraction         when a glass material transmits (Tf > 0);
//   caustics           light -> specular -> diffuse paths, when reflection or refraction is simulated.
// A planar light whose front half-space holds no other surface reaches nothing; it gets no photons and the plan
// says why. --effects overrides a choice ("+caustics", "-reflection", "all"); the plan records that too.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "baker/0_effects.h"
#include "mesh/lights.h"
#include "mesh/scene.h"
#include "mesh/surfaces.h"

namespace pb {

struct EffectDecision {
  bool simulated = false;
  bool overridden = false;  // set by --effects rather than by the scene
  std::string reason;
};

struct TransportPlan {
  std::array<EffectDecision, kAllEffects.size()> effects;
  std::vector<bool> lightReaches;       // per Light: false = it gets no photons
  std::vector<std::string> lightNotes;  // per Light: why it gets none; "" when it reaches a receiver
  bool specularMaterials = false;       // some surface is a mirror or glass (mesh/scene.h)
  float largestAlbedo = 0;              // max Kd over surfaces, any channel
  uint32_t significantBounces = 0;      // diffuse bounces until largestAlbedo^n < 1e-3; 0 when unbounded

  bool On(Effect e) const { return effects[size_t(e)].simulated; }
  // The photon loop must sample material classes when the scene has a specular surface (even with its effects
  // forbidden, so that the dropped flux is tallied) or when --effects forces a specular effect on.
  bool NeedsSpecularKernel() const {
    return specularMaterials || On(Effect::kReflection) || On(Effect::kRefraction) || On(Effect::kCaustics);
  }
  std::string Describe(Effect e) const;  // "simulated: why" or "skipped: why"
};

// InputError when no light reaches any receiver.
TransportPlan PlanTransport(const Scene& scene, const SurfaceSet& surfaces, const std::vector<Light>& lights,
                            const EffectOverrides& overrides);

}  // namespace pb
