#include "mesh/obj_loader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "mesh/errors.h"
#include "mesh/input_file.h"
#include "mesh/mtl_loader.h"
#include "mesh/polygon.h"
#include "mesh/scene_builder.h"
#include "mesh/text_lines.h"

namespace pb {
namespace {

// Resolves field `field` (0: position, 1: texture coordinate, 2: normal) of one OBJ face corner "v", "v/t", "v//n" or
// "v/t/n" to a 0-based index among `count`; kNoTexcoord when a texture coordinate or normal is absent.
uint32_t CornerIndex(const TextLine& line, const std::string& corner, int field, size_t count) {
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
  const char* what = field == 0 ? "vertex" : field == 1 ? "texture coordinate" : "normal";
  const char* plural = field == 0 ? "vertices" : field == 1 ? "texture coordinates" : "normals";
  if (resolved < 0 || resolved >= long(count))
    line.Fail(std::string(what) + " index " + text + " is out of range (" + std::to_string(count) + " " +
              (count == 1 ? what : plural) + " so far)");
  return uint32_t(resolved);
}

// OBJ statements that describe no polygon mesh: free-form curves and surfaces, and display or render hints.
bool IsFreeForm(const std::string& k) {
  for (const char* word : {"cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrp",
                           "sp", "end", "con", "vp"})
    if (k == word) return true;
  return false;
}
bool IsDisplayHint(const std::string& k) {
  for (const char* word : {"mg", "lod", "bevel", "c_interp", "d_interp", "shadow_obj", "trace_obj", "ctech", "stech",
                           "maplib", "usemap", "call", "csh", "vw"})
    if (k == word) return true;
  return false;
}

class ObjParser {
 public:
  ObjParser(const std::string& path, const LoadOptions& options)
      : path_(path), options_(options), builder_(result_.scene) {
    result_.scene.path = path;
    result_.scene.objectNames.push_back("");  // faces before any 'o'
  }

  LoadedScene Parse() {
    PB_CHECK(options_.scale > 0.0f && std::isfinite(options_.scale), "LoadOptions::scale is finite and > 0");
    TextFileReader reader(path_, "scene file");
    size_t told = 0, statements = 0;
    for (TextLine line; reader.Next(line);) {
      Statement(line);
      if (options_.progress && ++statements % 65536 == 0)
        options_.progress(reader.Position() - told, reader.Size()), told = reader.Position();
    }
    if (options_.progress) options_.progress(reader.Size() - told, reader.Size());
    builder_.StorePositions(path_);
    if (result_.scene.triangles.empty()) RefuseEmpty();
    result_.warnings = warnings_.Lines();
    return std::move(result_);
  }

 private:
  void Statement(const TextLine& line) {
    const std::string& k = line.Keyword();
    if (k == "v") {
      line.ExpectValues(3, 7);  // x y z [w] or x y z r g b (vertex colours, ignored).
      const double s = options_.scale;
      builder_.AddPosition({line.Double(1) * s, line.Double(2) * s, line.Double(3) * s});
    } else if (k == "vn") {
      line.ExpectValues(3, 3);
      for (size_t i = 1; i < line.tokens.size(); ++i) line.Number(i);
      ++normalCount_;
    } else if (k == "vt") {
      line.ExpectValues(1, 3);
      result_.scene.texcoords.push_back({line.Number(1), line.ValueCount() > 1 ? line.Number(2) : 0.0f});
    } else if (k == "f") {
      Face(line);
    } else if (k == "usemtl") {
      UseMaterial(line);
    } else if (k == "mtllib") {
      MaterialLibraries(line);
    } else if (k == "o" || k == "g") {
      currentObject_ = uint32_t(result_.scene.objectNames.size());  // names surfaces in the report.
      result_.scene.objectNames.push_back(line.Name());
    } else if (k == "s") {
      // Smoothing groups: every surface is flat-shaded from its chart normal.
    } else {
      Ignored(line);
    }
  }

  // What the baker does not read, with one warning per kind; the first line of each is kept for the message
  // that refuses a file without faces.
  void Ignored(const TextLine& line) {
    const std::string& k = line.Keyword();
    std::string kind, message;
    if (k == "l" || k == "p") {
      kind = "lines and points", message = "'" + k + "' (lines and points have no area to bake) is ignored";
    } else if (IsFreeForm(k)) {
      kind = "free-form", message = "free-form geometry ('" + k + "', cstype ... end) is not baked; ignored";
    } else if (IsDisplayHint(k)) {
      kind = "hint " + k, message = "'" + k + "' is ignored";
    } else {
      kind = "unknown " + k, message = "unknown OBJ statement '" + k + "' is ignored";
    }
    if (kind == "lines and points" || kind == "free-form") firstIgnored_.emplace(kind, line.number);
    warnings_.Add(kind, line.Warning(message));
  }

