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
// Usage: make-scene led-room|one-light|grid-room|lit-copy|door-rooms [--lamps N] [--triangles N]
// [--light-triangles N] [--from OBJ] [--gap M] [--cell M] --out DIR;
// prints the OBJ's path.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
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
  const auto faces = [&](const char* material, const std::vector<Quad>& quads) {
    obj += fmt::format("usemtl {}\n", material);
    for (const Quad& q : quads) GridFace(obj, vertex, q.corner, q.a, q.b, cell);
  };
  faces("floor", {{{-kW, 0, -kD}, {0, 0, 2 * kD}, {kW - kHalfWall, 0, 0}},      // room A, facing up
                  {{kHalfWall, 0, -kD}, {0, 0, 2 * kD}, {kW - kHalfWall, 0, 0}}});  // room B
  std::vector<Quad> walls = {
      {{-kW, kH, -kD}, {kW - kHalfWall, 0, 0}, {0, 0, 2 * kD}},  // ceilings, facing down
      {{kHalfWall, kH, -kD}, {kW - kHalfWall, 0, 0}, {0, 0, 2 * kD}},
      {{-kW, 0, -kD}, {0, kH, 0}, {0, 0, 2 * kD}},               // x = -4, facing +x
      {{kW, 0, -kD}, {0, 0, 2 * kD}, {0, kH, 0}},                // x = +4, facing -x
  };
  for (double x0 : {-kW, kHalfWall}) {  // each room's z = -2 (facing +z) and z = +2 (facing -z) walls
    walls.push_back({{x0, 0, -kD}, {kW - kHalfWall, 0, 0}, {0, kH, 0}});
    walls.push_back({{x0, 0, kD}, {0, kH, 0}, {kW - kHalfWall, 0, 0}});
  }
  // The dividing wall's two sides around the doorway: room A's faces -x (a along z, b along y), room B's +x.
  for (double z0 : {-kD, d}) {
    walls.push_back({{-kHalfWall, 0, z0}, {0, 0, kD - d}, {0, kH, 0}});
    walls.push_back({{kHalfWall, 0, z0}, {0, kH, 0}, {0, 0, kD - d}});
  }
  walls.push_back({{-kHalfWall, kDoorH, -d}, {0, 0, 2 * d}, {0, kH - kDoorH, 0}});
  walls.push_back({{kHalfWall, kDoorH, -d}, {0, kH - kDoorH, 0}, {0, 0, 2 * d}});
  // The doorway's jambs and head, facing into it.
  walls.push_back({{-kHalfWall, 0, -d}, {2 * kHalfWall, 0, 0}, {0, kDoorH, 0}});
  walls.push_back({{-kHalfWall, 0, d}, {0, kDoorH, 0}, {2 * kHalfWall, 0, 0}});
  walls.push_back({{-kHalfWall, kDoorH, -d}, {2 * kHalfWall, 0, 0}, {0, 0, 2 * d}});
  faces("white", walls);
  // The door: hinged at (kHalfWall, y, d), turned into room B by the angle that leaves `gap` at its free edge.
  const double t = std::asin(std::clamp(gap / kDoor, 0.0, 1.0)), s = std::sin(t), c = std::cos(t);
  const double u[3] = {kDoor * s, 0, -kDoor * c}, n[3] = {kDoorT * c, 0, kDoorT * s}, up[3] = {0, kDoorH, 0};
  const double hinge[3] = {kHalfWall, 0, d}, back[3] = {hinge[0] + n[0], 0, hinge[2] + n[2]};
  const double freeEdge[3] = {hinge[0] + u[0], 0, hinge[2] + u[2]};
  const double top[3] = {hinge[0], kDoorH, hinge[2]};
  faces("wood", {{{hinge[0], 0, hinge[2]}, {up[0], up[1], up[2]}, {u[0], u[1], u[2]}},  // facing -n: room A's side
                 {{back[0], 0, back[2]}, {u[0], u[1], u[2]}, {up[0], up[1], up[2]}},    // facing +n
                 {{freeEdge[0], 0, freeEdge[2]}, {n[0], n[1], n[2]}, {up[0], up[1], up[2]}},  // the free edge
                 {{top[0], top[1], top[2]}, {n[0], n[1], n[2]}, {u[0], u[1], u[2]}}});   // its top
  const double l = 0.25, y = kH - 0.01;  // the light, facing down, counter-clockwise seen from below
  obj += fmt::format("usemtl light\nv {0} {2} {1}\nv {3} {2} {1}\nv {3} {2} {4}\nv {0} {2} {4}\nf {5} {6} {7} {8}\n",
                     -kW / 2 - l, -l, y, -kW / 2 + l, l, vertex, vertex + 1, vertex + 2, vertex + 3);
  vertex += 4;
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
  app.add_option("kind", kind, "led-room, one-light or grid-room")
      ->check(CLI::IsMember({"led-room", "one-light", "grid-room", "lit-copy", "door-rooms"}));
  double gap = 0.12, cell = 0.1;
  app.add_option("--gap", gap, "door-rooms: the door's opening at its free edge [m]")->capture_default_str();
  app.add_option("--cell", cell, "door-rooms: the faces' grid [m]")->capture_default_str();
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
