// Textured albedo (map_Kd): PNG texels are decoded from sRGB to linear reflectance and sampled bilinearly with
// the OBJ convention (t = 0 at the bottom row); faces of a textured material need texture coordinates; the
// photon tracer and the PLY use Kd x texture, so a uniformly textured closed box keeps its closed form
// sum of hit flux = Phi / (1 - rho), and vertices at texel centres carry exactly their texel's reflectance.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <sstream>

#include "baker/1_trace_photons.h"
#include "baker/bake.h"
#include "mesh/errors.h"
#include "mesh/obj_loader.h"
#include "mesh/texture.h"
#include "tests/ply_reader.h"
#include "tests/test_scenes.h"
#include "tests/traced_scene.h"

namespace pb {
namespace {

double SrgbToLinear(int byte) {
  const double c = byte / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

TEST(Texture, DecodesSrgbAndSamplesBilinearlyFromTheBottomRow) {
  const std::string dir = test::TempDirectory("texture");
  // 2 x 2: top row red (200, 0, 0) and green (0, 100, 0); bottom row blue (0, 0, 50) and grey (128, 128, 128).
  test::WritePngRgb8(dir + "/t.png", 2, 2, {200, 0, 0, 0, 100, 0, 0, 0, 50, 128, 128, 128});
  const Texture t = LoadPngTexture(dir + "/t.png");
  ASSERT_EQ(t.width, 2);
  const float tolerance = 1e-6f;  // the exact sRGB curve, in float
  EXPECT_NEAR(t.Sample({0.25f, 0.75f}).r, SrgbToLinear(200), tolerance) << "top-left texel centre";
  EXPECT_NEAR(t.Sample({0.75f, 0.75f}).g, SrgbToLinear(100), tolerance) << "top-right";
  EXPECT_NEAR(t.Sample({0.25f, 0.25f}).b, SrgbToLinear(50), tolerance) << "bottom-left: t = 0 is the bottom";
  EXPECT_NEAR(t.Sample({0.75f, 0.25f}).r, SrgbToLinear(128), tolerance);
  EXPECT_NEAR(t.Sample({0.5f, 0.75f}).r, 0.5 * SrgbToLinear(200), tolerance) << "halfway between red and green";
  EXPECT_NEAR(t.Sample({1.25f, -0.25f}).r, t.Sample({0.25f, 0.75f}).r, 1e-6) << "repeat wrapping";
  EXPECT_NEAR(t.maximum.r, SrgbToLinear(200), tolerance);
  EXPECT_THROW(LoadPngTexture(dir + "/missing.png"), InputError);
}

// A floor quad whose corners sit at the four texel centres of a 2 x 2 texture; returns the OBJ path.
std::string WriteTexturedFloor(const std::string& dir, const std::string& faces) {
  test::WritePngRgb8(dir + "/t.png", 2, 2, {200, 0, 0, 0, 100, 0, 0, 0, 50, 128, 128, 128});
  test::WriteText(dir + "/f.mtl", "newmtl tex\nKd 0.9 0.9 0.9\nmap_Kd t.png\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n");
  test::WriteText(dir + "/f.obj",
                  "mtllib f.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
                  "vt 0.25 0.25\nvt 0.75 0.25\nvt 0.75 0.75\nvt 0.25 0.75\nusemtl tex\n" + faces +
                  "usemtl lamp\nv 0.4 1 0.4\nv 0.6 1 0.4\nv 0.6 1 0.6\nv 0.4 1 0.6\nf 5 6 7 8\n");
  return dir + "/f.obj";
}

TEST(Texture, VerticesCarryKdTimesTheirTexel) {
  const std::string dir = test::TempDirectory("texture-floor");
  BakeOptions o;
  o.scenePath = WriteTexturedFloor(dir, "f 1/1 4/4 3/3 2/2\n");
  o.outputPath = dir + "/out.ply";
  o.photons = 10000;
  Bake(o, Log(true));
  const test::PlyData ply = test::ReadPly(o.outputPath);
  int checked = 0;
  for (size_t v = 0; v < ply.VertexCount(); ++v) {
    if (ply.vertex.at("y")[v] != 0.0) continue;
    const double x = ply.vertex.at("x")[v], z = ply.vertex.at("z")[v];
    // (x, z) = (0, 0) has vt (0.25, 0.25): the bottom-left texel, blue; (1, 1) has (0.75, 0.75): top-right, green.
    if (x == 0 && z == 0) {
      EXPECT_NEAR(ply.vertex.at("reflectance_b")[v], 0.9 * SrgbToLinear(50), 1e-6);
      ++checked;
    }
    if (x == 1 && z == 1) {
      EXPECT_NEAR(ply.vertex.at("reflectance_g")[v], 0.9 * SrgbToLinear(100), 1e-6);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 2);
}

// A face of a textured material without texture coordinates (Blender's exporter writes one when an object
// without a UV map follows a textured one) gets Kd times the texture's mean, with a warning; faces with them keep
// the texture.
TEST(Texture, FacesOfATexturedMaterialWithoutTextureCoordinatesGetItsMean) {
  const std::string dir = test::TempDirectory("texture-novt");
  const LoadedScene loaded = LoadObj(WriteTexturedFloor(dir, "f 1 4 3 2\nf 1/1 2/2 3/3\n"));
  const Scene& s = loaded.scene;
  ASSERT_EQ(s.triangles.size(), 5u);
  const Material& untextured = s.MaterialOf(0);
  EXPECT_EQ(untextured.albedoTexture, -1);
  EXPECT_EQ(untextured.name, "tex (untextured)");
  const double mean = (SrgbToLinear(200) + 0 + 0 + SrgbToLinear(128)) / 4;  // the red channel of the 4 texels
  EXPECT_NEAR(untextured.albedo.r, 0.9 * mean, 1e-6);
  EXPECT_EQ(s.MaterialOf(2).name, "tex");
  EXPECT_EQ(s.MaterialOf(2).albedoTexture, 0);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("f.obj:11: warning: material 'tex' has a map_Kd texture, but the face has no "
                                    "texture coordinates"), std::string::npos) << loaded.warnings[0];
  // A texture that is not there is a warning (issue 19): the material is untextured, so no v/t is needed.
  test::WriteText(dir + "/gone.mtl", "newmtl tex\nmap_Kd nothere.png\n");
  test::WriteText(dir + "/gone.obj", "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 0 1\nusemtl tex\nf 1 2 3\n");
  const LoadedScene gone = LoadObj(dir + "/gone.obj");
  ASSERT_EQ(gone.warnings.size(), 1u);
  EXPECT_NE(gone.warnings[0].find("gone.mtl:2: warning: texture 'nothere.png' not found"), std::string::npos)
      << gone.warnings[0];
}

// A 69-byte PNG whose header declares 65535 x 65535 pixels (4.2 GB decoded) is refused from its header, before
// any allocation; a texture that two materials name is decoded once (issue 16).
TEST(Texture, AHugeDeclaredSizeOrAnHdrImageIsRefusedAndASharedTextureIsDecodedOnce) {
  const std::string dir = test::TempDirectory("texture-hostile");
  std::string ihdr = std::string("IHDR") + std::string("\x00\x00\xff\xff\x00\x00\xff\xff\x08\x02\x00\x00\x00", 13);
  const uint32_t crc = uint32_t(crc32(0, reinterpret_cast<const Bytef*>(ihdr.data()), uInt(ihdr.size())));
  const char crcBytes[4] = {char(crc >> 24), char(crc >> 16), char(crc >> 8), char(crc)};
  const std::string idat("\x00\x00\x00\x00IDAT\x35\xaf\x06\x1e", 12), iend("\x00\x00\x00\x00IEND\xae\x42\x60\x82", 12);
  test::WriteText(dir + "/huge.png", std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\x00\x00\x00\x0d", 4) + ihdr +
                                         std::string(crcBytes, 4) + idat + iend);
  try {
    LoadPngTexture(dir + "/huge.png");
    ADD_FAILURE() << "a 65535 x 65535 texture was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("texture of 65535 x 65535 pixels is larger than"), std::string::npos) << e.what();
  }
  // A 24-byte TGA (run-length grey) that declares 29186 x 1538 pixels, which stb_image filled and converted in over
  // 10 s under the sanitizers (fuzz_texture): refused from its header, since no format holds 45M pixels in 24
  // bytes. A legal 8192-pixel run-length TGA of 146 bytes (64 packets of 128) still decodes.
  try {
    LoadTexture(PB_SOURCE_DIR "/tests/fuzz/corpus/texture/tga-29186x1538-in-24-bytes-slow.tga");
    ADD_FAILURE() << "a 45M-pixel texture of 24 bytes was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("texture of 29186 x 1538 pixels in a file of 24 bytes"), std::string::npos)
        << e.what();
  }
  // Header: run-length grey, 8192 x 1 pixels of 8 bits, top row first.
  std::string tga("\x00\x00\x0b\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x20\x01\x00\x08\x20", 18);
  for (int packet = 0; packet < 64; ++packet) tga += std::string("\xff\x80", 2);  // 128 grey pixels of 0x80
  test::WriteText(dir + "/runs.tga", tga);
  const Texture runs = LoadTexture(dir + "/runs.tga");
  EXPECT_EQ(runs.width * runs.height, 8192);
  EXPECT_NEAR(runs.Mean().r, SrgbToLinear(128), 1e-6);
  // The HDR on which stb_image's decoder looped forever (fuzz_sky_image) is refused as a texture before it is decoded.
  try {
    LoadTexture(PB_SOURCE_DIR "/tests/fuzz/corpus/sky_image/empty-run-hung-stb.hdr");
    ADD_FAILURE() << "an HDR texture was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("an HDR image is not a reflectance texture"), std::string::npos) << e.what();
  }
  test::WritePngRgb8(dir + "/t.png", 1, 1, {128, 128, 128});
  test::WriteText(dir + "/two.mtl", "newmtl a\nmap_Kd t.png\nnewmtl b\nKd 0.5 0.5 0.5\nmap_Kd t.png\n");
  test::WriteText(dir + "/two.obj", "mtllib two.mtl\nv 0 0 0\nv 1 0 0\nv 0 0 1\nvt 0 0\nusemtl a\nf 1/1 2/1 3/1\n"
                                    "usemtl b\nf 1/1 3/1 2/1\n");
  const Scene scene = LoadObj(dir + "/two.obj").scene;
  EXPECT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.materials[0].albedoTexture, 0);
  EXPECT_EQ(scene.materials[1].albedoTexture, 0);
}

TEST(Texture, AUniformlyTexturedClosedBoxKeepsItsClosedForm) {
  // Walls with map_Kd of one grey texel (sRGB 188, linear 0.5029) and no Kd: rho is the texel's value, and the
  // hit flux sums to Phi / (1 - rho) with relative sd sqrt(rho / N) = 0.16% at N = 200k.
  const std::string dir = test::TempDirectory("texture-box");
  test::WritePngRgb8(dir + "/grey.png", 1, 1, {188, 188, 188});
  const std::string box = test::WriteClosedBox(dir, 1.0f, 0.5f, 0.2f, 10.0f);
  std::string mtl = test::ReadBytes(dir + "/box.mtl");
  mtl.replace(mtl.find("newmtl wall\nKd 0.5 0.5 0.5\n"), 26, "newmtl wall\nmap_Kd grey.png\n");
  test::WriteText(dir + "/box.mtl", mtl);
  // Every wall corner gets texture coordinate 1 (any will do for a one-texel texture); the light's faces follow
  // "usemtl light" and keep theirs.
  std::istringstream in(test::ReadBytes(box));
  std::string faced = "vt 0.5 0.5\n";
  bool walls = true;
  for (std::string line; std::getline(in, line);) {
    walls = walls && line != "usemtl light";
    if (walls && line.rfind("f ", 0) == 0) {
      std::istringstream corners(line.substr(2));
      std::ostringstream rewritten;
      rewritten << "f";
      for (std::string corner; corners >> corner;) rewritten << ' ' << corner << "/1";
      line = rewritten.str();
    }
    faced += line + "\n";
  }
  test::WriteText(box, faced);
  const test::TracedScene traced(box);
  constexpr uint64_t kPhotons = 200000;
  const PhotonStore hits = traced.Trace(kPhotons, 2);
  // The light has Kd 0.5 too, so every diffuse surface reflects rho; the texel decodes to about 0.503.
  const double rho = traced.scene.textures.at(0).maximum.g;
  ASSERT_NEAR(rho, SrgbToLinear(188), 1e-6);
  double flux = 0;
  hits.ForEach([&](const PhotonHit&, Rgb f) { flux += f.g; });
  // The light's own Kd is 0.5, not rho: the closed form then holds to about |rho - 0.5| x (light's share of hits),
  // well inside the noise bound below.
  EXPECT_NEAR(flux * (1 - rho) / hits.stats.fluxEmitted.g, 1.0, 5 * std::sqrt(rho / kPhotons) + 0.01);
}

}  // namespace
}  // namespace pb