  // mtllib: one or more files, names with spaces written as "\ "; a name as a whole is tried first, since some
  // exporters write spaces unescaped. A library that cannot be found is a warning: its materials fall back to
  // the default.
  void MaterialLibraries(const TextLine& line) {
    if (line.rest.empty()) return warnings_.Add("empty mtllib", line.Warning("'mtllib' names no file; ignored"));
    std::vector<std::string> names{line.rest};
    if (!FindNamedFile(path_, line.rest)) names = SplitEscaped(line.rest);
    for (const std::string& name : names) {
      const std::optional<std::string> library = FindNamedFile(path_, name);
      if (!library) {
        warnings_.Add("missing mtllib", line.Warning("material library '" + name + "' not found; its materials " +
                                                     "fall back to grey Kd 0.8"));
        continue;
      }
      if (std::find(libraries().begin(), libraries().end(), *library) != libraries().end()) continue;
      try {
        LoadMtl(*library, {result_.scene.materials, materialByName_, result_.scene.textures, warnings_});
      } catch (const InputError& e) {
        if (e.line() > 0) throw;
        line.Fail(e.message() + " ('" + *library + "')");
      }
      libraries().push_back(*library);
    }
  }
  std::vector<std::string>& libraries() { return result_.scene.materialLibraries; }

  void UseMaterial(const TextLine& line) {
    const auto it = materialByName_.find(line.Name());
    if (it != materialByName_.end()) {
      currentMaterial_ = int(it->second);
      return;
    }
    warnings_.Add("unknown material", line.Warning("material '" + line.Name() + "' is defined by no material " +
                                                   "library; its faces are grey Kd 0.8"));
    currentMaterial_ = int(DefaultMaterial());
  }

  // Faces before any usemtl, or with a material no library defines: diffuse grey, as Blender shows them.
  uint32_t DefaultMaterial() {
    if (!defaultMaterial_) {
      Material m{"(default)"};
      m.albedo = {kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo};
      defaultMaterial_ = uint32_t(result_.scene.materials.size());
      result_.scene.materials.push_back(m);
    }
    return *defaultMaterial_;
  }

  void Face(const TextLine& line) {
    if (line.ValueCount() < 3) {
      if (!firstIgnored_.count("short face")) firstIgnored_["short face"] = line.number;
      return warnings_.Add("short face", line.Warning("a face of " + std::to_string(line.ValueCount()) +
                                                      " corners has no area; skipped"));
    }
    line.ExpectValues(3, 1u << 16);
    if (currentMaterial_ < 0) {
      warnings_.Add("no usemtl", line.Warning("faces before any 'usemtl' are grey Kd 0.8"));
      currentMaterial_ = int(DefaultMaterial());
    }
    Scene& scene = result_.scene;
    // Texture coordinates are kept only for textured materials (normals never are).
    const bool textured = scene.materials[size_t(currentMaterial_)].albedoTexture >= 0;
    std::vector<uint32_t>& corners = corners_;  // reused from face to face
    std::vector<uint32_t>& texcoords = texcoords_;
    corners.clear(), texcoords.clear();
    for (size_t i = 1; i < line.tokens.size(); ++i) {
      corners.push_back(CornerIndex(line, line.tokens[i], 0, builder_.PositionCount()));
      texcoords.push_back(textured ? CornerIndex(line, line.tokens[i], 1, scene.texcoords.size()) : kNoTexcoord);
    }
    if (!textured) CheckUnusedIndices(line, 1, scene.texcoords.size());
    CheckUnusedIndices(line, 2, normalCount_);
    uint32_t material = uint32_t(currentMaterial_);
    if (textured && std::count(texcoords.begin(), texcoords.end(), kNoTexcoord) > 0) {
      material = Untextured(line, material);
      std::fill(texcoords.begin(), texcoords.end(), kNoTexcoord);
    }
    const auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
      AddTriangle(line, Triangle{{corners[a], corners[b], corners[c]},
                                 {texcoords[a], texcoords[b], texcoords[c]},
                                 material,
                                 currentObject_,
                                 uint32_t(line.number)});
    };
    if (corners.size() == 3) return add(0, 1, 2);  // what TriangulatePolygon gives a triangle, without its arrays
    for (const auto& [a, b, c] : Triangulate(line, corners)) add(a, b, c);
  }

