// OBJ and MTL files as other tools write them (issue 19): what the loader reads, what it ignores or defaults with
// one counted warning per kind, and the textures it finds and decodes.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>
#include <filesystem>

#include "mesh/errors.h"
#include "mesh/mtl_loader.h"
#include "mesh/obj_loader.h"
#include "mesh/text_lines.h"
#include "mesh/texture.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

const std::string kQuad = "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n";

// Writes dir/s.obj and (when given) dir/s.mtl; returns the OBJ's path.
std::string Write(const std::string& name, const std::string& obj, const std::string& mtl = "") {
  const std::string dir = test::TempDirectory(name);
  if (!mtl.empty()) test::WriteText(dir + "/s.mtl", mtl);
  test::WriteText(dir + "/s.obj", obj);
  return dir + "/s.obj";
}

// The one warning line that contains `fragment`; fails when there is none or more than one.
std::string WarningWith(const LoadedScene& loaded, const std::string& fragment) {
  std::string found;
  int count = 0;
  for (const std::string& w : loaded.warnings)
    if (w.find(fragment) != std::string::npos) found = w, ++count;
  EXPECT_EQ(count, 1) << "warnings with '" << fragment << "' among:\n" << [&] {
    std::string all;
    for (const std::string& w : loaded.warnings) all += w + "\n";
    return all;
  }();
  return found;
}

double TotalArea(const Scene& s) {
  double a = 0;
  for (uint32_t t = 0; t < s.triangles.size(); ++t) a += s.Area(t);
  return a;
}

TEST(ObjAsWritten, FacesWithoutAMaterialAreDefaultGrey) {
  const LoadedScene loaded = LoadObj(Write("no-usemtl", kQuad + "f 1 4 3 2\nf 1 2 3\nf 1 3 4\n"));  // the Stanford bunny
  ASSERT_EQ(loaded.scene.triangles.size(), 4u);
  const Material& m = loaded.scene.MaterialOf(0);
  EXPECT_EQ(m.kind, MaterialClass::kDiffuse);
  EXPECT_FLOAT_EQ(m.albedo.g, kDefaultAlbedo);
  EXPECT_NE(WarningWith(loaded, "before any 'usemtl'").find("s.obj:5: warning: faces before any 'usemtl' are grey"),
            std::string::npos);
}

TEST(ObjAsWritten, UnknownMaterialsAndMissingLibrariesFallBackToTheDefault) {
  const LoadedScene loaded = LoadObj(Write("fallback", "mtllib nothere.mtl\nmtllib s.mtl\n" + kQuad + "usemtl gold\nf 1 4 3 2\nusemtl red\nf 1 2 3\n"
                        "usemtl gold\nf 1 3 4\n",
            "newmtl red\nKd 0.5 0 0\n"));
  ASSERT_EQ(loaded.scene.triangles.size(), 4u);
  EXPECT_FLOAT_EQ(loaded.scene.MaterialOf(0).albedo.b, kDefaultAlbedo);
  EXPECT_FLOAT_EQ(loaded.scene.MaterialOf(2).albedo.r, 0.5f);
  EXPECT_EQ(loaded.scene.triangles[0].material, loaded.scene.triangles[3].material) << "one default material";
  EXPECT_NE(WarningWith(loaded, "'nothere.mtl' not found").find("s.obj:1: warning"), std::string::npos);
  EXPECT_NE(WarningWith(loaded, "material 'gold' is defined by no material library").find("(2 in all)"),
            std::string::npos);
}

TEST(ObjAsWritten, SeveralLibrariesOnOneLineAndEscapedSpaces) {
  const std::string dir = test::TempDirectory("mtllibs");
  test::WriteText(dir + "/a b.mtl", "newmtl A\nKd 0.1 0.1 0.1\n");
  test::WriteText(dir + "/c.mtl", "newmtl C\nKd 0.3 0.3 0.3\n");
  test::WriteText(dir + "/with space.mtl", "newmtl W\nKd 0.2 0.2 0.2\n");
  test::WriteText(dir + "/s.obj", "mtllib a\\ b.mtl missing.mtl c.mtl\nmtllib with space.mtl\n" + kQuad +
                                      "usemtl A\nf 1 2 3\nusemtl C\nf 1 3 4\nusemtl W\nf 4 3 2\n");
  const LoadedScene loaded = LoadObj(dir + "/s.obj");
  ASSERT_EQ(loaded.scene.triangles.size(), 3u);
  EXPECT_FLOAT_EQ(loaded.scene.MaterialOf(0).albedo.r, 0.1f);
  EXPECT_FLOAT_EQ(loaded.scene.MaterialOf(1).albedo.r, 0.3f);
  EXPECT_FLOAT_EQ(loaded.scene.MaterialOf(2).albedo.r, 0.2f);
  WarningWith(loaded, "'missing.mtl' not found");
}

