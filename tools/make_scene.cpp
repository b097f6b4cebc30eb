// make-scene: writes the large scenes that the scaling measurements bake (docs/performance.md, "Scale"), as OBJ and MTL.
//   led-room:  a grey room (Kd 0.5; 10 x 3 x 10 m, y up) under an LED ceiling of --lamps lamps, each one
//              emissive triangle (a right triangle of legs 2 cm) facing down 1 cm under the ceiling, in a square
//              grid, their radiance over three decades (20 levels, log-uniform, 10^(3 k / 19) W/(m^2 sr)).
//   one-light: the same room under one 1 x 1 m light of the LED ceiling's total flux, at the same height: the
//              baseline that the ceiling's bake time is measured against.
//   grid-room: the one-light room with its six faces cut into a grid of about --triangles triangles in all
//              (squares of side sqrt(2 A / N) over the faces' area A), for the front end's scaling.
//   --light-triangles N cuts the one light (one-light, grid-room) into a grid of about N triangles.
//   lit-copy:  a copy of the OBJ --from (a real asset that has no light of its own) with its material libraries
//              named by absolute path, and one emissive quad added: as wide as the model's bounding box in x and z,
//              facing down (y up) a tenth of the box's height above it, of radiance 10 W/(m^2 sr).
//   door-rooms: two rooms joined by a doorway whose door is left ajar by --gap m (12 cm), the only light in the
//              first: the real interiors' room lit through a gap (docs/real-assets.md).
//   atrium:    a 12 x 12 x 8 m court of two storeys of galleries around an 8 x 8 m well open to the sky, lit only by
//              a small sphere light 2 m above the opening: the real interiors' atrium (docs/real-assets.md).
//   glass-room: a bathroom lit only through a glazed window, a sky panel outside (every path crosses the glass).
// Usage: make-scene led-room|one-light|grid-room|lit-copy|door-rooms|atrium|glass-room [--lamps N] [--triangles N]
// [--light-triangles N] [--from OBJ] [--gap M] [--cell M] --out DIR;
// prints the OBJ's path.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

constexpr double kRoom = 10, kHeight = 3, kLeg = 0.02, kBelowCeiling = 0.01;
constexpr int kLevels = 20;
constexpr double kAtriumRadiance = 2000;  // the atrium's sphere light [W/(m^2 sr)]

double LevelRadiance(int level) { return std::pow(10.0, 3.0 * level / (kLevels - 1)); }

// The lamp's level: a fixed scramble of its index, so that neighbouring lamps differ.
int LampLevel(uint64_t lamp) { return int((lamp * 2654435761u >> 7) % kLevels); }

// One face of the room as a grid of cells of about `cell` [m]: corner + s a + t b for s, t in [0, 1], counter-
// clockwise about a x b (its front).
void GridFace(std::string& obj, uint64_t& vertex, const double corner[3], const double a[3], const double b[3],
              double cell) {
  const auto steps = [&](const double e[3]) {
    return std::max<uint64_t>(1, uint64_t(std::ceil(std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) / cell)));
  };
  const uint64_t ns = steps(a), nt = steps(b), first = vertex;
  for (uint64_t j = 0; j <= nt; ++j)
    for (uint64_t i = 0; i <= ns; ++i) {
      const double s = double(i) / double(ns), t = double(j) / double(nt);
      obj += fmt::format("v {:.6f} {:.6f} {:.6f}\n", corner[0] + s * a[0] + t * b[0], corner[1] + s * a[1] + t * b[1],
                         corner[2] + s * a[2] + t * b[2]);
      ++vertex;
    }
  for (uint64_t j = 0; j < nt; ++j)
    for (uint64_t i = 0; i < ns; ++i) {
      const uint64_t v00 = first + j * (ns + 1) + i, v10 = v00 + 1, v01 = v00 + ns + 1, v11 = v01 + 1;
      obj += fmt::format("f {} {} {}\nf {} {} {}\n", v00, v10, v11, v00, v11, v01);
    }
}

