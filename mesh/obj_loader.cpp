#include "mesh/obj_loader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "mesh/errors.h"
#include "mesh/input_file.h"
#include "mesh/texture.h"

namespace pb {
namespace {

// One line of an OBJ or MTL file, split into whitespace-separated tokens, with its location for messages.
struct Line {
  const std::string* file = nullptr;
  int number = 0;
  std::vector<std::string> tokens;

  [[noreturn]] void Fail(const std::string& message) const { throw InputError(*file, number, message); }
  std::string Warning(const std::string& message) const {
    return *file + ":" + std::to_string(number) + ": warning: " + message;
  }
  const std::string& Keyword() const { return tokens[0]; }
  void ExpectArguments(size_t atLeast, size_t atMost) const {
    const size_t n = tokens.size() - 1;
    if (n < atLeast || n > atMost)
      Fail("'" + Keyword() + "' takes " +
           (atLeast == atMost ? std::to_string(atLeast) : std::to_string(atLeast) + " to " + std::to_string(atMost)) +
           " values, found " + std::to_string(n));
  }
  float Number(size_t i) const { return Parse<float>(i); }
  double Double(size_t i) const { return Parse<double>(i); }
  template <typename T>
  T Parse(size_t i) const {
    const std::string& t = tokens[i];
    const char* begin = t.data() + (t.size() > 1 && t[0] == '+');  // from_chars refuses a leading '+'.
    T value = 0;
    const auto [end, ec] = std::from_chars(begin, t.data() + t.size(), value);
    if (ec != std::errc() || end != t.data() + t.size()) Fail("malformed number '" + t + "' in '" + Keyword() + "'");
    if (!std::isfinite(value)) Fail("non-finite number '" + t + "' in '" + Keyword() + "'");
    return value;
  }
  // The rest of the line after the keyword, for names that may contain spaces.
  std::string Rest() const {
    std::string s;
    for (size_t i = 1; i < tokens.size(); ++i) s += (i > 1 ? " " : "") + tokens[i];
    return s;
  }
};

// Reads a text file line by line, skipping blanks and comments. Lines end at LF, CRLF or a lone CR (old Mac
// exporters); a UTF-8 byte order mark at the start is skipped; a NUL byte is refused (not a text file).
class LineReader {
 public:
  // `what` names the file in messages ("scene file", "material library").
  LineReader(const std::string& path, const std::string& what) : path_(path) {
    RequireRegularFile(path, what);
    in_.open(path, std::ios::binary);
    if (!in_) throw InputError(path, 0, "cannot open " + what);
    if (in_.peek() == 0xEF) {
      char bom[3] = {};
      in_.read(bom, 3);
      if (std::string(bom, 3) != "\xEF\xBB\xBF") in_.seekg(0);
    }
  }
  bool Next(Line& line) {
    for (std::string text; ReadLine(text);) {
      ++number_;
      if (text.find('\0') != std::string::npos)
        throw InputError(path_, number_, "a NUL byte: this is not a text file");
      if (const size_t hash = text.find('#'); hash != std::string::npos) text.resize(hash);
      std::istringstream words(text);
      line = Line{&path_, number_, {}};
      for (std::string w; words >> w;) line.tokens.push_back(w);
      if (!line.tokens.empty()) return true;
    }
    return false;
  }

 private:
  bool ReadLine(std::string& text) {
    text.clear();
    int c = in_.get();
    if (c == std::char_traits<char>::eof()) return false;
    for (; c != std::char_traits<char>::eof() && c != '\n' && c != '\r'; c = in_.get()) text.push_back(char(c));
    if (c == '\r' && in_.peek() == '\n') in_.get();
    return true;
  }

