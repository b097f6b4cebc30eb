// The OBJ/MTL loader: what it reads, and how it refuses bad input (message names file:line).
#include "mesh/obj_loader.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <sys/stat.h>

#include "mesh/errors.h"
#include "mesh/lscm.h"
#include "mesh/surfaces.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

const char* kMtl = "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 2 3 4\n";

// Writes scene.obj (with the given body after "mtllib scene.mtl") and scene.mtl into a fresh directory.
std::string WriteScene(const std::string& name, const std::string& body, const std::string& mtl = kMtl) {
  const std::string dir = test::TempDirectory(name);
  test::WriteText(dir + "/scene.mtl", mtl);
  test::WriteText(dir + "/scene.obj", "mtllib scene.mtl\n" + body);
  return dir + "/scene.obj";
}

// Expects LoadObj to throw an InputError at `line` whose message contains `fragment`.
void ExpectError(const std::string& path, int line, const std::string& fragment) {
  try {
    LoadObj(path);
    ADD_FAILURE() << "no error for " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(e.file() + (line ? ":" + std::to_string(line) : "")), std::string::npos);
  }
}

const std::string kQuad = "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n";

TEST(ObjLoader, ReadsPolygonsMaterialsAndScale) {
  const std::string path = WriteScene("read", "o floor\n" + kQuad + "usemtl grey\nf 1 4 3 2\no lamp\nusemtl lamp\n"
                                              "v 0 2 0\nv 1 2 0\nv 0 2 1\nf -3/1/1 -2//1 -1\n");
  const LoadedScene loaded = LoadObj(path, {0.5f});
  const Scene& s = loaded.scene;
  ASSERT_EQ(s.triangles.size(), 3u);  // quad fan-triangulated + one triangle
  EXPECT_EQ(s.positions.size(), 7u);
  EXPECT_FLOAT_EQ(s.positions[2].x, 0.5f);  // scale applied
  EXPECT_FLOAT_EQ(s.Area(0) + s.Area(1), 0.25f);
  EXPECT_GT(s.FrontNormal(0).y, 0.99f);  // 1 4 3 2 is counter-clockwise seen from +y
  EXPECT_EQ(s.MaterialOf(2).name, "lamp");
  EXPECT_FLOAT_EQ(s.MaterialOf(2).emission.b, 4.0f);
  EXPECT_EQ(s.objectNames[s.triangles[2].object], "lamp");
  EXPECT_EQ(s.triangles[2].v[0], 4u);  // negative indices are relative to the end
}

// Progress (mesh/work_progress.h): the loader tells every byte of the file once, of the file's size; BuildSurfaces
// two passes over the triangles, the first report before any work (so that a shown stage's clock starts there).
TEST(ObjLoader, ReportsItsProgressAndTheSurfacesTheirs) {
  const std::string path = PB_SOURCE_DIR "/data/office_books/office_books.obj";
  uint64_t bytes = 0, total = 0;
  const LoadedScene loaded = LoadObj(path, {.progress = [&](uint64_t done, uint64_t all) { bytes += done, total = all; }});
  EXPECT_EQ(bytes, total);
  EXPECT_GT(total, 0u);
  EXPECT_NEAR(double(total), double(std::filesystem::file_size(path)), 16.0);  // a BOM or a last newline apart
  std::vector<std::pair<uint64_t, uint64_t>> reports;
  BuildSurfaces(loaded.scene, {}, [&](uint64_t done, uint64_t all) { reports.emplace_back(done, all); });
  ASSERT_GE(reports.size(), 2u);
  EXPECT_EQ(reports.front().first, 0u);
  uint64_t passes = 0;
  for (const auto& [done, all] : reports) {
    passes += done;
    EXPECT_EQ(all, 2 * loaded.scene.triangles.size());
  }
  EXPECT_EQ(passes, 2 * loaded.scene.triangles.size());
}