TEST(ObjAsWritten, Utf16ContinuationsAndIgnoredStatements) {
  const std::string text = "mtllib s.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nvw 1 0 0.5\nusemtl m\nf 1 \\\n 4 3 2\n"
                           "cstype bspline\ndeg 3\ncurv 0 1 1 2 3 4\nparm u 0 0 0 0 1 1 1 1\nend\nmg 1\nwobble 3\n"
                           "f\nl 1 2\n";
  // UTF-16 big endian with its byte order mark, as some Windows tools write.
  std::string utf16 = "\xFE\xFF";
  for (char c : text) utf16 += std::string(1, '\0') + c;
  const std::string path = Write("utf16", "", "newmtl m\nKd 0.5 0.5 0.5\n");
  test::WriteText(path, utf16);
  const LoadedScene loaded = LoadObj(path);
  ASSERT_EQ(loaded.scene.triangles.size(), 2u);
  EXPECT_NEAR(TotalArea(loaded.scene), 1.0, 1e-6);
  EXPECT_GT(loaded.scene.FrontNormal(0).y, 0.99f);
  WarningWith(loaded, "'vw' is ignored");
  EXPECT_NE(WarningWith(loaded, "free-form").find("s.obj:10:"), std::string::npos) << "counted from its first line";
  WarningWith(loaded, "'mg' is ignored");
  WarningWith(loaded, "unknown OBJ statement 'wobble'");
  EXPECT_NE(WarningWith(loaded, "a face of 0 corners").find("s.obj:17:"), std::string::npos)
      << "the continued face counts as line 8, so later lines keep their numbers";
  WarningWith(loaded, "lines and points");
}

// A file of 100,000 distinct unknown keywords (hostile, or badly broken) gives a bounded list of warnings, fast.
TEST(ObjAsWritten, WarningsOfManyKindsStayBounded) {
  std::string obj = kQuad + "f 1 4 3 2\n";
  for (int i = 0; i < 100000; ++i) obj += "w" + std::to_string(i) + " 1\n";
  const LoadedScene loaded = LoadObj(Write("many-kinds", obj));
  ASSERT_EQ(loaded.warnings.size(), WarningLog::kMaxKinds + 1);
  EXPECT_NE(loaded.warnings.back().find(std::to_string(100000 + 1 - WarningLog::kMaxKinds) + " more warnings of other kinds"),
            std::string::npos) << loaded.warnings.back();
}

TEST(ObjAsWritten, ConcavePolygonsKeepTheirAreaAndSide) {
  // Blender's L-shaped 3 m^2 floor, facing up, starting at the corner where a fan goes wrong.
  const LoadedScene loaded = LoadObj(Write("concave", "v 0 0 0\nv 2 0 0\nv 2 0 -1\nv 1 0 -1\nv 1 0 -2\nv 0 0 -2\nf 5 6 1 2 3 4\n"));
  ASSERT_EQ(loaded.scene.triangles.size(), 4u);
  EXPECT_NEAR(TotalArea(loaded.scene), 3.0, 1e-6);
  for (uint32_t t = 0; t < 4; ++t) EXPECT_GT(loaded.scene.FrontNormal(t).y, 0.99f) << t;
}

TEST(ObjAsWritten, LenientMtlStatements) {
  const std::string mtl =
      "Wavefront OBJ material file\n"           // a header without '#', as the McGuire archive writes
      "newmtl a\nNs 10\nKa 0 0 0c\nTr 0  illum 2\nKd 0.5 0.5 0.5\nKt 1 1 1\nPr 0.5\nPm 1\nsharpness 60\n"
      "newmtl b\nKd 0.2 0.2 0.2\nKs 0 1 x\nillum 2\n"  // a malformed Ks is not used by a diffuse material
      "newmtl metal\nKa 1 1 1\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\nillum 3\n"  // Blender's metal
      "newmtl\nKd 0.1 0.1 0.1\n";                                          // an empty name
  const LoadedScene loaded = LoadObj(Write("lenient", "mtllib s.mtl\n" + kQuad + "usemtl a\nf 1 2 3\nusemtl metal\nf 1 3 4\nusemtl\nf 4 3 2\n", mtl));
  ASSERT_EQ(loaded.scene.triangles.size(), 3u);
  const Material& metal = loaded.scene.MaterialOf(1);
  EXPECT_EQ(metal.kind, MaterialClass::kDiffuse) << "Kd + Ks > 1: baked as its diffuse part";
  EXPECT_FLOAT_EQ(metal.albedo.r, 0.8f);
  EXPECT_TRUE(metal.specular.IsBlack());
  EXPECT_FLOAT_EQ(loaded.scene.MaterialOf(2).albedo.g, 0.1f);
  EXPECT_NE(WarningWith(loaded, "'Wavefront' before any 'newmtl'").find("s.mtl:1:"), std::string::npos);
  EXPECT_NE(WarningWith(loaded, "in 'Ka', which is not used").find("s.mtl:4:"), std::string::npos);
  EXPECT_NE(WarningWith(loaded, "the rest ('illum 2') is ignored").find("s.mtl:5:"), std::string::npos);
  WarningWith(loaded, "'Kt' is ignored");
  WarningWith(loaded, "'Pr' is ignored");
  WarningWith(loaded, "'sharpness' is ignored");
  WarningWith(loaded, "in 'Ks', which is not used unless the material is a mirror");
  WarningWith(loaded, "material 'metal': illum 3 with Kd + Ks > 1");
  // The same malformed Ks on a mirror is an error.
  EXPECT_THROW(LoadObj(Write("bad-ks", "mtllib s.mtl\n" + kQuad, "newmtl m\nKs 0 1 x\nillum 3\n")), InputError);
}

