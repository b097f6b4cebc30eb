// Loads a triangle Scene from Wavefront OBJ + MTL. Positions are multiplied by `scale` to give metres.
//
// Supported: v, vn, vt, f (any polygon, fan-triangulated; v, v/t, v//n, v/t/n; negative indices), o, g, s,
// mtllib, usemtl; in MTL: newmtl, Kd, Ke, Ka, Ks, Ns, Ni, d, Tr, Tf, illum, map_Kd (a PNG albedo), and the other
// map_* statements (warned, ignored).
//
// Reflectance above 0.99 in any channel (Kd, or Kd + Ks for a mirror) is scaled down to 0.99 with a warning: a
// surface that absorbs nothing would never end a path in a closed scene.
//
// The material class (mesh/scene.h) comes from illum:
//   0-2 (and 10, with a warning): diffuse Kd. A Phong highlight Ks under illum 2 is not used.
//   3, 5, 8: mirror: Kd plus an ideal mirror of reflectance Ks (default 1).
//   4, 6, 7, 9: glass: index Ni (default 1.5), transmittance Tf, or else 1 - d (Tr = 1 - d; default clear).
// Lines and points (l, p) are ignored with a warning. Anything else is an InputError.
//
// Why not tinyobjloader: it reads "v 1 2 abc" as (1, 2, 0), accepts NaN coordinates and reports no line for
// most faults. A baker must refuse such input and name file:line, so this strict parser reads the subset above.
//
// Errors (InputError, "file:line: error: ..."): a missing OBJ or MTL file, a malformed number or index, a
// non-finite coordinate, an index out of range, an unknown material, a face before any usemtl, Kd outside
// [0, 1], a negative Ke. Zero-area triangles are skipped and counted in Scene::degenerateTrianglesSkipped. A triangle that repeats
// an earlier one (the same corner positions, facing the same side) is skipped and counted in
// Scene::duplicateTrianglesSkipped: coincident copies would split the photons and the area between them. A
// back-to-back copy (a two-sided panel) is kept.
#pragma once

#include <string>
#include <vector>

#include "mesh/scene.h"

namespace pb {

struct LoadOptions {
  float scale = 1.0f;  // metres per scene unit; range (0, inf), checked by the caller; typical 1 or 0.001.
};

struct LoadedScene {
  Scene scene;
  std::vector<std::string> warnings;  // "file:line: warning: ..." lines, in file order.
};

LoadedScene LoadObj(const std::string& path, const LoadOptions& options = {});

}  // namespace pb