TEST(ObjLoader, SkipsAndCountsZeroAreaTriangles) {
  const std::string path =
      WriteScene("degenerate", kQuad + "v 2 0 0\nusemtl grey\nf 1 2 3\nf 1 2 5\nf 1 1 3\nf 1 3 4\n");
  const LoadedScene loaded = LoadObj(path);
  EXPECT_EQ(loaded.scene.triangles.size(), 2u);
  EXPECT_EQ(loaded.scene.degenerateTrianglesSkipped, 2u);
  ASSERT_EQ(loaded.warnings.size(), 1u);  // one line per kind of warning, counted
  EXPECT_NE(loaded.warnings[0].find(":9: warning: zero-area triangle skipped (2 in all)"), std::string::npos)
      << loaded.warnings[0];
}

// Area in double is not enough: the rest of the bake computes normals in float. A triangle of 1e-30 m, or of 1 um
// a kilometre from the origin (its corners meet in float), has no float normal; it is dropped as zero-area (each
// hung the surface stage before, splitting one triangle forever). A scene wider than float areas allow is refused.
TEST(ObjLoader, TrianglesWithoutAFloatNormalAreZeroAreaAndHugeScenesAreRefused) {
  const std::string far = WriteScene("no-float-normal", kQuad + "v 1000 0 0\nv 1000.000001 0 0\nv 1000 0 0.000001\n"
                                     "v 0 1e-30 0\nv 1e-30 1e-30 0\nv 0 1e-30 1e-30\nusemtl grey\nf 1 3 2\nf 5 7 6\nf 8 10 9\n");
  const LoadedScene loaded = LoadObj(far);
  EXPECT_EQ(loaded.scene.triangles.size(), 1u);
  EXPECT_EQ(loaded.scene.degenerateTrianglesSkipped, 2u);
  for (uint32_t t = 0; t < loaded.scene.triangles.size(); ++t) EXPECT_TRUE(std::isfinite(loaded.scene.FrontNormal(t).y));
  ExpectError(WriteScene("only-tiny", "v 0 0 0\nv 1e-30 0 0\nv 0 0 1e-30\nusemtl grey\nf 1 2 3\n"), 0,
              "scene has no faces to bake: every face has zero area");
  ExpectError(WriteScene("huge", "v 1e38 0 0\nv -1e38 0 0\nv 0 0 1e38\nusemtl grey\nf 1 2 3\n"), 0,
              "the scene is 2e+38 m across, more than the 1e+09 m within which its areas stay finite in float");
}

TEST(ObjLoader, SkipsRepeatedTrianglesButKeepsBackToBackCopies) {
  // Face 2 repeats face 1 from another corner and through duplicated vertices; face 3 is face 1 turned over.
  const std::string path = WriteScene("repeat", kQuad + "v 0 0 0\nv 1 0 0\nusemtl grey\nf 1 2 3\nf 3 5 6\nf 1 3 2\n");
  const LoadedScene loaded = LoadObj(path);
  EXPECT_EQ(loaded.scene.triangles.size(), 2u);
  EXPECT_EQ(loaded.scene.duplicateTrianglesSkipped, 1u);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find(":10: warning: triangle repeats the one at line 9"), std::string::npos)
      << loaded.warnings[0];
}

TEST(ObjLoader, KeepsSliversThatHaveArea) {
  const std::string path = WriteScene("sliver", "v 0 0 0\nv 1 0 0\nv 0.5 0 1e-6\nusemtl grey\nf 1 3 2\n");
  EXPECT_EQ(LoadObj(path).scene.triangles.size(), 1u);
}

