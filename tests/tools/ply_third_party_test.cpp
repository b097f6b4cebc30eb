// MeshLab cannot run in CI, so the PLY is opened by a third-party reader instead: OpenMesh's PLY importer,
// an independent implementation of the format. It must read both encodings with per-vertex colours and
// normals, and see the same counts and colours.
#include <OpenMesh/Core/IO/MeshIO.hh>  // before the mesh kernel, as OpenMesh requires
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <gtest/gtest.h>

#include "baker/bake.h"
#include "tests/ply_reader.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

TEST(PlyThirdParty, OpenMeshReadsBinaryAndAsciiWithColoursAndNormals) {
  const std::string dir = test::TempDirectory("openmesh");
  for (const bool ascii : {false, true}) {
    BakeOptions o;
    o.scenePath = PB_SOURCE_DIR "/data/box/box.obj";
    o.outputPath = dir + (ascii ? "/a.ply" : "/b.ply");
    o.photons = 100'000;
    o.asciiPly = ascii;
    Bake(o, Log(true));
    const test::PlyData ours = test::ReadPly(o.outputPath);

    OmMesh mesh;
    mesh.request_vertex_colors();
    mesh.request_vertex_normals();
    OpenMesh::IO::Options read = OpenMesh::IO::Options::VertexColor | OpenMesh::IO::Options::VertexNormal;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(mesh, o.outputPath, read)) << o.outputPath;
    EXPECT_TRUE(read.check(OpenMesh::IO::Options::VertexColor));
    EXPECT_TRUE(read.check(OpenMesh::IO::Options::VertexNormal));
    ASSERT_EQ(mesh.n_vertices(), ours.VertexCount());
    ASSERT_EQ(mesh.n_faces(), ours.faces.size());
    for (size_t v = 0; v < mesh.n_vertices(); v += 53) {
      const auto c = mesh.color(mesh.vertex_handle(int(v)));
      EXPECT_EQ(c[0], ours.vertex.at("red")[v]);
      EXPECT_EQ(c[2], ours.vertex.at("blue")[v]);
      EXPECT_FLOAT_EQ(mesh.point(mesh.vertex_handle(int(v)))[1], float(ours.vertex.at("y")[v]));
    }
  }
}

}  // namespace
}  // namespace pb
