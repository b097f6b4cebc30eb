#include "tests/test_scenes.h"

#include <fmt/format.h>
#include <png.h>
#include <unistd.h>

#include <filesystem>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <vector>

namespace pb::test {
namespace {

// Appends a quad (a, b, c, d counter-clockwise seen from the front) as two triangles, cut into n x n cells.
struct ObjWriter {
  std::string text;
  int vertices = 0;
  void Quad(const float a[3], const float b[3], const float d[3], int n) {  // corners a, a+(b-a), a+(d-a)
    const int first = vertices + 1;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const float s = float(i) / float(n), t = float(j) / float(n);
        text += fmt::format("v {} {} {}\n", a[0] + s * (b[0] - a[0]) + t * (d[0] - a[0]),
                            a[1] + s * (b[1] - a[1]) + t * (d[1] - a[1]), a[2] + s * (b[2] - a[2]) + t * (d[2] - a[2]));
        ++vertices;
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int v00 = first + j * (n + 1) + i, v10 = v00 + 1, v01 = v00 + n + 1, v11 = v01 + 1;
        text += fmt::format("f {} {} {}\nf {} {} {}\n", v00, v10, v11, v00, v11, v01);
      }
  }
};

struct Mesh {
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<int, 3>> f;  // 0-based
};

Mesh Icosphere(int detail) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  Mesh m;
  m.v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  m.f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
         {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
         {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int d = 0; d < detail; ++d) {
    std::map<std::pair<int, int>, int> midpoint;
    const auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto [it, isNew] = midpoint.emplace(key, int(m.v.size()));
      if (isNew) m.v.push_back({(m.v[a][0] + m.v[b][0]) / 2, (m.v[a][1] + m.v[b][1]) / 2, (m.v[a][2] + m.v[b][2]) / 2});
      return it->second;
    };
    std::vector<std::array<int, 3>> faces;
    for (const auto& f : m.f) {
      const int a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      faces.insert(faces.end(), {{f[0], a, c}, {f[1], b, a}, {f[2], c, b}, {a, b, c}});
    }
    m.f = std::move(faces);
  }
  for (auto& p : m.v) {
    const double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    p = {p[0] / l, p[1] / l, p[2] / l};
  }
  return m;  // unit radius, counter-clockwise seen from outside
}

Mesh Cylinder(int segments, double radius, double height) {
  Mesh m;
  const int rings = std::max(2, segments / 4);
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const double a = 2 * M_PI * i / segments;
      m.v.push_back({radius * std::cos(a), -height / 2 + height * j / rings, radius * std::sin(a)});
    }
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const int a = j * segments + i, b = j * segments + (i + 1) % segments, c = a + segments, d = b + segments;
      m.f.push_back({a, c, b});  // counter-clockwise seen from outside
      m.f.push_back({b, c, d});
    }
  for (int cap = 0; cap < 2; ++cap) {
    const int centre = int(m.v.size()), ring = cap == 0 ? 0 : rings * segments;
    m.v.push_back({0, cap == 0 ? -height / 2 : height / 2, 0});
    for (int i = 0; i < segments; ++i) {
      const int a = ring + i, b = ring + (i + 1) % segments;
      m.f.push_back(cap == 0 ? std::array<int, 3>{centre, a, b} : std::array<int, 3>{centre, b, a});
    }
  }
  return m;
}

void AppendMesh(std::string& obj, int& vertexCount, const Mesh& m, double scale, bool inward) {
  for (const auto& p : m.v) obj += fmt::format("v {} {} {}\n", p[0] * scale, p[1] * scale, p[2] * scale);
  for (const auto& f : m.f)
    obj += inward ? fmt::format("f {} {} {}\n", vertexCount + f[0] + 1, vertexCount + f[2] + 1, vertexCount + f[1] + 1)
                  : fmt::format("f {} {} {}\n", vertexCount + f[0] + 1, vertexCount + f[1] + 1, vertexCount + f[2] + 1);
  vertexCount += int(m.v.size());
}

}  // namespace