TEST(ObjLoader, RejectsBadInputNamingFileAndLine) {
  ExpectError("/nonexistent/scene.obj", 0, "cannot open");
  ExpectError(WriteScene("malformed", "v 1 2 abc\n"), 2, "malformed number 'abc'");
  ExpectError(WriteScene("nan", "v 1 nan 0\n"), 2, "non-finite");
  ExpectError(WriteScene("inf", "v 1 2 3\nv inf 0 0\n"), 3, "non-finite");
  ExpectError(WriteScene("short", "v 1 2\n"), 2, "takes 3 to 7 values");
  ExpectError(WriteScene("range", kQuad + "usemtl grey\nf 1 2 9\n"), 7, "vertex index 9 is out of range (4 vertices");
  const std::string textured = WriteScene("texcoord-range", kQuad + "vt 0 0\nusemtl textured\nf 1/1 2/-2 3/1\n");
  test::AddTexture(textured.substr(0, textured.size() - 3) + "mtl");
  ExpectError(textured, 8, "texture coordinate index -2 is out of range (1 texture coordinate so far)");
  ExpectError(WriteScene("zero-index", kQuad + "usemtl grey\nf 0 1 2\n"), 7, "malformed face index");
  ExpectError(WriteScene("bad-normal", kQuad + "vn 0 1 0\nusemtl grey\nf 1//x 2//1 3//1\n"), 8, "malformed face index");
  ExpectError(WriteScene("empty", kQuad), 0, "no faces");
  ExpectError(WriteScene("short-faces", kQuad + "usemtl grey\nf 1\nf 1 2\n"), 7,
              "no faces to bake: its faces have fewer than 3 corners");
  ExpectError(WriteScene("lines", kQuad + "l 1 2\np 3\n"), 6, "no faces to bake: it has only lines and points");
}

TEST(ObjLoader, RejectsBadMaterialsNamingTheMtlLine) {
  const auto mtlPath = [](const std::string& objPath) { return objPath.substr(0, objPath.size() - 3) + "mtl"; };
  const std::string kd = WriteScene("kd", kQuad, "newmtl hot\nKd 1.5 0 0\n");
  try {
    LoadObj(kd);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), mtlPath(kd));
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("Kd must lie in [0, 1]"), std::string::npos) << e.what();
  }
  const std::string ke = WriteScene("ke", kQuad, "newmtl neg\nKe -1 0 0\n");
  EXPECT_THROW(LoadObj(ke), InputError);
  const std::string junk = WriteScene("junk", kQuad, "newmtl a\nKd 0.5 x 0.5\n");
  EXPECT_THROW(LoadObj(junk), InputError);
  // Found by fuzzing: an illum beyond int's range was cast to int (undefined behaviour) before it was checked.
  for (const std::string illum : {"34444444444444444444444444444444444", "-1", "2.5", "11"}) {
    const std::string path = WriteScene("illum", kQuad, "newmtl a\nKd 0.5 0.5 0.5\nillum " + illum + "\n");
    try {
      LoadObj(path);
      ADD_FAILURE() << illum;
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), 3) << e.what();
      EXPECT_NE(std::string(e.what()).find("illum takes a whole number 0-10"), std::string::npos) << e.what();
    }
  }
}

// Files as other programs write them, and files that are not files (issue 16): a byte order mark and CR-only or
// CRLF line ends are read; a NUL byte, a folder, a FIFO and /dev/zero are refused at once with what they are.
TEST(ObjLoader, ReadsBomAndAnyLineEndsAndRefusesWhatIsNotATextFile) {
  const std::string body = "usemtl grey\n" + kQuad + "f 1 4 3 2\n";
  for (const auto& [name, ends] : {std::pair{"cr", "\r"}, std::pair{"crlf", "\r\n"}}) {
    std::string text = "\xEF\xBB\xBFmtllib scene.mtl\n" + body;
    std::string converted;
    for (char c : text) converted += c == '\n' ? std::string(ends) : std::string(1, c);
    const std::string path = WriteScene(std::string("line-ends-") + name, "");
    test::WriteText(path, converted);
    const LoadedScene loaded = LoadObj(path);
    EXPECT_EQ(loaded.scene.triangles.size(), 2u) << name;
  }
  const std::string nul = WriteScene("nul", std::string("v 0 0 0\nv 1 0\0 0\n", 17));
  ExpectError(nul, 3, "a NUL byte: this is not a text file");
  const std::string dir = test::TempDirectory("not-files");
  ExpectError(dir, 0, "cannot open scene file: it is a folder");
  ExpectError("/dev/zero", 0, "cannot open scene file: not a regular file");
  const std::string fifo = dir + "/fifo.obj";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  ExpectError(fifo, 0, "not a regular file");  // would hang forever if opened
  test::WriteText(dir + "/zero.obj", "mtllib /dev/zero\n" + body);
  ExpectError(dir + "/zero.obj", 1, "material library: not a regular file");
}