  std::string path_;
  std::ifstream in_;
  int number_ = 0;
};

std::string Directory(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// A file named in `from` (an mtllib or map_Kd argument): absolute as given, else relative to `from`'s folder.
std::string ResolveBeside(const std::string& from, const std::string& name) {
  return !name.empty() && name[0] == '/' ? name : Directory(from) + name;
}

Rgb ReadRgb(const Line& line) {
  line.ExpectArguments(1, 3);
  const float r = line.Number(1);
  if (line.tokens.size() == 2) return {r, r, r};  // "Kd 0.5" is grey, as in the MTL spec.
  line.ExpectArguments(3, 3);
  return {r, line.Number(2), line.Number(3)};
}

// The statements of one MTL material as written, before its class is decided (illum and the values it uses).
struct MtlEntry {
  Material material;
  Line start;  // the 'newmtl' line, for messages
  bool hasKd = false;
  Rgb textureMaximum{1, 1, 1};  // of its map_Kd, for the reflectance cap
  int illum = 2;
  std::optional<Rgb> ks, tf;
  std::optional<float> ni, d;
};

bool InUnitInterval(Rgb c) { return c.r >= 0 && c.g >= 0 && c.b >= 0 && c.r <= 1 && c.g <= 1 && c.b <= 1; }

// The largest reflectance a diffuse or mirror material keeps. A surface that absorbs nothing keeps photons (and
// paths) bouncing until they escape: in a closed scene forever, and H = Phi / (A (1 - rho)) diverges. At 0.99 a
// photon's expected path is still bounded, at 100 surfaces.
constexpr float kMaxReflectance = 0.99f;

// Scales Kd and Ks down together so that no channel of Kd + Ks exceeds kMaxReflectance, with a warning.
void CapReflectance(Material& m, Rgb textureMaximum, const Line& where, std::vector<std::string>& warnings) {
  const float total = (m.albedo * textureMaximum + m.specular).Max();
  if (total <= kMaxReflectance) return;
  warnings.push_back(where.Warning("material '" + m.name + "': reflectance " + std::to_string(total).substr(0, 5) +
                                   " capped at 0.99, since a surface that absorbs nothing never ends a path in a "
                                   "closed scene"));
  m.albedo = m.albedo * (kMaxReflectance / total);
  m.specular = m.specular * (kMaxReflectance / total);
}

MaterialClass ClassOfIllum(int illum) {
  switch (illum) {
    case 3: case 5: case 8: return MaterialClass::kMirror;
    case 4: case 6: case 7: case 9: return MaterialClass::kGlass;
    default: return MaterialClass::kDiffuse;
  }
}

// Turns the statements of one material into a checked Material of its class (see obj_loader.h).
Material ResolveMaterial(MtlEntry e, std::vector<std::string>& warnings) {
  Material& m = e.material;
  const Line& where = e.start;
  const std::string named = "material '" + m.name + "': ";
  if (!InUnitInterval(m.albedo)) where.Fail(named + "Kd must lie in [0, 1] per channel (energy conservation)");
  if (m.emission.r < 0 || m.emission.g < 0 || m.emission.b < 0) where.Fail(named + "Ke must be non-negative");
  if (e.illum > 9) warnings.push_back(where.Warning(named + "illum " + std::to_string(e.illum) + " is baked as diffuse Kd"));
  m.kind = ClassOfIllum(e.illum);
  if (m.kind == MaterialClass::kMirror) {
    m.specular = e.ks.value_or(Rgb{1, 1, 1});
    if (!InUnitInterval(m.specular) || !InUnitInterval(m.albedo + m.specular))
      where.Fail(named + "a mirror needs Ks in [0, 1] and Kd + Ks <= 1 per channel (energy conservation)");
  } else if (m.kind == MaterialClass::kGlass) {
    m.ior = e.ni.value_or(1.5f);
    if (!(m.ior > 0.0f && m.ior <= 10.0f)) where.Fail(named + "glass needs Ni in (0, 10]");
    const float d = e.d.value_or(0.0f);
    m.transmittance = e.tf.value_or(Rgb{1 - d, 1 - d, 1 - d});
    if (!InUnitInterval(m.transmittance) || d < 0 || d > 1) where.Fail(named + "glass needs Tf and d in [0, 1]");
    if (m.transmittance.IsBlack())
      warnings.push_back(where.Warning(named + "glass transmits nothing (d 1 and no Tf); set Tf or d < 1"));
    if (!m.albedo.IsBlack()) warnings.push_back(where.Warning(named + "Kd is not used by glass"));
    m.albedo = {};
  }
  if (m.albedoTexture >= 0 && !e.hasKd) m.albedo = {1, 1, 1};  // map_Kd alone: the texture is the albedo
  CapReflectance(m, e.textureMaximum, where, warnings);
  return m;
}

// Parses an MTL file into `materials`, keyed by name in `byName`.
// map_Kd FILE: loads the texture (relative to the MTL file) into `textures`; options such as -s are refused.
void ReadAlbedoTexture(const Line& line, const std::string& mtlPath, MtlEntry& entry, std::vector<Texture>& textures) {
  line.ExpectArguments(1, 64);
  if (line.tokens[1][0] == '-') line.Fail("map_Kd options (" + line.tokens[1] + ") are not supported; give a file only");
  const std::string file = ResolveBeside(mtlPath, line.Rest());
  // A texture that several materials share is decoded once.
  const size_t index = size_t(std::find_if(textures.begin(), textures.end(), [&](const Texture& t) {
                                return t.path == file;
                              }) - textures.begin());
  if (index == textures.size()) {
    try {
      textures.push_back(LoadPngTexture(file));
    } catch (const InputError& e) {
      line.Fail(e.message() + " ('" + file + "')");
    }
  }
  entry.material.albedoTexture = int(index);
  entry.textureMaximum = textures[size_t(entry.material.albedoTexture)].maximum;
}

void LoadMtl(const std::string& path, const Line& mtllibLine, std::vector<Material>& materials,
             std::unordered_map<std::string, uint32_t>& byName, std::vector<Texture>& textures,
             std::vector<std::string>& warnings) {
  std::optional<LineReader> opened;
  try {
    opened.emplace(path, "material library");
  } catch (const InputError& e) {
    mtllibLine.Fail(e.message() + " ('" + path + "')");
  }
  LineReader& reader = *opened;
  std::optional<MtlEntry> current;
  auto finish = [&] {
    if (current) materials.push_back(ResolveMaterial(std::move(*current), warnings));
  };
  for (Line line; reader.Next(line);) {
    const std::string& k = line.Keyword();
    if (k == "newmtl") {
      finish();
      line.ExpectArguments(1, 64);
      const std::string name = line.Rest();
      if (byName.count(name)) line.Fail("material '" + name + "' defined twice");
      byName[name] = uint32_t(materials.size());
      current = MtlEntry{Material{name}, line};
      continue;
    }
    if (!current) line.Fail("'" + k + "' before any 'newmtl'");
    if (k == "Kd") {
      current->material.albedo = ReadRgb(line);
      current->hasKd = true;
    } else if (k == "map_Kd") {
      ReadAlbedoTexture(line, path, *current, textures);
    } else if (k == "Ke") {
      current->material.emission = ReadRgb(line);
    } else if (k == "Ks") {
      current->ks = ReadRgb(line);
    } else if (k == "Tf") {
      current->tf = ReadRgb(line);
    } else if (k == "Ka") {
      ReadRgb(line);
    } else if (k == "Ni" || k == "d" || k == "Tr" || k == "Ns") {
      line.ExpectArguments(1, 1);
      const float value = line.Number(1);
      if (k == "Ni") current->ni = value;
      if (k == "d") current->d = value;
      if (k == "Tr") current->d = 1.0f - value;  // Tr is the complement of d
    } else if (k == "illum") {
      line.ExpectArguments(1, 1);
      const float illum = line.Number(1);
      // Range first: casting a float beyond int's range (illum 3.4e34, found by fuzzing) is undefined.
      if (!(illum >= 0 && illum <= 10) || illum != std::floor(illum)) line.Fail("illum takes a whole number 0-10");
      current->illum = int(illum);
    } else if (k.rfind("map_", 0) == 0 || k == "bump" || k == "disp" || k == "refl") {
      warnings.push_back(line.Warning("'" + k + "' is ignored (of the texture maps, only map_Kd, the albedo, is used)"));
    } else {
      line.Fail("unknown MTL statement '" + k + "'");
    }
  }
  finish();
}

// Resolves field `field` (0: position, 1: texture coordinate) of one OBJ face corner "v", "v/t", "v//n" or
// "v/t/n" to a 0-based index among `count`; kNoTexcoord when a texture coordinate is absent.
uint32_t CornerIndex(const Line& line, const std::string& corner, int field, size_t count) {
  size_t start = 0;
  for (int f = 0; f < field; ++f) {
    start = corner.find('/', start);
    if (start == std::string::npos) return kNoTexcoord;
    ++start;
  }
  const std::string text = corner.substr(start, corner.find('/', start) - start);
  if (field > 0 && text.empty()) return kNoTexcoord;
  long index = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), index);
  if (ec != std::errc() || end != text.data() + text.size() || index == 0)
    line.Fail("malformed face index '" + corner + "'");
  const long resolved = index > 0 ? index - 1 : long(count) + index;
  const char* what = field == 0 ? "vertices" : "texture coordinates";
  if (resolved < 0 || resolved >= long(count))
    line.Fail("face index " + text + " is out of range (" + std::to_string(count) + " " + what + " so far)");
  return uint32_t(resolved);
}

using Position = std::array<double, 3>;  // world [m], as read

bool IsDegenerate(const Position& a, const Position& b, const Position& c) {
  // In double, so that slivers of aspect ratio up to ~1e9 are kept and only zero-area faces are dropped.
  const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
  const double twiceArea = std::sqrt(cx * cx + cy * cy + cz * cz);
  const double longest2 = std::max({e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2],
                                    e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]});
  return !(twiceArea > 1e-18 * longest2) || twiceArea == 0.0;
}