// Writes a 2 x 2 RGB image: red, green / blue, white.
const std::vector<unsigned char> kPixels = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};

TEST(ObjAsWritten, TexturesInEveryCommonFormatDecodeAlike) {
  const std::string dir = test::TempDirectory("formats");
  test::WritePngRgb8(dir + "/t.png", 2, 2, kPixels);
  ASSERT_TRUE(stbi_write_tga((dir + "/t.tga").c_str(), 2, 2, 3, kPixels.data()));
  ASSERT_TRUE(stbi_write_bmp((dir + "/t.bmp").c_str(), 2, 2, 3, kPixels.data()));
  ASSERT_TRUE(stbi_write_jpg((dir + "/t.jpg").c_str(), 2, 2, 3, kPixels.data(), 100));
  const Texture png = LoadTexture(dir + "/t.png");
  for (const char* format : {"tga", "bmp", "jpg"}) {
    const Texture t = LoadTexture(dir + "/t." + format);
    ASSERT_EQ(t.width, 2);
    ASSERT_EQ(t.height, 2);
    // TGA and BMP are lossless; JPEG's chroma subsampling blurs a 2 x 2 image of four colours.
    const float tolerance = std::string(format) == "jpg" ? 0.35f : 1e-6f;
    for (size_t i = 0; i < 4; ++i) {
      EXPECT_NEAR(t.texels[i].r, png.texels[i].r, tolerance) << format << " texel " << i;
      EXPECT_NEAR(t.texels[i].g, png.texels[i].g, tolerance) << format << " texel " << i;
      EXPECT_NEAR(t.texels[i].b, png.texels[i].b, tolerance) << format << " texel " << i;
    }
  }
  // The format comes from the bytes: a PNG named .jpg still reads.
  std::filesystem::copy_file(dir + "/t.png", dir + "/png.jpg");
  EXPECT_FLOAT_EQ(LoadTexture(dir + "/png.jpg").texels[3].g, png.texels[3].g);
  // Not an image at all: refused, naming the file.
  test::WriteText(dir + "/not.jpg", "hello");
  try {
    LoadTexture(dir + "/not.jpg");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir + "/not.jpg");
    EXPECT_NE(std::string(e.what()).find("cannot read texture"), std::string::npos) << e.what();
  }
}

// A TGA header that declares 65535 x 65535 pixels is refused before its pixels are allocated.
TEST(ObjAsWritten, HugeDeclaredTexturesAreRefusedFromTheHeader) {
  const std::string dir = test::TempDirectory("huge-tga");
  std::string tga(18, '\0');
  tga[2] = 2;                                 // uncompressed true colour
  tga[12] = tga[13] = tga[14] = tga[15] = char(0xFF);  // width, height 65535
  tga[16] = 24;
  test::WriteText(dir + "/h.tga", tga + std::string(64, '\x7f'));
  try {
    LoadTexture(dir + "/h.tga");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("larger than the 8192 x 8192"), std::string::npos) << e.what();
  }
}

