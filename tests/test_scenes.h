// Closed-form test scenes written as OBJ + MTL into a fresh temporary directory, and small helpers to load them.
// All lengths in metres, radiance in W/(m^2 sr).
#pragma once

#include <array>
#include <string>
#include <vector>

namespace pb::test {

// Writes an 8-bit sRGB PNG of width x height pixels, `rgb` row-major, top row first, 3 bytes per pixel.
void WritePngRgb8(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb);

// A fresh, empty directory under the system temp dir, unique to this process and `name`.
std::string TempDirectory(const std::string& name);

// Writes `text` to `path` (overwriting).
void WriteText(const std::string& path, const std::string& text);

// Appends a material "textured" with map_Kd tex.png to the material library `mtlPath`, and writes tex.png (2 x 2
// grey pixels) beside it; returns the PNG's path. No face uses the material; the texture is still loaded.
std::string AddTexture(const std::string& mtlPath);

// A disc of radius 1 m in the plane y = 0, cut as one OBJ polygon of `corners` corners (as CAD exports write flat
// caps), under a 0.4 m square light of radiance 10 facing down 1 m above its centre; both black, so H is direct
// light only. Returns the OBJ path (dir/d.obj).
std::string WriteDiscPolygon(const std::string& dir, int corners);

// A square light of side `lightSide` and radiance `radiance` (grey), facing down at height `height`, centred
// over a square floor of side `floorSide` in the plane y = 0, both centred on the y axis, black (Kd 0) unless
// floorAlbedo is given. The light is black, so no light returns to the floor: its H is Lambert's either way.
// The floor is cut into `floorCells` x `floorCells` quads. Returns the OBJ path.
std::string WriteSquareLightOverFloor(const std::string& directory, float lightSide, float radiance, float height,
                                      float floorSide, int floorCells, float floorAlbedo = 0);

// A hard shadow: a grey (Kd `albedo`) floor square y = 0, x and z in [-1, 1] (cut into floorCells^2 quads),
// lit by a small square light (side `lightSide`, radiance `radiance`) facing down at y = 1 above the origin,
// with a black (Kd 0) square occluder of side `occluderSide` at y = 0.5 between them. The umbra on the floor is
// the square of side 2 * occluderSide - lightSide, and the penumbra around it is lightSide wide. With
// occluderSide = 0 there is no occluder. Returns the OBJ path.
std::string WriteShadowScene(const std::string& directory, float albedo, float lightSide, float radiance,
                             float occluderSide, int floorCells);

// A grey (Kd `albedo`) floor square y = 0, x and z in [-2, 2], facing up, under rectangular lamps of radiance
// `radiance` (Kd 0) at height y, spanning [x0, x1] x [z0, z1], each facing down or up. Returns the OBJ path.
struct TestLamp {
  float x0, x1, z0, z1, y;
  bool facingDown = true;
};
std::string WriteFloorWithLamps(const std::string& directory, float albedo, float radiance,
                                const std::vector<TestLamp>& lamps);

// An LED ceiling: side x side square lamps (Kd 0) of side `lampSide` on a grid of pitch `pitch` centred over the
// origin at height `height`, facing down, each its own surface and so its own light, over a black floor y = 0 of
// side `floorSide` (one quad). Lamp (i, j) has the grey radiance LampGridRadiance(i, j): 20 levels spread evenly
// in log over 1 to 1000 W/(m^2 sr), so that the lamps' powers span three decades. Returns the OBJ path
// (dir/lamps.obj); LampGridSquare gives lamp (i, j)'s corners.
std::string WriteLampGrid(const std::string& directory, int side, float pitch, float lampSide, float height,
                          float floorSide);
double LampGridRadiance(int i, int j);
std::vector<std::array<double, 3>> LampGridSquare(int side, float pitch, float lampSide, float height, int i, int j);

// A narrow gap: a grey (Kd 0.5) room [0, 1]^3 m, its floor cut into 20 x 20 quads (5 cm), lit by a 0.2 m square
// light of radiance 10 just under the ceiling, and a grey slab [0.3, 0.7] x [0.003, 0.013] x [0.3, 0.7] floating
// 3 mm above the floor: the floor under it is lit only through the 3 mm mouth around its rim. Returns the OBJ path.
std::string WriteGapScene(const std::string& directory);

// A grey (Kd 0.5) 10 x 10 m floor y = 0 under two 1 x 1 m lamps facing down at y = 1: "a" of radiance 1 and "b"
// of radiance 3, so Phi_a : Phi_b = 1 : 3. Returns the OBJ path.
std::string WriteTwoLamps(const std::string& directory);

// A closed cube of side `side` whose six inward-facing walls have grey albedo `albedo`, with a small square
// light of side `lightSide` and radiance `radiance` facing down `lightGap` x `side` below the ceiling (0: flush
// with it, overlapping the ceiling's faces). With glassRadius > 0 a
// clear glass icosphere (material "glass", index `ior`, Tf 1, 1280 triangles) of that radius stands on the
// floor's centre, 1% of `side` above it. Returns the OBJ path.
std::string WriteClosedBox(const std::string& directory, float side, float albedo, float lightSide, float radiance,
                           float glassRadius = 0, float ior = 1.5f, float lightGap = 0.001f);

// Closed curved receivers around a small emissive icosphere (radius `lightRadius`, radiance `radiance`, facing
// out) at the origin. The receiver faces inward, has grey albedo `albedo`, and is one of:
//   kSphere:   an icosphere of radius 1 m, the icosahedron subdivided `detail` times (20 * 4^detail triangles);
//   kBlob:     that icosphere with its radius modulated, r = 1 + 0.25 sin(2 theta) cos(3 phi) + 0.1 cos(5 theta);
//   kCylinder: a capped cylinder of radius 0.6 m and height 1.6 m, 16 * 2^detail segments around.
enum class CurvedShape { kSphere, kBlob, kCylinder };
std::string WriteCurvedEnclosure(const std::string& directory, CurvedShape shape, int detail, float albedo,
                                 float lightRadius, float radiance);

}  // namespace pb::test
