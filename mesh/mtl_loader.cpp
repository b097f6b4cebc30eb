#include "mesh/mtl_loader.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "mesh/errors.h"
#include "mesh/input_file.h"
#include "mesh/texture.h"

namespace pb {
namespace {

// The statements of one MTL material as written, before its class is decided (illum and the values it uses).
struct MtlEntry {
  Material material;
  TextLine start;  // the 'newmtl' line, for messages
  bool hasKd = false;
  bool textureMissing = false;   // map_Kd names a file that does not exist
  Rgb textureMaximum{1, 1, 1};  // of its map_Kd, for the reflectance cap
  int illum = 2;
  std::optional<Rgb> ks, tf;
  std::optional<InputError> ksError;  // a malformed Ks: an error only if the material is a mirror
  std::optional<float> ni, d;
};

Rgb ReadRgb(const TextLine& line) {
  line.ExpectValues(1, 3);
  const float r = line.Number(1);
  if (line.ValueCount() == 1) return {r, r, r};  // "Kd 0.5" is grey, as in the MTL spec.
  line.ExpectValues(3, 3);
  return {r, line.Number(2), line.Number(3)};
}

// The first value of a scalar statement; further values are ignored with a warning ("Tr 0  illum 2", as the
// McGuire archive writes).
float ReadScalar(const TextLine& line, WarningLog& warnings) {
  line.ExpectValues(1, 64);
  if (line.ValueCount() > 1)
    warnings.Add("extra values", line.Warning("'" + line.Keyword() + "' takes one value; the rest ('" +
                                              line.JoinValues(2) + "') is ignored"));
  return line.Number(1);
}

bool InUnitInterval(Rgb c) { return c.r >= 0 && c.g >= 0 && c.b >= 0 && c.r <= 1 && c.g <= 1 && c.b <= 1; }

// Caps Kd and Ks together at kMaxReflectance (mesh/scene.h), with a warning.
void CapReflectance(Material& m, Rgb textureMaximum, const TextLine& where, WarningLog& warnings) {
  const std::optional<float> total = CapReflectance(m, textureMaximum);
  if (!total) return;
  warnings.Add("reflectance cap " + m.name,
               where.Warning("material '" + m.name + "': reflectance " + std::to_string(*total).substr(0, 5) +
                             " capped at 0.99, since a surface that absorbs nothing never ends a path in a closed scene"));
}

MaterialClass ClassOfIllum(int illum) {
  switch (illum) {
    case 3: case 5: case 8: return MaterialClass::kMirror;
    case 4: case 6: case 7: case 9: return MaterialClass::kGlass;
    default: return MaterialClass::kDiffuse;
  }
}

void ResolveMirror(MtlEntry& e, const std::string& named, WarningLog& warnings) {
  Material& m = e.material;
  if (e.ksError) throw *e.ksError;
  m.specular = e.ks.value_or(Rgb{1, 1, 1});
  if (!InUnitInterval(m.specular)) e.start.Fail(named + "a mirror needs Ks in [0, 1] per channel");
  if (InUnitInterval(m.albedo + m.specular)) return;
  // Blender writes illum 3, Kd 0.8, Ks 0.5 for any metal: a mirror that would reflect more than arrives.
  warnings.Add("metal as diffuse",
               e.start.Warning(named + "illum " + std::to_string(e.illum) +
                               " with Kd + Ks > 1 (as Blender writes metals) would reflect more light than arrives; "
                               "baked as its diffuse part Kd"));
  m.kind = MaterialClass::kDiffuse;
  m.specular = {};
}

void ResolveGlass(MtlEntry& e, const std::string& named, WarningLog& warnings) {
  Material& m = e.material;
  m.ior = e.ni.value_or(1.5f);
  if (!(m.ior > 0.0f && m.ior <= 10.0f)) e.start.Fail(named + "glass needs Ni in (0, 10]");
  const float d = e.d.value_or(0.0f);
  m.transmittance = e.tf.value_or(Rgb{1 - d, 1 - d, 1 - d});
  if (!InUnitInterval(m.transmittance) || d < 0 || d > 1) e.start.Fail(named + "glass needs Tf and d in [0, 1]");
  if (m.transmittance.IsBlack())
    warnings.Add("opaque glass", e.start.Warning(named + "glass transmits nothing (d 1 and no Tf); set Tf or d < 1"));
  if (!m.albedo.IsBlack()) warnings.Add("glass Kd", e.start.Warning(named + "Kd is not used by glass"));
  m.albedo = {};
}

// Turns the statements of one material into a checked Material of its class (see mtl_loader.h).
Material ResolveMaterial(MtlEntry e, WarningLog& warnings) {
  Material& m = e.material;
  const std::string named = "material '" + m.name + "': ";
  if (!InUnitInterval(m.albedo)) e.start.Fail(named + "Kd must lie in [0, 1] per channel (energy conservation)");
  if (m.emission.r < 0 || m.emission.g < 0 || m.emission.b < 0) e.start.Fail(named + "Ke must be non-negative");
  if (e.illum > 9)
    warnings.Add("illum 10", e.start.Warning(named + "illum " + std::to_string(e.illum) + " is baked as diffuse Kd"));
  m.kind = ClassOfIllum(e.illum);
  if (m.kind == MaterialClass::kMirror) ResolveMirror(e, named, warnings);
  if (m.kind == MaterialClass::kGlass) ResolveGlass(e, named, warnings);
  if (m.albedoTexture >= 0 && !e.hasKd) m.albedo = {1, 1, 1};  // map_Kd alone: the texture is the albedo
  if (e.textureMissing && !e.hasKd) m.albedo = Rgb{kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo};
  CapReflectance(m, e.textureMaximum, e.start, warnings);
  return m;
}

// What a map_Kd option takes: up to `values` values (-s, -o and -t take one to three), numbers or words
// (on/off, a channel, a name); values 0 for an unknown option.
struct OptionShape {
  int values = 0;
  bool numeric = true;
};
OptionShape ShapeOf(const std::string& option) {
  if (option == "-s" || option == "-o" || option == "-t") return {3, true};
  if (option == "-mm") return {2, true};
  for (const char* number : {"-boost", "-bm", "-cc", "-texres"})
    if (option == number) return {1, true};
  for (const char* word : {"-blendu", "-blendv", "-clamp", "-imfchan", "-type", "-colorspace"})
    if (option == word) return {1, false};
  return {};
}

bool IsNumber(const std::string& token) {
  char* end = nullptr;
  std::strtod(token.c_str(), &end);
  return !token.empty() && end == token.c_str() + token.size();
}

// map_Kd's options (MTL spec: "-s u v w", "-o u v w", "-clamp on|off" and others) before its file name. -s, -o
// and -clamp are kept in the material; the rest are ignored with a warning. Returns the index of the first token
// of the file name.
size_t ReadTextureOptions(const TextLine& line, Material& m, WarningLog& warnings) {
  size_t i = 1;
  while (i < line.tokens.size() && line.tokens[i].size() > 1 && line.tokens[i][0] == '-' && !IsNumber(line.tokens[i])) {
    const std::string& option = line.tokens[i++];
    const auto [most, numeric] = ShapeOf(option);
    if (most == 0) {
      warnings.Add("map_Kd option", line.Warning("unknown map_Kd option '" + option + "' is ignored"));
      continue;
    }
    std::vector<float> values;
    while (i < line.tokens.size() && int(values.size()) < most && (!numeric || IsNumber(line.tokens[i]))) {
      values.push_back(numeric ? line.Number(i) : 0.0f);
      if (option == "-clamp") m.textureClamp = line.tokens[i] == "on";
      ++i;
    }
    if (values.empty()) line.Fail("map_Kd option '" + option + "' needs a value");
    if (option == "-s") m.textureScale = {values[0], values.size() > 1 ? values[1] : 1.0f};
    if (option == "-o") m.textureOffset = {values[0], values.size() > 1 ? values[1] : 0.0f};
    if (option != "-s" && option != "-o" && option != "-clamp")
      warnings.Add("map_Kd option " + option, line.Warning("map_Kd option '" + option + "' is ignored"));
  }
  if (i >= line.tokens.size()) line.Fail("map_Kd names no file");
  return i;
}

// map_Kd [options] FILE: the albedo texture, found beside the MTL file as exporters name it.
void ReadAlbedoTexture(const TextLine& line, const std::string& mtlPath, MtlEntry& entry, MaterialTable& table) {
  line.ExpectValues(1, 1u << 10);
  const size_t first = ReadTextureOptions(line, entry.material, table.warnings);
  std::string name = line.JoinValues(first);
  const std::vector<std::string> unescaped = SplitEscaped(name);
  if (unescaped.size() == 1) name = unescaped[0];  // "texture\ 01.png"
  int how = 0;
  const std::optional<std::string> file = FindNamedFile(mtlPath, name, &how);
  if (!file) {
    table.warnings.Add("texture not found", line.Warning("texture '" + name + "' not found; material '" +
                                                         entry.material.name + "' keeps its Kd"));
    entry.textureMissing = true;
    return;
  }
  if (how > 1)
    table.warnings.Add("texture path", line.Warning("texture '" + name + "' read as '" + *file + "'"));
  // A texture that several materials share is decoded once.
  const auto same = [&](const Texture& t) { return t.path == *file; };
  const size_t index = size_t(std::find_if(table.textures.begin(), table.textures.end(), same) - table.textures.begin());
  if (index == table.textures.size()) {
    try {
      table.textures.push_back(LoadTexture(*file));
    } catch (const InputError& e) {
      line.Fail(e.message() + " ('" + *file + "')");
    }
  }
  entry.material.albedoTexture = int(index);
  entry.textureMaximum = table.textures[index].maximum;
}

// Statements a diffuse baker has no use for: read over, with one warning per keyword.
bool IsUnused(const std::string& k) {
  for (const char* unused : {"Kt", "Km", "sharpness", "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor",
                             "norm", "bump", "disp", "decal", "refl"})
    if (k == unused) return true;
  return k.rfind("map_", 0) == 0;
}

// Reads a value that only some classes use (Ks, for mirrors) or none does (Ka, Ns): a malformed one is a warning,
// kept in `deferred` (when given) to become the error if the class turns out to use it.
template <typename Read>
void ReadUnlessUnused(const TextLine& line, WarningLog& warnings, Read read,
                      std::optional<InputError>* deferred = nullptr) {
  try {
    read();
  } catch (const InputError& e) {
    warnings.Add("malformed " + line.Keyword(), line.Warning(e.message() + ", which is not used" +
                                                  (deferred ? " unless the material is a mirror" : "")));
    if (deferred) deferred->emplace(e);
  }
}

// One statement of the material being read.
void ReadStatement(const TextLine& line, const std::string& path, MtlEntry& entry, MaterialTable& table) {
  const std::string& k = line.Keyword();
  if (k == "Kd") {
    entry.material.albedo = ReadRgb(line);
    entry.hasKd = true;
  } else if (k == "map_Kd") {
    ReadAlbedoTexture(line, path, entry, table);
  } else if (k == "Ke") {
    entry.material.emission = ReadRgb(line);
  } else if (k == "Ks") {
    ReadUnlessUnused(line, table.warnings, [&] { entry.ks = ReadRgb(line); }, &entry.ksError);
  } else if (k == "Ka" || k == "Ns") {  // Phong terms a diffuse baker does not use: only checked
    ReadUnlessUnused(line, table.warnings, [&] { k == "Ka" ? void(ReadRgb(line)) : void(ReadScalar(line, table.warnings)); });
  } else if (k == "Tf") {
    entry.tf = ReadRgb(line);
  } else if (k == "Ni") {
    entry.ni = ReadScalar(line, table.warnings);
  } else if (k == "d") {
    entry.d = ReadScalar(line, table.warnings);
  } else if (k == "Tr") {
    entry.d = 1.0f - ReadScalar(line, table.warnings);  // Tr is the complement of d
  } else if (k == "illum") {
    const float illum = ReadScalar(line, table.warnings);
    // Range first: casting a float beyond int's range (illum 3.4e34, found by fuzzing) is undefined.
    if (!(illum >= 0 && illum <= 10) || illum != std::floor(illum)) line.Fail("illum takes a whole number 0-10");
    entry.illum = int(illum);
  } else if (IsUnused(k)) {
    const bool texture = k.rfind("map_", 0) == 0 || k == "bump" || k == "disp" || k == "decal" || k == "refl";
    table.warnings.Add("unused " + k, line.Warning("'" + k + "' is ignored" +
                                                   (texture ? " (of the texture maps, only map_Kd, the albedo, is used)"
                                                            : " (a diffuse baker does not use it)")));
  } else {
    table.warnings.Add("unknown " + k, line.Warning("unknown MTL statement '" + k + "' is ignored"));
  }
}

}  // namespace

void LoadMtl(const std::string& path, MaterialTable table) {
  TextFileReader reader(path, "material library");
  std::optional<MtlEntry> current;
  auto finish = [&] {
    if (current) table.materials.push_back(ResolveMaterial(std::move(*current), table.warnings));
  };
  for (TextLine line; reader.Next(line);) {
    if (line.Keyword() == "newmtl") {
      finish();
      const std::string name = line.Name();  // may be empty: a material named ""
      if (table.byName.count(name)) line.Fail("material '" + name + "' defined twice");
      table.byName[name] = uint32_t(table.materials.size());
      current = MtlEntry{Material{name}, line};
    } else if (!current) {
      table.warnings.Add("before newmtl", line.Warning("'" + line.Keyword() + "' before any 'newmtl' is ignored"));
    } else {
      ReadStatement(line, path, *current, table);
    }
  }
  finish();
}

}  // namespace pb
