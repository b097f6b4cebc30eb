// Loads a triangle Scene from Wavefront OBJ + MTL (mesh/mtl_loader.h), as the tools that users have write them.
// Positions are multiplied by `scale` to give metres.
//
// Read: v (x y z, with an optional w or r g b), vt, vn (checked, not used: surfaces are shaded from their charts),
// f (any polygon: v, v/t, v//n, v/t/n; negative indices count back from the end), o, g, s, mtllib (one or more
// files; "\ " escapes a space), usemtl. The text itself: mesh/text_lines.h (BOM, UTF-16, any line end, '\'
// continuation).
//
// Polygons are triangulated in their own plane (mesh/polygon.h): convex ones as a fan, concave ones by ear
// clipping, so an L-shaped floor keeps its area and faces its side.
//
// Ignored, with one warning per kind (counted, with its first file:line): lines and points (l, p), free-form
// curves and surfaces (cstype ... end), display and render hints (mg, lod, bevel, maplib, usemap, ...), faces of
// fewer than three corners, and unknown statements. Defaulted, with a warning: faces before any usemtl, or whose
// usemtl names a material no library defines, get the default material, diffuse grey Kd 0.8 (kDefaultAlbedo);
// so do all faces when an mtllib file cannot be found.
//
// Errors (InputError, "file:line: error: ..."), for what would make the geometry wrong: a missing OBJ file, a
// malformed or non-finite number in v, vt or vn, a malformed face index, a vertex index out of range (or a texture
// coordinate index, on a textured face; a textured face with no texture coordinates at all gets Kd times the
// image's mean, with a warning), and a scene with no face to bake
// (the message names what it had instead: lines, points, faces of one or two corners). Zero-area triangles are
// skipped and counted in Scene::degenerateTrianglesSkipped. A triangle that repeats an earlier one (the same corner
// positions, facing the same side) is skipped and counted in Scene::duplicateTrianglesSkipped: coincident copies
// would split the photons and the area between them. A back-to-back copy (a two-sided panel) is kept.
//
// Why not tinyobjloader: it reads "v 1 2 abc" as (1, 2, 0), accepts NaN coordinates and reports no line for
// most faults. A baker must refuse such input and name file:line, so this parser is our own.
#pragma once

#include <string>

#include "mesh/scene_file.h"

namespace pb {

LoadedScene LoadObj(const std::string& path, const LoadOptions& options = {});

}  // namespace pb
