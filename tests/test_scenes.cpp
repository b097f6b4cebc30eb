#include "tests/test_scenes.h"

#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

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

}  // namespace

std::string TempDirectory(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("photonbake-test-{}-{}", getpid(), name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

void WriteText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string WriteSquareLightOverFloor(const std::string& directory, float lightSide, float radiance, float height,
                                      float floorSide, int floorCells) {
  WriteText(directory + "/scene.mtl",
            fmt::format("newmtl black\nKd 0 0 0\nnewmtl light\nKd 0 0 0\nKe {0} {0} {0}\n", radiance));
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

std::string WriteClosedBox(const std::string& directory, float side, float albedo, float lightSide, float radiance) {
  WriteText(directory + "/box.mtl", fmt::format("newmtl wall\nKd {0} {0} {0}\nnewmtl light\nKd {0} {0} {0}\n"
                                                "Ke {1} {1} {1}\n",
                                                albedo, radiance));
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
  const float c = s / 2, l = lightSide / 2, y = s * 0.999f;
  const float la[3] = {c - l, y, c - l}, lb[3] = {c + l, y, c - l}, ld[3] = {c - l, y, c + l};
  obj.Quad(la, lb, ld, 1);
  WriteText(directory + "/box.obj", obj.text);
  return directory + "/box.obj";
}

}  // namespace pb::test