// The room's six faces gridded into about `triangles` triangles, each facing in.
std::string GridRoom(uint64_t triangles, uint64_t& vertex) {
  const double r = kRoom / 2, h = kHeight, area = 2 * kRoom * kRoom + 4 * kRoom * kHeight;
  const double cell = std::sqrt(2 * area / double(triangles));
  struct Face {
    double corner[3], a[3], b[3];
  };
  const Face faces[] = {{{-r, 0, -r}, {0, 0, 2 * r}, {2 * r, 0, 0}},  {{-r, h, -r}, {2 * r, 0, 0}, {0, 0, 2 * r}},
                        {{-r, 0, -r}, {2 * r, 0, 0}, {0, h, 0}},      {{r, 0, -r}, {0, 0, 2 * r}, {0, h, 0}},
                        {{r, 0, r}, {-2 * r, 0, 0}, {0, h, 0}},       {{-r, 0, r}, {0, 0, -2 * r}, {0, h, 0}}};
  std::string obj = "mtllib room.mtl\nusemtl grey\n";
  for (const Face& f : faces) GridFace(obj, vertex, f.corner, f.a, f.b, cell);
  return obj;
}

// Floor, ceiling and four walls, each facing into the room.
std::string Room() {
  const double r = kRoom / 2, h = kHeight;
  std::string obj = "mtllib room.mtl\nusemtl grey\n";
  const double corners[8][3] = {{-r, 0, -r}, {r, 0, -r}, {r, 0, r}, {-r, 0, r},
                                {-r, h, -r}, {r, h, -r}, {r, h, r}, {-r, h, r}};
  for (const auto& c : corners) obj += fmt::format("v {} {} {}\n", c[0], c[1], c[2]);
  obj += "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  return obj;
}