TEST(ObjLoader, MaterialClassFollowsIllum) {
  const std::string mtl =
      "newmtl matte\nKd 0.5 0.5 0.5\nKs 0.9 0.9 0.9\nillum 2\n"         // Phong highlight: still diffuse
      "newmtl mirror\nKd 0.1 0.1 0.1\nKs 0.8 0.7 0.6\nillum 3\n"
      "newmtl glass\nKd 0.2 0.2 0.2\nNi 1.33\nTf 0.9 1 1\nillum 7\n"
      "newmtl frosted\nd 0.25\nillum 4\n"
      "newmtl plain_mirror\nillum 5\n";
  const LoadedScene loaded = LoadObj(WriteScene("classes", kQuad + "usemtl matte\nf 1 2 3\n", mtl));
  const std::vector<Material>& m = loaded.scene.materials;
  ASSERT_EQ(m.size(), 5u);
  EXPECT_EQ(m[0].kind, MaterialClass::kDiffuse);
  EXPECT_TRUE(m[0].specular.IsBlack());
  EXPECT_EQ(m[1].kind, MaterialClass::kMirror);
  EXPECT_FLOAT_EQ(m[1].specular.b, 0.6f);
  EXPECT_FLOAT_EQ(m[1].albedo.r, 0.1f);
  EXPECT_EQ(m[2].kind, MaterialClass::kGlass);
  EXPECT_FLOAT_EQ(m[2].ior, 1.33f);
  EXPECT_FLOAT_EQ(m[2].transmittance.r, 0.9f);
  EXPECT_TRUE(m[2].albedo.IsBlack()) << "glass does not use Kd";
  EXPECT_FLOAT_EQ(m[3].transmittance.g, 0.75f) << "without Tf, glass transmits 1 - d";
  EXPECT_FLOAT_EQ(m[3].ior, 1.5f);
  EXPECT_FLOAT_EQ(m[4].specular.g, 0.99f) << "a mirror without Ks reflects everything, capped at 0.99";
  ASSERT_EQ(loaded.warnings.size(), 2u);
  EXPECT_NE(loaded.warnings[1].find("material 'plain_mirror': reflectance 1.000 capped at 0.99"), std::string::npos)
      << loaded.warnings[1];
  EXPECT_NE(loaded.warnings[0].find("scene.mtl:9: warning: material 'glass': Kd is not used"), std::string::npos)
      << loaded.warnings[0];
}