std::string WriteCurvedEnclosure(const std::string& directory, CurvedShape shape, int detail, float albedo,
                                 float lightRadius, float radiance) {
  WriteText(directory + "/curved.mtl", fmt::format("newmtl wall\nKd {0} {0} {0}\nnewmtl light\nKd 0 0 0\n"
                                                   "Ke {1} {1} {1}\n", albedo, radiance));
  Mesh receiver = shape == CurvedShape::kCylinder ? Cylinder(16 << detail, 0.6, 1.6) : Icosphere(detail);
  if (shape == CurvedShape::kBlob)
    for (auto& p : receiver.v) {
      const double theta = std::acos(std::clamp(p[1], -1.0, 1.0)), phi = std::atan2(p[2], p[0]);
      const double r = 1 + 0.25 * std::sin(2 * theta) * std::cos(3 * phi) + 0.1 * std::cos(5 * theta);
      p = {p[0] * r, p[1] * r, p[2] * r};
    }
  std::string obj = "mtllib curved.mtl\no receiver\nusemtl wall\n";
  int count = 0;
  AppendMesh(obj, count, receiver, 1.0, true);
  obj += "o light\nusemtl light\n";
  AppendMesh(obj, count, Icosphere(1), lightRadius, false);
  WriteText(directory + "/curved.obj", obj);
  return directory + "/curved.obj";
}

void WritePngRgb8(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = png_uint_32(width);
  image.height = png_uint_32(height);
  image.format = PNG_FORMAT_RGB;
  png_image_write_to_file(&image, path.c_str(), 0, rgb.data(), 0, nullptr);
}