// door-rooms: two rooms side by side (x in [-4, 0] and [0, 4], z in [-2, 2], 2.5 m high, y up) through a 10 cm wall
// whose 0.9 x 2.1 m doorway holds a 4 cm door hinged on room B's side and left ajar by `gap` [m] at its free edge;
// one 0.5 m square light (radiance 30) under room A's ceiling. Room B is lit only through the gap. Faces are gridded
// at `cell` [m]; walls white (Kd 0.75), floors grey (0.5), the door wood (0.45, 0.35, 0.25).
struct Quad {
  double corner[3], a[3], b[3];  // front: a x b
};
std::string DoorRooms(double gap, double cell, uint64_t& vertex) {
  constexpr double kW = 4, kD = 2, kH = 2.5, kHalfWall = 0.05, kDoor = 0.9, kDoorH = 2.1, kDoorT = 0.04;
  const double d = kDoor / 2;
  std::string obj = "mtllib room.mtl\n";
  const auto faces = [&](const char* object, const char* material, const std::vector<Quad>& quads) {
    obj += fmt::format("o {}\nusemtl {}\n", object, material);
    for (const Quad& q : quads) GridFace(obj, vertex, q.corner, q.a, q.b, cell);
  };
  // Each room its own object, so that the accuracy tool's objects.md gives each room's error apart.
  for (const double x0 : {-kW, kHalfWall}) {
    const char* room = x0 < 0 ? "room_a" : "room_b";
    const double facing = x0 < 0 ? 1 : -1, far = x0 < 0 ? -kW : kW, wall = x0 < 0 ? -kHalfWall : kHalfWall;
    std::vector<Quad> quads = {
        {{x0, 0, -kD}, {0, 0, 2 * kD}, {kW - kHalfWall, 0, 0}},         // floor, facing up
        {{x0, kH, -kD}, {kW - kHalfWall, 0, 0}, {0, 0, 2 * kD}},        // ceiling, facing down
        {{x0, 0, -kD}, {kW - kHalfWall, 0, 0}, {0, kH, 0}},             // z = -2, facing +z
        {{x0, 0, kD}, {0, kH, 0}, {kW - kHalfWall, 0, 0}},              // z = +2, facing -z
    };
    // The far wall (x = -4 facing +x, x = +4 facing -x) and the dividing wall's side around the doorway.
    quads.push_back(facing > 0 ? Quad{{far, 0, -kD}, {0, kH, 0}, {0, 0, 2 * kD}} : Quad{{far, 0, -kD}, {0, 0, 2 * kD}, {0, kH, 0}});
    for (const double z0 : {-kD, d})
      quads.push_back(facing > 0 ? Quad{{wall, 0, z0}, {0, 0, kD - d}, {0, kH, 0}} : Quad{{wall, 0, z0}, {0, kH, 0}, {0, 0, kD - d}});
    quads.push_back(facing > 0 ? Quad{{wall, kDoorH, -d}, {0, 0, 2 * d}, {0, kH - kDoorH, 0}}
                               : Quad{{wall, kDoorH, -d}, {0, kH - kDoorH, 0}, {0, 0, 2 * d}});
    faces(room, "floor", {quads[0]});
    faces(room, "white", {quads.begin() + 1, quads.end()});
  }
  // The doorway's jambs and head, facing into it.
  faces("doorway", "white", {{{-kHalfWall, 0, -d}, {2 * kHalfWall, 0, 0}, {0, kDoorH, 0}},
                             {{-kHalfWall, 0, d}, {0, kDoorH, 0}, {2 * kHalfWall, 0, 0}},
                             {{-kHalfWall, kDoorH, -d}, {2 * kHalfWall, 0, 0}, {0, 0, 2 * d}}});
  // The door: hinged at (kHalfWall, y, d), turned into room B by the angle that leaves `gap` at its free edge.
  const double t = std::asin(std::clamp(gap / kDoor, 0.0, 1.0)), s = std::sin(t), c = std::cos(t);
  const double u[3] = {kDoor * s, 0, -kDoor * c}, n[3] = {kDoorT * c, 0, kDoorT * s}, up[3] = {0, kDoorH, 0};
  const double hinge[3] = {kHalfWall, 0, d}, back[3] = {hinge[0] + n[0], 0, hinge[2] + n[2]};
  const double freeEdge[3] = {hinge[0] + u[0], 0, hinge[2] + u[2]};
  const double top[3] = {hinge[0], kDoorH, hinge[2]};
  faces("door", "wood", {{{hinge[0], 0, hinge[2]}, {up[0], up[1], up[2]}, {u[0], u[1], u[2]}},  // facing -n: room A's side
                 {{back[0], 0, back[2]}, {u[0], u[1], u[2]}, {up[0], up[1], up[2]}},    // facing +n
                 {{freeEdge[0], 0, freeEdge[2]}, {n[0], n[1], n[2]}, {up[0], up[1], up[2]}},  // the free edge
                 {{top[0], top[1], top[2]}, {n[0], n[1], n[2]}, {u[0], u[1], u[2]}}});   // its top
  const double l = 0.25, y = kH - 0.01;  // the light, facing down, counter-clockwise seen from below
  obj += fmt::format("o room_a\nusemtl light\nv {0} {2} {1}\nv {3} {2} {1}\nv {3} {2} {4}\nv {0} {2} {4}\nf {5} {6} {7} {8}\n",
                     -kW / 2 - l, -l, y, -kW / 2 + l, l, vertex, vertex + 1, vertex + 2, vertex + 3);
  vertex += 4;
  return obj;
}