TEST(ObjLoader, RejectsSpecularMaterialsThatCreateEnergy) {
  const auto expect = [](const std::string& name, const std::string& mtl, const std::string& fragment,
                         int line = 3) {
    try {
      LoadObj(WriteScene(name, kQuad, "newmtl ok\nKd 0.5 0.5 0.5\n" + mtl));
      ADD_FAILURE() << mtl;
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect("ks", "newmtl m\nKd 0.6 0.6 0.6\nKs 1.5 0.5 0.5\nillum 3\n", "Ks in [0, 1]");
  expect("ni", "newmtl g\nNi 0\nillum 4\n", "Ni in (0, 10]");
  expect("tf", "newmtl g\nTf 1.2 1 1\nillum 6\n", "Tf and d in [0, 1]");
  expect("illum", "newmtl g\nillum 2.5\n", "whole number", 4);
}

TEST(Surfaces, GroupsConnectedCoplanarTrianglesOfOneMaterial) {
  // Two quads sharing an edge at a right angle, plus a coplanar quad of another material beside the first.
  const std::string path = WriteScene("surfaces", "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 0 1 0\nv 1 1 0\n"
                                                  "v 2 0 0\nv 2 0 1\nusemtl grey\nf 1 4 3 2\nf 1 2 6 5\n"
                                                  "usemtl lamp\nf 2 3 8 7\n");
  const Scene scene = LoadObj(path).scene;
  const SurfaceSet set = BuildSurfaces(scene);
  ASSERT_EQ(set.surfaces.size(), 3u);
  EXPECT_EQ(set.surfaceOfTriangle[0], set.surfaceOfTriangle[1]);
  EXPECT_NE(set.surfaceOfTriangle[0], set.surfaceOfTriangle[2]);
  EXPECT_NE(set.surfaceOfTriangle[0], set.surfaceOfTriangle[4]);
  // Charts are isometric: (u,v) distances equal 3-D distances on the plane.
  const SurfaceChart& chart = set.surfaces[0].chart;
  const Point2 a = chart.ToUv({0, 0, 0}), b = chart.ToUv({1, 0, 1});
  EXPECT_NEAR(LengthSquared(a - b), 2.0f, 1e-6f);
  EXPECT_NEAR(set.surfaces[0].area, 1.0, 1e-6);
}

// A flat polygon of 40,000 corners, fan-triangulated, has slivers whose float corners leave their normals
// meaningless (some flip over). They must join the floor's one planar surface rather than split it into
// zero-area surfaces, or make it "curved" and send slivers to CGAL's LSCM, which crashed on them.
TEST(Surfaces, SliversOfAHugePolygonJoinItsPlanarSurface) {
  const Scene scene = LoadObj(test::WriteDiscPolygon(test::TempDirectory("surfaces-disc"), 40000)).scene;
  const SurfaceSet set = BuildSurfaces(scene);
  ASSERT_EQ(set.surfaces.size(), 2u);  // the floor and the lamp
  EXPECT_EQ(set.CurvedCount(), 0u);
  EXPECT_NEAR(set.surfaces[0].area, 20000 * std::sin(2 * M_PI / 40000), 1e-4);
}

// A closed box 30 micrometres wide 100 m from the origin, beside a 200 m floor (as the conference room's tiny
// boxes at --scale 0.003): float rounding there can turn each of its triangles' normals by degrees, so none votes
// on planarity, and their area vectors sum to nothing. It must not become a "planar" surface with a NaN normal: every chart's normal is finite.
TEST(Surfaces, ATinyClosedBoxOfSliversHasNoNaNNormal) {
  const std::string dir = test::TempDirectory("surfaces-tiny-box");
  std::string obj = "mtllib b.mtl\nusemtl grey\n";
  for (int k = 0; k < 8; ++k)
    obj += fmt::format("v {} {} {}\n", 100 + 3e-5 * (k & 1), 100 + 3e-5 * ((k >> 1) & 1), 100 + 3e-5 * ((k >> 2) & 1));
  obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  obj += "usemtl floor\nv -100 0 -100\nv -100 0 100\nv 100 0 100\nv 100 0 -100\nf 9 10 11 12\n";
  test::WriteText(dir + "/b.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl floor\nKd 0.5 0.5 0.5\n");
  test::WriteText(dir + "/b.obj", obj);
  const Scene scene = LoadObj(dir + "/b.obj").scene;
  const SurfaceSet set = BuildSurfaces(scene);
  ASSERT_FALSE(set.surfaces.empty());
  for (const Surface& s : set.surfaces) {
    const Normal3 n = s.chart.frame.n;
    EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
  }
}

TEST(Surfaces, ConformalMapRefusesAPatchWithoutArea) {
  const std::vector<Point3> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  const std::vector<std::array<uint32_t, 3>> strip = {{0, 1, 2}, {1, 3, 2}};
  EXPECT_FALSE(ConformalMap(line, strip).has_value());
}

TEST(Surfaces, BundledBoxHasItsSeventeenSurfaces) {
  const Scene scene = LoadObj(PB_SOURCE_DIR "/data/box/box.obj").scene;
  const SurfaceSet set = BuildSurfaces(scene);
  // floor, ceiling, 3 walls, 2 blocks x (top + 4 sides), 2 lights; the twisted red wall stays one surface.
  EXPECT_EQ(set.surfaces.size(), 17u);
  double floorArea = 0;
  for (const Surface& s : set.surfaces)
    if (scene.objectNames[scene.triangles[s.triangles[0]].object] == "floor") floorArea = s.area;
  EXPECT_NEAR(floorArea, 0.5 * (0.5528 + 0.5496) * 0.5592, 1e-4);  // trapezoid from the published corners
}

}  // namespace
}  // namespace pb