std::string TempDirectory(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("photonbake-test-{}-{}", getpid(), name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

void WriteText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string AddTexture(const std::string& mtlPath) {
  std::ofstream(mtlPath, std::ios::app) << "\nnewmtl textured\nKd 1 1 1\nmap_Kd tex.png\n";
  const std::string png = std::filesystem::path(mtlPath).parent_path() / "tex.png";
  WritePngRgb8(png, 2, 2, std::vector<unsigned char>(12, 128));
  return png;
}

std::string WriteDiscPolygon(const std::string& dir, int corners) {
  std::string obj = "mtllib d.mtl\n";
  for (int i = 0; i < corners; ++i) {
    const double a = 2 * M_PI * i / corners;
    obj += fmt::format("v {:.9f} 0 {:.9f}\n", std::cos(a), std::sin(a));
  }
  obj += "usemtl floor\nf";
  for (int i = corners; i >= 1; --i) obj += fmt::format(" {}", i);  // counter-clockwise seen from above
  obj += "\nv -0.2 1 -0.2\nv 0.2 1 -0.2\nv 0.2 1 0.2\nv -0.2 1 0.2\nusemtl lamp\n";
  obj += fmt::format("f {} {} {} {}\n", corners + 1, corners + 2, corners + 3, corners + 4);
  WriteText(dir + "/d.mtl", "newmtl floor\nKd 0 0 0\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n");
  WriteText(dir + "/d.obj", obj);
  return dir + "/d.obj";
}

std::string WriteSquareLightOverFloor(const std::string& directory, float lightSide, float radiance, float height,
                                      float floorSide, int floorCells, float floorAlbedo) {
  WriteText(directory + "/scene.mtl", fmt::format("newmtl black\nKd {1} {1} {1}\nnewmtl light\nKd 0 0 0\nKe {0} {0} {0}\n",
                                                  radiance, floorAlbedo));
  ObjWriter obj;
  obj.text = "mtllib scene.mtl\nusemtl black\n";
  const float f = floorSide / 2, l = lightSide / 2;
  // Floor faces +y: corners (-f,0,f) -> (f,0,f) -> (-f,0,-f) is counter-clockwise seen from above.
  const float fa[3] = {-f, 0, f}, fb[3] = {f, 0, f}, fd[3] = {-f, 0, -f};
  obj.Quad(fa, fb, fd, floorCells);
  obj.text += "usemtl light\n";
  // Light faces -y: counter-clockwise seen from below.
  const float la[3] = {-l, height, -l}, lb[3] = {l, height, -l}, ld[3] = {-l, height, l};
  obj.Quad(la, lb, ld, 1);
  WriteText(directory + "/scene.obj", obj.text);
  return directory + "/scene.obj";
}

double LampGridRadiance(int i, int j) { return std::pow(10.0, 3.0 * double((i * 7 + j * 13) % 20) / 19.0); }

std::vector<std::array<double, 3>> LampGridSquare(int side, float pitch, float lampSide, float height, int i, int j) {
  const double x = (i - 0.5 * (side - 1)) * pitch - 0.5 * lampSide, z = (j - 0.5 * (side - 1)) * pitch - 0.5 * lampSide;
  // Counter-clockwise seen from below: facing down.
  return {{x, height, z}, {x + lampSide, height, z}, {x + lampSide, height, z + lampSide}, {x, height, z + lampSide}};
}

std::string WriteLampGrid(const std::string& directory, int side, float pitch, float lampSide, float height,
                          float floorSide) {
  std::string mtl = "newmtl black\nKd 0 0 0\n";
  for (int level = 0; level < 20; ++level)
    mtl += fmt::format("newmtl lamp_{0}\nKd 0 0 0\nKe {1} {1} {1}\n", level, std::pow(10.0, 3.0 * level / 19.0));
  WriteText(directory + "/lamps.mtl", mtl);
  const float f = floorSide / 2;
  std::string obj = fmt::format("mtllib lamps.mtl\nusemtl black\nv {0} 0 {0}\nv {1} 0 {0}\nv {1} 0 {1}\nv {0} 0 {1}\n"
                                "f 1 4 3 2\n", -f, f);
  int vertex = 5;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      obj += fmt::format("usemtl lamp_{}\n", (i * 7 + j * 13) % 20);
      for (const auto& c : LampGridSquare(side, pitch, lampSide, height, i, j))
        obj += fmt::format("v {} {} {}\n", c[0], c[1], c[2]);
      obj += fmt::format("f {} {} {} {}\n", vertex, vertex + 1, vertex + 2, vertex + 3);
      vertex += 4;
    }
  WriteText(directory + "/lamps.obj", obj);
  return directory + "/lamps.obj";
}

std::string WriteShadowScene(const std::string& directory, float albedo, float lightSide, float radiance,
                             float occluderSide, int floorCells) {
  WriteText(directory + "/shadow.mtl", fmt::format("newmtl floor\nKd {0} {0} {0}\nnewmtl black\nKd 0 0 0\n"
                                                   "newmtl light\nKd 0 0 0\nKe {1} {1} {1}\n", albedo, radiance));
  ObjWriter obj;
  obj.text = "mtllib shadow.mtl\nusemtl floor\n";
  const float fa[3] = {-1, 0, 1}, fb[3] = {1, 0, 1}, fd[3] = {-1, 0, -1};  // faces +y
  obj.Quad(fa, fb, fd, floorCells);
  if (occluderSide > 0) obj.text += "usemtl black\n";
  const float o = occluderSide / 2, oa[3] = {-o, 0.5f, o}, ob[3] = {o, 0.5f, o}, od[3] = {-o, 0.5f, -o};
  if (occluderSide > 0) obj.Quad(oa, ob, od, 1);
  obj.text += "usemtl light\n";
  const float l = lightSide / 2, la[3] = {-l, 1, -l}, lb[3] = {l, 1, -l}, ld[3] = {-l, 1, l};  // faces -y
  obj.Quad(la, lb, ld, 1);
  WriteText(directory + "/shadow.obj", obj.text);
  return directory + "/shadow.obj";
}

std::string WriteFloorWithLamps(const std::string& directory, float albedo, float radiance,
                                const std::vector<TestLamp>& lamps) {
  WriteText(directory + "/lamps.mtl", fmt::format("newmtl floor\nKd {0} {0} {0}\nnewmtl lamp\nKd 0 0 0\n"
                                                  "Ke {1} {1} {1}\n", albedo, radiance));
  ObjWriter obj;
  obj.text = "mtllib lamps.mtl\nusemtl floor\n";
  const float fa[3] = {-2, 0, 2}, fb[3] = {2, 0, 2}, fd[3] = {-2, 0, -2};  // counter-clockwise from above
  obj.Quad(fa, fb, fd, 1);
  obj.text += "usemtl lamp\n";
  for (const TestLamp& l : lamps) {
    const float a[3] = {l.x0, l.y, l.z0}, b[3] = {l.x1, l.y, l.z0}, d[3] = {l.x0, l.y, l.z1};  // faces -y
    if (l.facingDown) {
      obj.Quad(a, b, d, 1);
    } else {
      obj.Quad(a, d, b, 1);
    }
  }
  WriteText(directory + "/lamps.obj", obj.text);
  return directory + "/lamps.obj";
}

std::string WriteClosedBox(const std::string& directory, float side, float albedo, float lightSide, float radiance,
                           float glassRadius, float ior, float lightGap) {
  WriteText(directory + "/box.mtl", fmt::format("newmtl wall\nKd {0} {0} {0}\nnewmtl light\nKd {0} {0} {0}\n"
                                                "Ke {1} {1} {1}\nnewmtl glass\nNi {2}\nTf 1 1 1\nillum 7\n",
                                                albedo, radiance, ior));
  ObjWriter obj;
  obj.text = "mtllib box.mtl\nusemtl wall\n";
  const float s = side;
  // Six walls of the cube [0,s]^3, each counter-clockwise seen from inside.
  const float walls[6][3][3] = {
      {{0, 0, 0}, {0, 0, s}, {s, 0, 0}},  // floor, faces +y
      {{0, s, 0}, {s, s, 0}, {0, s, s}},  // ceiling, faces -y
      {{0, 0, 0}, {s, 0, 0}, {0, s, 0}},  // z = 0, faces +z
      {{0, 0, s}, {0, s, s}, {s, 0, s}},  // z = s, faces -z
      {{0, 0, 0}, {0, s, 0}, {0, 0, s}},  // x = 0, faces +x
      {{s, 0, 0}, {s, 0, s}, {s, s, 0}},  // x = s, faces -x
  };
  for (const auto& w : walls) obj.Quad(w[0], w[1], w[2], 4);
  obj.text += "usemtl light\n";
  const float c = s / 2, l = lightSide / 2, y = s * (1 - lightGap);
  const float la[3] = {c - l, y, c - l}, lb[3] = {c + l, y, c - l}, ld[3] = {c - l, y, c + l};
  obj.Quad(la, lb, ld, 1);
  if (glassRadius > 0) {
    obj.text += "o glass\nusemtl glass\n";
    Mesh sphere = Icosphere(3);
    for (auto& p : sphere.v)
      p = {c + glassRadius * p[0], 0.01 * s + glassRadius * (1 + p[1]), c + glassRadius * p[2]};
    AppendMesh(obj.text, obj.vertices, sphere, 1.0, false);
  }
  WriteText(directory + "/box.obj", obj.text);
  return directory + "/box.obj";
}

std::string WriteGapScene(const std::string& directory) {
  WriteText(directory + "/gap.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 10 10 10\n");
  ObjWriter obj;
  obj.text = "mtllib gap.mtl\nusemtl grey\n";
  // Quads {a, b, d, cuts}, counter-clockwise seen from the side they face.
  const auto quad = [&](std::array<float, 3> a, std::array<float, 3> b, std::array<float, 3> d, int n) {
    obj.Quad(a.data(), b.data(), d.data(), n);
  };
  quad({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 20);  // the room, facing in
  quad({0, 1, 0}, {1, 1, 0}, {0, 1, 1}, 4);
  quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 4);
  quad({0, 0, 1}, {0, 1, 1}, {1, 0, 1}, 4);
  quad({0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 4);
  quad({1, 0, 0}, {1, 0, 1}, {1, 1, 0}, 4);
  const float x0 = 0.3f, x1 = 0.7f, y0 = 0.003f, y1 = 0.013f, z0 = 0.3f, z1 = 0.7f;  // the slab, facing out
  quad({x0, y0, z0}, {x1, y0, z0}, {x0, y0, z1}, 4);
  quad({x0, y1, z0}, {x0, y1, z1}, {x1, y1, z0}, 4);
  quad({x0, y0, z0}, {x0, y1, z0}, {x1, y0, z0}, 1);
  quad({x0, y0, z1}, {x1, y0, z1}, {x0, y1, z1}, 1);
  quad({x0, y0, z0}, {x0, y0, z1}, {x0, y1, z0}, 1);
  quad({x1, y0, z0}, {x1, y1, z0}, {x1, y0, z1}, 1);
  obj.text += "usemtl light\n";
  quad({0.4f, 0.99f, 0.4f}, {0.6f, 0.99f, 0.4f}, {0.4f, 0.99f, 0.6f}, 1);
  WriteText(directory + "/gap.obj", obj.text);
  return directory + "/gap.obj";
}

std::string WriteTwoLamps(const std::string& directory) {
  WriteText(directory + "/two.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl a\nKe 1 1 1\nnewmtl b\nKe 3 3 3\n");
  WriteText(directory + "/two.obj",
            "mtllib two.mtl\nv -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nusemtl floor\nf 1 4 3 2\n"
            "v 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\nusemtl a\nf 5 6 7 8\n"
            "v 2 1 0\nv 3 1 0\nv 3 1 1\nv 2 1 1\nusemtl b\nf 9 10 11 12\n");
  return directory + "/two.obj";
}

}  // namespace pb::test
