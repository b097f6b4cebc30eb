// Stage 4 as the command line sets it (--refine, --tolerance, --max-vertices, --subdivide); refinement itself is
// baker/4_refine_mesh.h's, which validates these settings.
#pragma once

#include <cstddef>

namespace pb {

// --refine, --tolerance, --max-vertices, --subdivide.
struct RefineSettings {
  bool adaptive = false;        // --refine: coarsen where the light is flat, refine where it changes
  float tolerance = 0.02f;      // --tolerance: largest displayed-luminance error; range (0, 1), typical 0.01-0.05
  size_t maxVertices = 200'000; // --max-vertices: budget of the written mesh's vertices; >= 3, typical 1e4-1e6
  int subdivide = 0;            // --subdivide: uniform levels first; range [0, 8], each ~4x the vertices
  // Edges are not cut below this fraction of their surface's h [m]: the estimate is smooth at scale h.
  float minimumEdgeFraction = 0.125f;
  bool Enabled() const { return adaptive || subdivide > 0; }
  void Validate() const;  // the ranges above; an InputError naming the option
};

}  // namespace pb
