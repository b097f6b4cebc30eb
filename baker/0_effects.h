// The light transport a bake may simulate, effect by effect, and --effects, the user's overrides of the plan's
// choice (baker/0_plan_transport.h decides, from the scene's materials and lights).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace pb {

enum class Effect : uint8_t { kDirect, kInterreflection, kReflection, kRefraction, kCaustics };
inline constexpr std::array<Effect, 5> kAllEffects = {Effect::kDirect, Effect::kInterreflection, Effect::kReflection,
                                                      Effect::kRefraction, Effect::kCaustics};
std::string EffectName(Effect e);

// --effects: "auto" (the default), "all", or a comma-separated list of NAME or +NAME (force on) and -NAME
// (forbid). A forbidden effect's photons are dropped where it would happen, and their flux is reported.
struct EffectOverrides {
  std::array<std::optional<bool>, kAllEffects.size()> forced;
};
EffectOverrides ParseEffectOverrides(std::string_view text);  // InputError("--effects", ...) on a bad name

}  // namespace pb