class ObjParser {
 public:
  ObjParser(const std::string& path, const LoadOptions& options) : path_(path), options_(options) {
    result_.scene.path = path;
    result_.scene.objectNames.push_back("");  // faces before any 'o'
  }

  LoadedScene Parse() {
    PB_CHECK(options_.scale > 0.0f && std::isfinite(options_.scale), "LoadOptions::scale is finite and > 0");
    LineReader reader(path_, "scene file");
    for (Line line; reader.Next(line);) Statement(line);
    if (result_.scene.triangles.empty()) throw InputError(path_, 0, "scene has no faces");
    StorePositions();
    return std::move(result_);
  }

 private:
  void Statement(const Line& line) {
    const std::string& k = line.Keyword();
    if (k == "v") {
      line.ExpectArguments(3, 7);  // x y z [w] or x y z r g b (vertex colours, ignored).
      const double s = options_.scale;
      positions_.push_back({line.Double(1) * s, line.Double(2) * s, line.Double(3) * s});
    } else if (k == "vn") {
      line.ExpectArguments(3, 3);
      for (size_t i = 1; i < line.tokens.size(); ++i) line.Number(i);
    } else if (k == "vt") {
      line.ExpectArguments(1, 3);
      result_.scene.texcoords.push_back({line.Number(1), line.tokens.size() > 2 ? line.Number(2) : 0.0f});
    } else if (k == "f") {
      Face(line);
    } else if (k == "usemtl") {
      line.ExpectArguments(1, 64);
      const auto it = materialByName_.find(line.Rest());
      if (it == materialByName_.end()) line.Fail("unknown material '" + line.Rest() + "'");
      currentMaterial_ = int(it->second);
    } else if (k == "mtllib") {
      line.ExpectArguments(1, 64);
      const std::string library = ResolveBeside(path_, line.Rest());
      LoadMtl(library, line, result_.scene.materials, materialByName_, result_.scene.textures, result_.warnings);
      result_.scene.materialLibraries.push_back(library);
    } else if (k == "o" || k == "g") {
      currentObject_ = uint32_t(result_.scene.objectNames.size());  // names surfaces in the report.
      result_.scene.objectNames.push_back(line.tokens.size() > 1 ? line.Rest() : std::string());
    } else if (k == "s") {
      // Smoothing groups: every surface is flat-shaded from its chart normal.
    } else if (k == "l" || k == "p") {
      result_.warnings.push_back(line.Warning("'" + k + "' (lines/points) is ignored"));
    } else {
      line.Fail("unknown OBJ statement '" + k + "'");
    }
  }

