// Display colour for the PLY's uchar red/green/blue: radiance L [W/(m^2 sr)] times an exposure, compressed
// per channel by Reinhard's x / (1 + x), then encoded with the sRGB transfer curve to 8 bits.
// Automatic exposure (Reinhard et al. 2002, "Photographic Tone Reproduction") maps the log-average luminance
// of the vertices to the key 0.18. The float properties of the PLY are never tone-mapped.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "mesh/color.h"

namespace pb {

// 0.18 / exp(mean ln Y) over the radiances with luminance Y > 0; 1 when there are none. Black vertices (glass,
// black paint, unlit corners) say nothing about the exposure, and any fixed offset inside the log would depend
// on the scene's units, so they are left out.
float AutoExposure(std::span<const Rgb> radiance);

std::array<uint8_t, 3> ToneMap(Rgb radiance, float exposure);

// The same curve before its sRGB encoding: Reinhard's x / (1 + x) of exposure x radiance per channel, linear, in
// [0, 1). glTF's COLOR_0 is linear (the viewer encodes it), so the glTF output stores this.
Rgb ToneMapLinear(Rgb radiance, float exposure);

// The displayed grey level in [0, 1] of radiance L: the same curve as ToneMap, applied to L's luminance and not
// quantised. Mesh refinement (baker/4_refine_mesh.h) measures its interpolation error in this unit.
float DisplayedLuminance(Rgb radiance, float exposure);

}  // namespace pb