  // A face of a textured material without texture coordinates (Blender's exporter keeps the last usemtl for the
  // next object, which may have no UV map): it gets the material with its texture averaged, Kd x the image's mean.
  uint32_t Untextured(const TextLine& line, uint32_t textured) {
    Scene& scene = result_.scene;
    const uint32_t variant = UntexturedVariant(scene, textured, untextured_);
    warnings_.Add("no texcoords", line.Warning("material '" + scene.materials[textured].name +
                                               "' has a map_Kd texture, but the face has no texture coordinates "
                                               "(v/t): it gets Kd times the texture's mean"));
    return variant;
  }

  // Normals are never used (surfaces are shaded from their charts), nor are texture coordinates without a
  // texture, so an index of theirs out of range is a warning, as in every other reader; a malformed one is still an
  // error.
  void CheckUnusedIndices(const TextLine& line, int field, size_t count) {
    for (size_t i = 1; i < line.tokens.size(); ++i) {
      try {
        CornerIndex(line, line.tokens[i], field, count);
      } catch (const InputError& e) {
        if (e.message().find("out of range") == std::string::npos) throw;
        return warnings_.Add(field == 1 ? "texcoord index" : "normal index",
                             line.Warning(e.message() + (field == 1 ? "; the face has no texture, so they are not used"
                                                                    : "; normals are not used")));
      }
    }
  }

  std::vector<std::array<uint32_t, 3>> Triangulate(const TextLine& line, const std::vector<uint32_t>& corners) {
    std::vector<PolygonCorner> polygon;
    for (uint32_t c : corners) polygon.push_back(builder_.position(c));
    PolygonTriangulation cut = TriangulatePolygon(polygon);
    if (cut.irregular)
      warnings_.Add("irregular polygon", line.Warning("a polygon whose edges cross itself was cut as well as it "
                                                      "can be; its triangles may overlap"));
    return std::move(cut.triangles);
  }

  void AddTriangle(const TextLine& line, const Triangle& t) {
    const SceneBuilder::Outcome added = builder_.AddTriangle(t, uint32_t(line.number));
    if (added.skipped == SceneBuilder::Skipped::kZeroArea)
      warnings_.Add("zero-area", line.Warning("zero-area triangle skipped"));
    if (added.skipped == SceneBuilder::Skipped::kRepeat)
      warnings_.Add("repeat", line.Warning("triangle repeats the one at line " + std::to_string(added.repeatedTag) +
                                           " (same corners, same side); skipped"));
  }

  // A scene with no face to bake is refused, naming what it had instead.
  [[noreturn]] void RefuseEmpty() const {
    for (const auto& [kind, why] : {std::pair{"short face", "its faces have fewer than 3 corners"},
                                    std::pair{"lines and points", "it has only lines and points ('l', 'p')"},
                                    std::pair{"free-form", "it has only free-form curves and surfaces"}})
      if (firstIgnored_.count(kind))
        throw InputError(path_, firstIgnored_.at(kind), std::string("scene has no faces to bake: ") + why);
    if (result_.scene.degenerateTrianglesSkipped > 0)
      throw InputError(path_, 0, "scene has no faces to bake: every face has zero area");
    throw InputError(path_, 0, "scene has no faces");
  }

  std::string path_;
  LoadOptions options_;
  LoadedScene result_;
  SceneBuilder builder_;
  std::unordered_map<std::string, uint32_t> materialByName_;
  std::optional<uint32_t> defaultMaterial_;
  std::unordered_map<uint32_t, uint32_t> untextured_;  // textured material -> its untextured variant
  std::unordered_map<std::string, int> firstIgnored_;  // kind of ignored statement -> its first line
  WarningLog warnings_;
  size_t normalCount_ = 0;
  std::vector<uint32_t> corners_, texcoords_;  // Face's, kept to reuse their memory
  int currentMaterial_ = -1;
  uint32_t currentObject_ = 0;
};

}  // namespace

LoadedScene LoadObj(const std::string& path, const LoadOptions& options) { return ObjParser(path, options).Parse(); }

}  // namespace pb