// An axis-aligned box [lo, hi] as gridded faces, each facing out; `ends` false leaves out its two faces across y
// (a pillar standing on one slab and carrying the next).
void GridBox(std::string& obj, uint64_t& vertex, const double lo[3], const double hi[3], double cell, bool ends) {
  const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
  std::vector<Quad> quads = {
      {{lo[0], lo[1], lo[2]}, {0, dy, 0}, {dx, 0, 0}},  // z = lo, facing -z
      {{lo[0], lo[1], hi[2]}, {dx, 0, 0}, {0, dy, 0}},  // z = hi, facing +z
      {{lo[0], lo[1], lo[2]}, {0, 0, dz}, {0, dy, 0}},  // x = lo, facing -x
      {{hi[0], lo[1], lo[2]}, {0, dy, 0}, {0, 0, dz}},  // x = hi, facing +x
  };
  if (ends) {
    quads.push_back({{lo[0], lo[1], lo[2]}, {dx, 0, 0}, {0, 0, dz}});  // y = lo, facing -y
    quads.push_back({{lo[0], hi[1], lo[2]}, {0, 0, dz}, {dx, 0, 0}});  // y = hi, facing +y
  }
  for (const Quad& q : quads) GridFace(obj, vertex, q.corner, q.a, q.b, cell);
}