TEST(ObjAsWritten, TexturePathsAsExportersWriteThem) {
  const std::string dir = test::TempDirectory("texture-paths");
  std::filesystem::create_directories(dir + "/Textures");
  test::WritePngRgb8(dir + "/Textures/Wood.png", 2, 2, kPixels);
  test::WritePngRgb8(dir + "/beside.png", 2, 2, kPixels);
  const std::string mtl = "newmtl win\nmap_Kd textures\\wood.PNG\n"               // backslash and letter case
                          "newmtl abs\nmap_Kd /home/artist/project/beside.png\n"  // another machine's absolute path
                          "newmtl gone\nKd 0.4 0.4 0.4\nmap_Kd not_shipped.jpg\n"
                          "newmtl gone_no_kd\nmap_Kd not_shipped.jpg\n"
                          "newmtl opts\nmap_Kd -s 2 3 1 -o 0.5 0.25 -clamp on -bm 0.5 -texres 512 beside.png\n";
  test::WriteText(dir + "/s.mtl", mtl);
  test::WriteText(dir + "/s.obj", "mtllib s.mtl\n" + kQuad + "vt 0 0\nusemtl win\nf 1/1 2/1 3/1\n");
  const LoadedScene loaded = LoadObj(dir + "/s.obj");
  const std::vector<Material>& m = loaded.scene.materials;
  ASSERT_EQ(m.size(), 5u);
  ASSERT_EQ(loaded.scene.textures.size(), 2u) << "beside.png is decoded once for two materials";
  EXPECT_EQ(m[0].albedoTexture, 0);
  EXPECT_EQ(loaded.scene.textures[0].path, dir + "/Textures/Wood.png");
  EXPECT_EQ(m[1].albedoTexture, 1);
  EXPECT_EQ(m[4].albedoTexture, 1);
  WarningWith(loaded, "texture 'textures\\wood.PNG' read as");
  EXPECT_EQ(m[2].albedoTexture, -1);
  EXPECT_FLOAT_EQ(m[2].albedo.r, 0.4f) << "a texture not shipped: the material keeps its Kd";
  EXPECT_FLOAT_EQ(m[3].albedo.r, kDefaultAlbedo) << "and with no Kd, the default grey";
  EXPECT_NE(WarningWith(loaded, "texture 'not_shipped.jpg' not found").find("(2 in all)"), std::string::npos);
  EXPECT_FLOAT_EQ(m[4].textureScale.u, 2.0f);
  EXPECT_FLOAT_EQ(m[4].textureScale.v, 3.0f);
  EXPECT_FLOAT_EQ(m[4].textureOffset.u, 0.5f);
  EXPECT_FLOAT_EQ(m[4].textureOffset.v, 0.25f);
  EXPECT_TRUE(m[4].textureClamp);
  WarningWith(loaded, "map_Kd option '-bm' is ignored");
  WarningWith(loaded, "map_Kd option '-texres' is ignored");
  // -s 2 3 and -o 0.5 0.25 move where the texture is read: (0.1, 0.1) reads it at (0.7, 0.55).
  const Scene& s = loaded.scene;
  Material plain = m[4];
  plain.textureScale = {1, 1}, plain.textureOffset = {0, 0}, plain.textureClamp = false;
  EXPECT_FLOAT_EQ(s.AlbedoAtTexcoord(m[4], {0.1f, 0.1f}).g, s.AlbedoAtTexcoord(plain, {0.7f, 0.55f}).g);
  // -clamp on: beyond [0, 1] the corner texel (top right: green), not the repeat.
  const Rgb corner = s.AlbedoAtTexcoord(m[4], {5.0f, 5.0f});
  EXPECT_FLOAT_EQ(corner.g, m[4].albedo.g * s.textures[1].Texel(1, 0).g);
  EXPECT_FLOAT_EQ(corner.r, 0.0f);
}

}  // namespace
}  // namespace pb

namespace pb {
namespace {

// Blender 3.4's two OBJ exporters (tools/blender-export.py, absolute texture paths that lead nowhere here): each
// file loads, finds its textures beside it, keeps its concave L's area and side, and bakes.
TEST(ObjAsWritten, Blender34ExportsLoadAndBake) {
  for (const char* name : {"new_absolute", "legacy_absolute"}) {
    const std::string path = std::string(PB_SOURCE_DIR "/tests/data/blender/") + name + ".obj";
    const LoadedScene loaded = LoadObj(path);
    const Scene& s = loaded.scene;
    EXPECT_EQ(s.textures.size(), 2u) << name;
    for (const Texture& t : s.textures)
      EXPECT_EQ(std::filesystem::path(t.path).parent_path(), std::filesystem::path(path).parent_path()) << t.path;
    WarningWith(loaded, "material 'Metal': illum 3 with Kd + Ks > 1");
    double lArea = 0;
    for (uint32_t t = 0; t < s.triangles.size(); ++t) {
      if (s.objectNames[s.triangles[t].object].rfind("LShape", 0) != 0) continue;
      lArea += s.Area(t);
      EXPECT_GT(s.FrontNormal(t).z, 0.99f) << name << " triangle " << t;
    }
    EXPECT_NEAR(lArea, 0.75, 1e-6) << name;
    const std::string out = test::TempDirectory(std::string("blender-bake-") + name) + "/b.ply";
    const test::ToolRun run = test::RunTool(PB_BAKE_EXE, path + " -o " + out + " --photons 20000 --threads 2 -q");
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(std::filesystem::exists(out));
  }
}

}  // namespace
}  // namespace pb