  void Face(const Line& line) {
    line.ExpectArguments(3, 1u << 16);
    if (currentMaterial_ < 0) line.Fail("face before any 'usemtl'; every face needs a material");
    Scene& scene = result_.scene;
    // Texture coordinates are read (and checked) only for textured materials; like normals, they are otherwise
    // unused.
    const bool textured = scene.materials[size_t(currentMaterial_)].albedoTexture >= 0;
    std::vector<uint32_t> corners, texcoords;
    for (size_t i = 1; i < line.tokens.size(); ++i) {
      corners.push_back(CornerIndex(line, line.tokens[i], 0, positions_.size()));
      texcoords.push_back(textured ? CornerIndex(line, line.tokens[i], 1, scene.texcoords.size()) : kNoTexcoord);
    }
    if (textured && std::count(texcoords.begin(), texcoords.end(), kNoTexcoord) > 0)
      line.Fail("material '" + scene.materials[size_t(currentMaterial_)].name +
                "' has a map_Kd texture, so every corner needs a texture coordinate (v/t)");
    for (size_t i = 1; i + 1 < corners.size(); ++i) {  // fan triangulation
      const Triangle t{{corners[0], corners[i], corners[i + 1]},
                       {texcoords[0], texcoords[i], texcoords[i + 1]},
                       uint32_t(currentMaterial_),
                       currentObject_,
                       uint32_t(line.number)};
      if (IsDegenerate(positions_[t.v[0]], positions_[t.v[1]], positions_[t.v[2]])) {
        ++scene.degenerateTrianglesSkipped;
        result_.warnings.push_back(line.Warning("zero-area triangle skipped"));
        continue;
      }
      if (const auto [it, isNew] = faceLines_.emplace(FaceKey(t), line.number); !isNew) {
        ++scene.duplicateTrianglesSkipped;
        result_.warnings.push_back(line.Warning("triangle repeats the one at line " + std::to_string(it->second) +
                                                " (same corners, same side); skipped"));
        continue;
      }
      scene.triangles.push_back(t);
    }
  }

