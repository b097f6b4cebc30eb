#include "tests/ply_reader.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pb::test {

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

PlyData ReadPly(const std::string& path) {
  const std::string bytes = ReadBytes(path);
  std::istringstream in(bytes);
  std::string line;
  std::getline(in, line);
  if (line != "ply") throw std::runtime_error("not a PLY: " + path);
  PlyData ply;
  std::vector<std::string> types;
  size_t vertices = 0, faces = 0;
  std::string element;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      words >> ply.format;
    } else if (keyword == "element") {
      size_t count = 0;
      words >> element >> count;
      (element == "vertex" ? vertices : faces) = count;
    } else if (keyword == "property" && element == "vertex") {
      std::string type, name;
      words >> type >> name;
      if (type != "float" && type != "uchar") throw std::runtime_error("unexpected type " + type);
      types.push_back(type);
      ply.vertexProperties.push_back(name);
    } else if (keyword == "property" && element == "face") {
      if (line != "property list uchar int vertex_indices") throw std::runtime_error("unexpected face list");
    } else if (keyword != "comment") {
      throw std::runtime_error("unexpected header line: " + line);
    }
  }
  const bool binary = ply.format == "binary_little_endian";
  if (!binary && ply.format != "ascii") throw std::runtime_error("unexpected format " + ply.format);
  size_t offset = size_t(in.tellg());
  auto readBinary = [&](void* out, size_t n) {
    if (offset + n > bytes.size()) throw std::runtime_error("PLY truncated");
    std::memcpy(out, bytes.data() + offset, n);
    offset += n;
  };
  for (size_t v = 0; v < vertices; ++v)
    for (size_t p = 0; p < types.size(); ++p) {
      double value = 0;
      if (!binary) {
        in >> value;
      } else if (types[p] == "float") {
        float f;
        readBinary(&f, 4);
        value = f;
      } else {
        uint8_t c;
        readBinary(&c, 1);
        value = c;
      }
      ply.vertex[ply.vertexProperties[p]].push_back(value);
    }
  for (size_t f = 0; f < faces; ++f) {
    std::array<int, 3> face{};
    int count = 0;
    if (binary) {
      uint8_t n;
      readBinary(&n, 1);
      count = n;
      if (count == 3) readBinary(face.data(), 12);
    } else {
      in >> count >> face[0] >> face[1] >> face[2];
    }
    if (count != 3) throw std::runtime_error("non-triangle face");
    ply.faces.push_back(face);
  }
  if (binary && offset != bytes.size()) throw std::runtime_error("trailing bytes after faces");
  if (!binary && !in) throw std::runtime_error("ASCII PLY truncated");
  return ply;
}

}  // namespace pb::test
