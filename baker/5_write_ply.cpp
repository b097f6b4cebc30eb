#include "baker/5_write_ply.h"

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <optional>

#include "baker/files/atomic_file.h"
#include "baker/tone_map.h"

namespace pb {
namespace {

static_assert(std::endian::native == std::endian::little, "binary PLY is written as raw little-endian memory");

std::string Header(const BakedMesh& baked, bool ascii, float exposure) {
  std::string h = "ply\n";
  h += ascii ? "format ascii 1.0\n" : "format binary_little_endian 1.0\n";
  h += "comment photonbake: irradiance H [W/m^2], reflectance R (Kd x map_Kd), radiance [W/(m^2 sr)] = Le + R*H/pi, "
       "quality = luminance of H\n";
  h += fmt::format("comment red/green/blue: sRGB of Reinhard(exposure * radiance), exposure {:.6g}\n", exposure);
  h += fmt::format("element vertex {}\n", baked.mesh.VertexCount());
  for (const char* p : {"x", "y", "z", "nx", "ny", "nz"}) h += fmt::format("property float {}\n", p);
  for (const char* p : {"red", "green", "blue"}) h += fmt::format("property uchar {}\n", p);
  for (const char* p : {"irradiance_r", "irradiance_g", "irradiance_b", "radiance_r", "radiance_g", "radiance_b",
                        "quality", "reflectance_r", "reflectance_g", "reflectance_b"})
    h += fmt::format("property float {}\n", p);
  if (!baked.sh.empty()) {
    h += "comment sh_C0..sh_C3: L1 spherical harmonics of the incident radiance [W/(m^2 sr)] per channel C: L00 and "
         "L1 along world x, y, z; irradiance E(n) = 2.0466534 (sh_C1 nx + sh_C2 ny + sh_C3 nz)\n";
    for (const char c : {'r', 'g', 'b'})
      for (int k = 0; k < 4; ++k) h += fmt::format("property float sh_{}{}\n", c, k);
  }
  h += fmt::format("element face {}\n", baked.mesh.faces.size());
  h += "property list uchar int vertex_indices\nend_header\n";
  return h;
}

// One vertex's properties in header order.
struct VertexRecord {
  float position[3], normal[3];
  std::array<uint8_t, 3> colour;
  float irradiance[3], radiance[3], quality, reflectance[3];
  std::optional<std::array<float, 12>> sh;  // with --sh: sh_r0..sh_r3, sh_g0..sh_g3, sh_b0..sh_b3
};

// A vertex's SH in the PLY's order: per channel, L00 then L1 along x, y, z.
std::array<float, 12> ShRecord(const ShL1& sh) {
  std::array<float, 12> out;
  for (int k = 0; k < 4; ++k) out[k] = sh.c[k].r, out[4 + k] = sh.c[k].g, out[8 + k] = sh.c[k].b;
  return out;
}

VertexRecord RecordOf(const BakedMesh& baked, size_t v, float exposure) {
  const Point3 p = baked.mesh.positions[v];
  const std::array<double, 3>& o = baked.mesh.origin;  // back to world coordinates, added in double
  const Normal3 n = baked.mesh.normals[v];
  const Rgb H = baked.irradiance[v], L = baked.Radiance(v), R = baked.albedo[v];
  VertexRecord r{{float(o[0] + p.x), float(o[1] + p.y), float(o[2] + p.z)}, {n.x, n.y, n.z}, ToneMap(L, exposure),
                 {H.r, H.g, H.b}, {L.r, L.g, L.b}, Luminance(H), {R.r, R.g, R.b}, std::nullopt};
  if (!baked.sh.empty()) r.sh = ShRecord(baked.sh[v]);
  return r;
}

template <typename T>
void Put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

void AppendBinary(std::string& out, const VertexRecord& r) {
  for (float f : r.position) Put(out, f);
  for (float f : r.normal) Put(out, f);
  for (uint8_t c : r.colour) Put(out, c);
  for (float f : r.irradiance) Put(out, f);
  for (float f : r.radiance) Put(out, f);
  Put(out, r.quality);
  for (float f : r.reflectance) Put(out, f);
  if (r.sh)
    for (float f : *r.sh) Put(out, f);
}

void AppendAscii(std::string& out, const VertexRecord& r) {
  out += fmt::format("{} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {}\n", r.position[0], r.position[1],
                     r.position[2], r.normal[0], r.normal[1], r.normal[2], r.colour[0], r.colour[1], r.colour[2],
                     r.irradiance[0], r.irradiance[1], r.irradiance[2], r.radiance[0], r.radiance[1], r.radiance[2],
                     r.quality, r.reflectance[0], r.reflectance[1], r.reflectance[2]);
  if (r.sh) {
    out.pop_back();  // the line's end, after the SH
    for (float f : *r.sh) out += fmt::format(" {}", f);
    out += '\n';
  }
}

std::string Body(const BakedMesh& baked, bool ascii, float exposure) {
  std::string out;
  out.reserve(baked.mesh.VertexCount() * 61 + baked.mesh.faces.size() * 13);
  for (size_t v = 0; v < baked.mesh.VertexCount(); ++v) {
    const VertexRecord r = RecordOf(baked, v, exposure);
    ascii ? AppendAscii(out, r) : AppendBinary(out, r);
  }
  for (const auto& f : baked.mesh.faces) {
    if (ascii) {
      out += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
    } else {
      Put(out, uint8_t(3));
      for (uint32_t i : f) Put(out, int32_t(i));
    }
  }
  return out;
}

}  // namespace

float DisplayExposure(const BakedMesh& baked, std::optional<float> user) {
  if (user) return *user;
  std::vector<Rgb> radiance(baked.mesh.VertexCount());
  for (size_t v = 0; v < radiance.size(); ++v) radiance[v] = baked.Radiance(v);
  return AutoExposure(radiance);
}

float WritePly(OutputFiles& outputs, const std::string& path, const BakedMesh& baked, const PlyOptions& options) {
  const float exposure = DisplayExposure(baked, options.exposure);
  const std::string header = Header(baked, options.ascii, exposure);
  const std::string body = Body(baked, options.ascii, exposure);
  outputs.Write(path, [&](std::ostream& out) {
    out.write(header.data(), std::streamsize(header.size()));
    out.write(body.data(), std::streamsize(body.size()));
  });
  return exposure;
}

}  // namespace pb