// A sphere of `radius` about `centre` as a twice-subdivided icosahedron (320 triangles), each facing out.
void Sphere(std::string& obj, uint64_t& vertex, const double centre[3], double radius) {
  using V = std::array<double, 3>;
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<V> points = {{-1, g, 0}, {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                           {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < 2; ++level) {
    std::vector<std::array<int, 3>> finer;
    const auto middle = [&](int a, int b) {
      points.push_back({(points[a][0] + points[b][0]) / 2, (points[a][1] + points[b][1]) / 2,
                        (points[a][2] + points[b][2]) / 2});
      return int(points.size() - 1);
    };
    for (const auto& f : faces) {
      const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    faces = finer;
  }
  for (const auto& f : faces)
    for (int corner : f) {
      const V& p = points[size_t(corner)];
      const double scale = radius / std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      obj += fmt::format("v {:.6f} {:.6f} {:.6f}\n", centre[0] + p[0] * scale, centre[1] + p[1] * scale,
                         centre[2] + p[2] * scale);
    }
  for (size_t f = 0; f < faces.size(); ++f, vertex += 3) obj += fmt::format("f {} {} {}\n", vertex, vertex + 1, vertex + 2);
}

// atrium: y up; outer walls at x, z = +-6 (8 m high, facing in), a ground floor over all of it; galleries 2 m deep
// around the 8 x 8 m well, their first floor a 20 cm slab at 3.8-4 m and their roof a slab at 8-8.2 m, both
// bordering the well; 0.4 m pillars every 2 m along the well's edge on both storeys, a 1 m balustrade 10 cm thick
// between the first floor's pillars, and four 1 x 3 m banners (2 cm thick) hanging into the well from the roof's
// edge, one per side. The only light: a sphere of radius 0.15 m, radiance kAtriumRadiance, 2 m above the opening, half
// of whose flux leaves upward. Faces gridded at `cell` [m]; stone (Kd 0.6, 0.55, 0.45), the floor 0.5, the banners
// red, green, blue and white.
std::string Atrium(double cell, uint64_t& vertex) {
  constexpr double kOut = 6, kWell = 4, kTop = 8, kFirst = 4, kSlab = 0.2, kPillar = 0.2;
  std::string obj = "mtllib room.mtl\nusemtl floor\n";
  {
    const double corner[3] = {-kOut, 0, -kOut}, a[3] = {0, 0, 2 * kOut}, b[3] = {2 * kOut, 0, 0};
    GridFace(obj, vertex, corner, a, b, cell);
  }
  obj += "usemtl stone\n";
  const std::vector<Quad> walls = {{{-kOut, 0, -kOut}, {2 * kOut, 0, 0}, {0, kTop, 0}},
                                   {{kOut, 0, kOut}, {-2 * kOut, 0, 0}, {0, kTop, 0}},
                                   {{-kOut, 0, kOut}, {0, 0, -2 * kOut}, {0, kTop, 0}},
                                   {{kOut, 0, -kOut}, {0, 0, 2 * kOut}, {0, kTop, 0}}};
  for (const Quad& q : walls) GridFace(obj, vertex, q.corner, q.a, q.b, cell);
  // Each slab is four boxes around the well: two full-width strips across z, two strips between them across x.
  for (double y0 : {kFirst - kSlab, kTop}) {
    const double strips[4][4] = {{-kOut, kOut, kWell, kOut}, {-kOut, kOut, -kOut, -kWell},
                                 {kWell, kOut, -kWell, kWell}, {-kOut, -kWell, -kWell, kWell}};
    for (const auto& s : strips) {
      const double lo[3] = {s[0], y0, s[2]}, hi[3] = {s[1], y0 + kSlab, s[3]};
      GridBox(obj, vertex, lo, hi, cell, true);
    }
  }
  for (int i = -2; i <= 2; ++i)  // pillars along the well's four edges, the corners shared
    for (int side = 0; side < 4; ++side) {
      if ((side >= 2) && (i == -2 || i == 2)) continue;
      const double along = 2.0 * i, across = side % 2 == 0 ? kWell : -kWell;
      const double x = side < 2 ? along : across, z = side < 2 ? across : along;
      for (const auto& [y0, y1] : {std::pair{0.0, kFirst - kSlab}, std::pair{kFirst, kTop}}) {
        const double lo[3] = {x - kPillar, y0, z - kPillar}, hi[3] = {x + kPillar, y1, z + kPillar};
        GridBox(obj, vertex, lo, hi, cell, false);
      }
    }
  for (int side = 0; side < 4; ++side) {  // the balustrade: 5 cm inside the slab's edge, pillar to pillar
    const double across = side % 2 == 0 ? kWell - 0.15 : -kWell + 0.05;
    for (int i = -2; i < 2; ++i) {
      const double a0 = 2.0 * i + kPillar, a1 = 2.0 * (i + 1) - kPillar;
      const double lo[3] = {side < 2 ? a0 : across, kFirst, side < 2 ? across : a0};
      const double hi[3] = {side < 2 ? a1 : across + 0.1, kFirst + 1, side < 2 ? across + 0.1 : a1};
      GridBox(obj, vertex, lo, hi, cell, true);
    }
  }
  const char* banners[4] = {"red", "green", "blue", "white"};
  for (int side = 0; side < 4; ++side) {  // centred between two pillars, 10 cm into the well
    obj += fmt::format("usemtl {}\n", banners[side]);
    const double across = side % 2 == 0 ? kWell - 0.12 : -kWell + 0.1;
    const double lo[3] = {side < 2 ? -1.5 : across, kTop - 3, side < 2 ? across : -1.5};
    const double hi[3] = {side < 2 ? -0.5 : across + 0.02, kTop, side < 2 ? across + 0.02 : -0.5};
    GridBox(obj, vertex, lo, hi, cell, true);
  }
  obj += "usemtl light\n";
  const double centre[3] = {0, kTop + kSlab + 2, 0};
  Sphere(obj, vertex, centre, 0.15);
  return obj;
}

// glass-room: a bathroom (x in [0, 3], y in [0, 2.6] up, z in [0, 2.4]; walls of tiles, Kd 0.8) lit only through
// a 0.8 x 0.9 m window in its x = 3 wall (12 cm thick, its outer face and reveal modelled), glazed with a 6 mm pane
// of glass (illum 7, Ni 1.5, Tf 0.9; frosted in the real ones, smooth here, as the baker reads any glass), beyond
// which a 4 x 4 m sky panel (radiance 8) faces the window 1.5 m out. Inside: a bath along the z = 0 wall, a sink
// cabinet and a toilet along z = 2.4, a mirror (illum 3) above the sink, a shelf under it with four bottles. Every
// path into the room passes the glass twice; faces gridded at `cell` [m].
std::string GlassRoom(double cell, uint64_t& vertex) {
  constexpr double kW = 3, kH = 2.6, kD = 2.4, kT = 0.12, y0 = 1.3, y1 = 2.2, z0 = 0.8, z1 = 1.6;
  std::string obj = "mtllib room.mtl\n";
  const auto faces = [&](const char* object, const char* material, const std::vector<Quad>& quads) {
    obj += fmt::format("o {}\nusemtl {}\n", object, material);
    for (const Quad& q : quads) GridFace(obj, vertex, q.corner, q.a, q.b, cell);
  };
  const auto box = [&](const char* object, const char* material, std::array<double, 3> lo, std::array<double, 3> hi) {
    obj += fmt::format("o {}\nusemtl {}\n", object, material);
    GridBox(obj, vertex, lo.data(), hi.data(), cell, true);
  };
  faces("floor", "floor", {{{0, 0, 0}, {0, 0, kD}, {kW, 0, 0}}});
  faces("room", "tiles", {{{0, kH, 0}, {kW, 0, 0}, {0, 0, kD}},    // ceiling, facing down
                          {{0, 0, 0}, {kW, 0, 0}, {0, kH, 0}},     // z = 0, facing +z
                          {{0, 0, kD}, {0, kH, 0}, {kW, 0, 0}},    // z = D, facing -z
                          {{0, 0, 0}, {0, kH, 0}, {0, 0, kD}}});   // x = 0, facing +x
  // The window wall around its opening, inside (facing -x) and out (facing +x), and the opening's reveal.
  std::vector<Quad> wall;
  for (const double x : {kW, kW + kT}) {
    const bool in = x == kW;
    for (const auto& [za, zb, ya, yb] : {std::array{0.0, kD, 0.0, y0}, std::array{0.0, kD, y1, kH},
                                         std::array{0.0, z0, y0, y1}, std::array{z1, kD, y0, y1}})
      wall.push_back(in ? Quad{{x, ya, za}, {0, 0, zb - za}, {0, yb - ya, 0}}
                        : Quad{{x, ya, za}, {0, yb - ya, 0}, {0, 0, zb - za}});
  }
  wall.push_back({{kW, y0, z0}, {0, 0, z1 - z0}, {kT, 0, 0}});  // sill, facing up
  wall.push_back({{kW, y1, z0}, {kT, 0, 0}, {0, 0, z1 - z0}});  // head, facing down
  wall.push_back({{kW, y0, z0}, {kT, 0, 0}, {0, y1 - y0, 0}});  // jamb, facing +z
  wall.push_back({{kW, y0, z1}, {0, y1 - y0, 0}, {kT, 0, 0}});  // jamb, facing -z
  faces("window_wall", "tiles", wall);
  const double mid = kW + kT / 2, gap = 0.001;
  box("pane", "glass", {mid - 0.003, y0 + gap, z0 + gap}, {mid + 0.003, y1 - gap, z1 - gap});
  box("bath", "ceramic", {0, 0, 0}, {1.7, 0.55, 0.75});
  box("sink", "wood", {0.6, 0, 1.95}, {1.2, 0.85, kD});
  box("toilet", "ceramic", {2.3, 0, 1.8}, {2.7, 0.42, kD});
  box("toilet", "ceramic", {2.25, 0.42, 2.2}, {2.75, 0.8, kD});
  faces("mirror", "mirror", {{{0.55, 1.1, kD - 0.005}, {0, 0.8, 0}, {0.7, 0, 0}}});
  box("shelf", "wood", {0.6, 0.98, 2.25}, {1.2, 1.0, kD});
  for (int i = 0; i < 4; ++i) {
    const double x = 0.65 + 0.14 * i;
    box("bottles", i % 2 == 0 ? "bottle" : "ceramic", {x, 1.0, 2.3}, {x + 0.05, 1.0 + 0.08 + 0.03 * i, 2.35});
  }
  faces("sky", "sky", {{{kW + 1.5, -0.5, -0.8}, {0, 0, kD + 1.6}, {0, 4, 0}}});  // facing -x, toward the window
  return obj;
}

void Write(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

// lit-copy: `from`'s statements, its mtllib names made absolute, then the light over its bounding box.
std::string LitCopy(const std::string& from, const std::string& lightMtl) {
  std::ifstream in(from);
  if (!in) throw std::runtime_error("cannot read " + from);
  const std::filesystem::path folder = std::filesystem::absolute(from).parent_path();
  std::string obj, line;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("mtllib ", 0) == 0) line = "mtllib " + (folder / line.substr(7)).string();
    if (line.rfind("v ", 0) == 0) {
      double p[3] = {0, 0, 0};
      if (std::sscanf(line.c_str() + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) == 3) {
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
      }
    }
    obj += line + '\n';
  }
  const double y = hi[1] + 0.1 * (hi[1] - lo[1]);
  obj += fmt::format("mtllib {}\nusemtl photonbake_light\n", lightMtl);
  // Counter-clockwise seen from below: facing down.
  obj += fmt::format("v {0} {1} {2}\nv {3} {1} {2}\nv {3} {1} {4}\nv {0} {1} {4}\nf -4 -3 -2 -1\n", lo[0], y, lo[2],
                     hi[0], hi[2]);
  return obj;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"make-scene: the large scenes of the scaling measurements (photonbake)"};
  std::string kind = "led-room", out = "out/scene";
  uint64_t lamps = 100000;
  uint64_t triangles = 2'000'000;
  app.add_option("kind", kind, "led-room, one-light, grid-room, lit-copy, door-rooms, atrium or glass-room")
      ->check(CLI::IsMember({"led-room", "one-light", "grid-room", "lit-copy", "door-rooms", "atrium",
                                 "glass-room"}));
  double gap = 0.12, cell = 0.1;
  app.add_option("--gap", gap, "door-rooms: the door's opening at its free edge [m]")->capture_default_str();
  const CLI::Option* cellGiven =
      app.add_option("--cell", cell, "door-rooms, atrium, glass-room: the faces' grid [m] (atrium: 0.2 unless given)")
          ->capture_default_str();
  app.add_option("--triangles", triangles, "grid-room: triangles of the room's faces")->capture_default_str();
  app.add_option("--lamps", lamps, "lamps of the LED ceiling (one-light: whose flux it carries)")->capture_default_str();
  uint64_t lightTriangles = 2;
  app.add_option("--light-triangles", lightTriangles, "one-light, grid-room: triangles of the light")->capture_default_str();
  std::string from;
  app.add_option("--from", from, "lit-copy: the OBJ to copy");
  app.add_option("--out", out, "folder for room.obj and room.mtl")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::filesystem::create_directories(out);
  if (kind == "lit-copy") {
    const std::string lightMtl = std::filesystem::absolute(out + "/photonbake_light.mtl").string();
    Write(lightMtl, "newmtl photonbake_light\nKd 0 0 0\nKe 10 10 10\n");
    const std::string obj = out + "/" + std::filesystem::path(from).filename().string();
    Write(obj, LitCopy(from, lightMtl));
    fmt::print("{}: {} with a light added\n", obj, from);
    return 0;
  }

  if (kind == "door-rooms") {
    uint64_t vertex = 1;
    Write(out + "/room.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl white\nKd 0.75 0.75 0.75\nnewmtl wood\n"
                             "Kd 0.45 0.35 0.25\nnewmtl light\nKd 0 0 0\nKe 30 30 30\n");
    Write(out + "/room.obj", DoorRooms(gap, cell, vertex));
    fmt::print("{}/room.obj: two rooms, the second lit through a door ajar by {} m\n", out, gap);
    return 0;
  }
  if (kind == "atrium") {
    uint64_t vertex = 1;
    Write(out + "/room.mtl", fmt::format("newmtl floor\nKd 0.5 0.5 0.5\nnewmtl stone\nKd 0.6 0.55 0.45\n"
                                         "newmtl red\nKd 0.6 0.1 0.1\nnewmtl green\nKd 0.1 0.5 0.15\n"
                                         "newmtl blue\nKd 0.1 0.15 0.6\nnewmtl white\nKd 0.8 0.8 0.8\n"
                                         "newmtl light\nKd 0 0 0\nKe {0} {0} {0}\n", kAtriumRadiance));
    Write(out + "/room.obj", Atrium(cellGiven->count() > 0 ? cell : 0.2, vertex));
    fmt::print("{}/room.obj: an atrium open to the sky, lit by a small sphere above the opening\n", out);
    return 0;
  }
  if (kind == "glass-room") {
    uint64_t vertex = 1;
    Write(out + "/room.mtl", "newmtl floor\nKd 0.35 0.33 0.3\nnewmtl tiles\nKd 0.8 0.8 0.78\n"
                             "newmtl ceramic\nKd 0.85 0.85 0.85\nnewmtl wood\nKd 0.45 0.3 0.2\n"
                             "newmtl bottle\nKd 0.2 0.45 0.7\nnewmtl glass\nillum 7\nKd 0 0 0\nNi 1.5\n"
                             "Tf 0.9 0.9 0.9\nnewmtl mirror\nillum 3\nKd 0 0 0\nKs 0.9 0.9 0.9\n"
                             "newmtl sky\nKd 0 0 0\nKe 8 8 9\n");
    Write(out + "/room.obj", GlassRoom(cell, vertex));
    fmt::print("{}/room.obj: a bathroom lit only through a glazed window\n", out);
    return 0;
  }
  std::string mtl = "newmtl grey\nKd 0.5 0.5 0.5\n";
  uint64_t first = kind == "grid-room" ? 1 : 9;  // the next vertex's index: the light's first
  std::string obj = kind == "grid-room" ? GridRoom(triangles, first) : Room();
  const auto side = uint64_t(std::ceil(std::sqrt(double(lamps))));
  const double pitch = 0.9 * kRoom / double(side), y = kHeight - kBelowCeiling;
  double flux = 0;  // sum of Ke A over the lamps [W/sr]
  for (uint64_t lamp = 0; lamp < lamps; ++lamp) flux += LevelRadiance(LampLevel(lamp)) * kLeg * kLeg / 2;
  if (kind != "led-room") {
    mtl += fmt::format("newmtl light\nKd 0 0 0\nKe {0} {0} {0}\n", flux);  // 1 m^2
    if (lightTriangles <= 2) {
      obj += fmt::format("usemtl light\nv -0.5 {0} -0.5\nv 0.5 {0} -0.5\nv 0.5 {0} 0.5\nv -0.5 {0} 0.5\n"
                         "f {1} {2} {3} {4}\n", y, first, first + 1, first + 2, first + 3);
    } else {  // the same square cut into about lightTriangles triangles, facing down
      const double corner[3] = {-0.5, y, -0.5}, a[3] = {1, 0, 0}, b[3] = {0, 0, 1};
      obj += "usemtl light\n";
      GridFace(obj, first, corner, a, b, std::sqrt(2.0 / double(lightTriangles)));
    }
  } else {
    for (int level = 0; level < kLevels; ++level)
      mtl += fmt::format("newmtl lamp_{0}\nKd 0 0 0\nKe {1} {1} {1}\n", level, LevelRadiance(level));
    uint64_t vertex = 9;
    for (int level = 0; level < kLevels; ++level) {  // grouped by material, as exporters write them
      obj += fmt::format("usemtl lamp_{}\n", level);
      for (uint64_t lamp = 0; lamp < lamps; ++lamp) {
        if (LampLevel(lamp) != level) continue;
        const double x = (double(lamp % side) - 0.5 * double(side - 1)) * pitch;
        const double z = (double(lamp / side) - 0.5 * double(side - 1)) * pitch;
        // Counter-clockwise seen from below: facing down.
        obj += fmt::format("v {} {} {}\nv {} {} {}\nv {} {} {}\nf {} {} {}\n", x, y, z, x + kLeg, y, z, x, y,
                           z + kLeg, vertex, vertex + 1, vertex + 2);
        vertex += 3;
      }
    }
  }
  Write(out + "/room.mtl", mtl);
  Write(out + "/room.obj", obj);
  fmt::print("{}/room.obj: {} (total Ke A {:.4g} W/sr, flux {:.4g} W)\n", out,
             kind == "led-room" ? fmt::format("{} lamps", lamps) : std::string("one light"), flux, M_PI * flux);
}
