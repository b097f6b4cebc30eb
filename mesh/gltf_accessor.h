// What the glTF loader (mesh/gltf_loader.h) reads glTF's binary data with: 4x4 node transforms (column-major, as
// glTF stores them; positions in metres) and a bounds-checked view of an accessor's elements. tinygltf parses the
// JSON and the buffers but checks no accessor against its buffer view, nor a view against its buffer; every such
// fault here is an InputError naming the JSON path ("/accessors/3: ..."). Normalized integer components read in
// [0, 1] (or [-1, 1]), as the glTF specification maps them.
#pragma once

#include <tiny_gltf.h>

#include <array>
#include <initializer_list>
#include <string>
#include <vector>

#include "mesh/scene_builder.h"

namespace pb::gltf {

using Matrix = std::array<double, 16>;

inline constexpr Matrix kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

inline Matrix Multiply(const Matrix& a, const Matrix& b) {
  Matrix m{};
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row)
      for (int k = 0; k < 4; ++k) m[col * 4 + row] += a[k * 4 + row] * b[col * 4 + k];
  return m;
}

// T * R * S, with R from the unit quaternion (x, y, z, w).
inline Matrix FromTrs(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& s) {
  const double x = r.size() == 4 ? r[0] : 0, y = r.size() == 4 ? r[1] : 0, z = r.size() == 4 ? r[2] : 0,
               w = r.size() == 4 ? r[3] : 1;
  const double sx = s.size() == 3 ? s[0] : 1, sy = s.size() == 3 ? s[1] : 1, sz = s.size() == 3 ? s[2] : 1;
  Matrix m{1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
           2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
           2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
           0,                       0,                       0,                       1};
  for (int k = 0; k < 3; ++k) m[k] *= sx, m[4 + k] *= sy, m[8 + k] *= sz;
  if (t.size() == 3) m[12] = t[0], m[13] = t[1], m[14] = t[2];
  return m;
}

inline double LinearDeterminant(const Matrix& m) {
  return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
         m[8] * (m[1] * m[6] - m[5] * m[2]);
}

inline Position Apply(const Matrix& m, const double p[3]) {
  return {m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12], m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13],
          m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14]};
}

// The most elements an accessor without a buffer view (all zeros) may have: no buffer bounds them.
inline constexpr size_t kMaxZeroElements = size_t(1) << 24;

// Bytes per component of a glTF component type; 0 for an unknown one.
int ComponentBytes(int type);

class Accessor {
 public:
  // The accessor `index`, which must have `components` components of one of `types`. `where` is the JSON path
  // of the reference, and `file` the glTF file, for messages.
  Accessor(const tinygltf::Model& model, int index, int components, std::initializer_list<int> types,
           const std::string& where, const std::string& file);

  size_t count() const { return count_; }
  // Component k of element i; normalized integers are mapped to [0, 1] (or [-1, 1]).
  double Get(size_t i, int k) const;
  uint64_t Index(size_t i) const { return uint64_t(Get(i, 0)); }  // for index accessors (never normalized)

 private:
  template <typename T>
  double Read(const unsigned char* p, double unit) const;

  const unsigned char* data_ = nullptr;  // null: every element is zero
  size_t count_ = 0, stride_ = 0;
  int type_ = 0, components_ = 0;
  bool normalized_ = false;
};

}  // namespace pb::gltf
