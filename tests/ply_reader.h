// A minimal, independent PLY reader for tests: reads what bake writes (binary little-endian or ASCII, vertex
// properties of type float or uchar, faces as "list uchar int") and checks the header as it goes.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

namespace pb::test {

struct PlyData {
  std::string format;                                 // "binary_little_endian" or "ascii"
  std::vector<std::string> vertexProperties;          // in header order
  std::map<std::string, std::vector<double>> vertex;  // property -> one value per vertex
  std::vector<std::array<int, 3>> faces;
  size_t VertexCount() const { return vertex.empty() ? 0 : vertex.begin()->second.size(); }
};

// Throws std::runtime_error on anything unexpected.
PlyData ReadPly(const std::string& path);

std::string ReadBytes(const std::string& path);

}  // namespace pb::test
