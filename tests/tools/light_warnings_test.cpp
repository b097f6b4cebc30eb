// What the bake warns about the light it found, as a user sees it on the command line (baker/diagnostics.h): surfaces
// lit only from behind, and surfaces whose vertices show far less light than their photons brought.
#include <gtest/gtest.h>

#include <string>

#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

using test::RunBake;

// A panel hung under a light with its faces wound the wrong way round (its front turned down to a black floor): the
// photons reach only its back, its front reads black, and the bake says so, naming it; wound the right way, it is
// lit and nothing is said.
TEST(LightWarnings, SurfacesLitOnlyFromBehindAreWarnedAbout) {
  const std::string dir = test::TempDirectory("back-lit");
  test::WriteText(dir + "/p.mtl", "newmtl black\nKd 0 0 0\nnewmtl wood\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 5 5 5\n");
  const auto bake = [&](bool wrong) {
    const std::string panel = wrong ? "f 5 6 7 8\n" : "f 8 7 6 5\n";  // counter-clockwise from below: front down
    test::WriteText(dir + "/p.obj", "mtllib p.mtl\nusemtl black\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nf 1 4 3 2\n"
                                    "usemtl wood\nv -0.25 0.5 -0.25\nv 0.25 0.5 -0.25\nv 0.25 0.5 0.25\nv -0.25 0.5 0.25\n" +
                                    panel + "usemtl light\nv -0.5 1 -0.5\nv 0.5 1 -0.5\nv 0.5 1 0.5\nv -0.5 1 0.5\n"
                                            "f 9 10 11 12\n");
    return RunBake(dir + "/p.obj -o " + dir + "/p.ply --photons 20000 --direct photons");  // first hits stored
  };
  const test::ToolRun wrong = bake(true);
  ASSERT_EQ(wrong.status, 0) << wrong.output;
  EXPECT_NE(wrong.output.find("p.obj: warning: 1 surface of 0.25 m^2 in all lit only from behind"), std::string::npos)
      << wrong.output;
  EXPECT_NE(wrong.output.find("('wood', 0.25 m^2,"), std::string::npos) << wrong.output;
  const test::ToolRun right = bake(false);
  ASSERT_EQ(right.status, 0) << right.output;
  EXPECT_EQ(right.output.find("lit only from behind"), std::string::npos) << right.output;
}

// A 4 x 4 m floor of two triangles under a light, its four corners each under a 0.6 m block: every vertex of the
// floor lies under a block, in the dark, and reads 0, while the photons light its middle. The bake says so, naming
// the floor; with the blocks moved off its corners (to its middle), its corners see the light and nothing is said;
// --refine, which adds vertices where the light is, mends it.
TEST(LightWarnings, SurfacesWhoseVerticesMissTheirLightAreWarnedAbout) {
  const std::string dir = test::TempDirectory("missed-light");
  test::WriteText(dir + "/f.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl block\nKd 0.7 0.7 0.7\nnewmtl light\nKd 0 0 0\nKe 20 20 20\n");
  // A closed 0.6 m block of six quads, facing out, its lower corner at (x, 0, z).
  const auto block = [](float x, float z, int& v) {
    std::string text;
    for (int k = 0; k < 8; ++k)
      text += "v " + std::to_string(x + 0.6f * float(k & 1)) + " " + std::to_string(0.6f * float((k >> 1) & 1)) + " " +
              std::to_string(z + 0.6f * float((k >> 2) & 1)) + "\n";
    const int faces[6][4] = {{2, 3, 1, 0}, {5, 7, 6, 4}, {1, 5, 4, 0}, {6, 7, 3, 2}, {4, 6, 2, 0}, {3, 7, 5, 1}};
    for (const auto& f : faces)
      text += "f " + std::to_string(v + f[0]) + " " + std::to_string(v + f[1]) + " " + std::to_string(v + f[2]) + " " +
              std::to_string(v + f[3]) + "\n";
    v += 8;
    return text;
  };
  const auto bake = [&](bool onCorners, const std::string& options) {
    std::string obj = "mtllib f.mtl\nusemtl floor\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nf 1 4 3 2\n"
                      "usemtl light\nv -0.5 2 -0.5\nv 0.5 2 -0.5\nv 0.5 2 0.5\nv -0.5 2 0.5\nf 5 6 7 8\nusemtl block\n";
    int v = 9;
    for (const auto& [x, z] : {std::pair{-2.1f, -2.1f}, {1.5f, -2.1f}, {1.5f, 1.5f}, {-2.1f, 1.5f}})
      obj += onCorners ? block(x, z, v) : block(0.3f * x, 0.3f * z, v);
    test::WriteText(dir + "/f.obj", obj);
    return RunBake(dir + "/f.obj -o " + dir + "/f.ply --photons 200000 --h 0.2 " + options);
  };
  const test::ToolRun corners = bake(true, "");
  ASSERT_EQ(corners.status, 0) << corners.output;
  EXPECT_EQ(corners.output.find("lit only from behind"), std::string::npos) << "the blocks face out: " << corners.output;
  EXPECT_NE(corners.output.find("f.obj: warning: 1 surface of 16 m^2 in all show less than a quarter of the light their photons "
                                "brought"), std::string::npos) << corners.output;
  EXPECT_NE(corners.output.find("('floor', 16 m^2: its vertices 0 W/m^2"), std::string::npos) << corners.output;
  const test::ToolRun middle = bake(false, "");
  ASSERT_EQ(middle.status, 0) << middle.output;
  EXPECT_EQ(middle.output.find("show less than a quarter of the light"), std::string::npos) << middle.output;
  const test::ToolRun refined = bake(true, "--refine");
  ASSERT_EQ(refined.status, 0) << refined.output;
  EXPECT_EQ(refined.output.find("show less than a quarter of the light"), std::string::npos) << refined.output;
}

}  // namespace
}  // namespace pb