  // The triangle's corner positions, rotated so that the smallest comes first: equal for the same triangle
  // facing the same way, whatever its vertex indices or starting corner; a back-to-back copy differs.
  using Key = std::array<Position, 3>;
  struct KeyHash {
    size_t operator()(const Key& k) const {
      size_t h = 0;
      for (const Position& p : k)
        for (double c : p) h = h * 1000003u ^ std::hash<double>()(c);
      return h;
    }
  };
  Key FaceKey(const Triangle& t) const {
    Key k{positions_[t.v[0]], positions_[t.v[1]], positions_[t.v[2]]};
    std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
    return k;
  }

  // Chooses the local origin (mesh/scene.h) and stores the positions relative to it, in float.
  void StorePositions() {
    Position lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const Position& p : positions_)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    double size = 0, distance = 0;
    Position centre{};
    for (int k = 0; k < 3; ++k) {
      centre[k] = 0.5 * (lo[k] + hi[k]);
      size = std::max(size, hi[k] - lo[k]);
      distance = std::max(distance, std::abs(centre[k]));
    }
    Scene& scene = result_.scene;
    if (distance > size) scene.origin = centre;
    scene.positions.reserve(positions_.size());
    for (const Position& p : positions_) {
      const Point3 local = scene.ToLocal(p[0], p[1], p[2]);
      if (!std::isfinite(local.x) || !std::isfinite(local.y) || !std::isfinite(local.z))
        throw InputError(path_, 0, "the scene spans more than a float can hold (about 3e38 m)");
      scene.positions.push_back(local);
    }
  }

  std::string path_;
  LoadOptions options_;
  LoadedScene result_;
  std::vector<Position> positions_;
  std::unordered_map<Key, int, KeyHash> faceLines_;  // each kept triangle -> its 'f' line
  std::unordered_map<std::string, uint32_t> materialByName_;
  int currentMaterial_ = -1;
  uint32_t currentObject_ = 0;
};

}  // namespace

LoadedScene LoadObj(const std::string& path, const LoadOptions& options) { return ObjParser(path, options).Parse(); }

}  // namespace pb
