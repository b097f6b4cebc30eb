// A scene file, whatever its format: what every loader takes (LoadOptions) and gives (LoadedScene), which format
// a path names, and the one dispatch, LoadScene, to the OBJ reader (mesh/obj_loader.h) or the glTF 2.0 reader
// (mesh/gltf_loader.h). Positions come out in metres: the file's units times LoadOptions::scale.
#pragma once

#include <string>
#include <vector>

#include "mesh/scene.h"
#include "mesh/work_progress.h"

namespace pb {

struct LoadOptions {
  float scale = 1.0f;  // metres per scene unit; range (0, inf), checked by the caller; typical 1 or 0.001.
  double luminousEfficacy = 683;  // [lm/W]: glTF's photometric lights (candela, lux) to watts
  WorkProgress progress;  // when given: the OBJ's bytes as they are parsed (a glTF file is read by tinygltf at once)
};

struct LoadedScene {
  Scene scene;
  std::vector<std::string> warnings;  // "file:line: warning: ..." lines, one per kind, in order of first appearance.
};

// True when the name ends in .gltf or .glb, in any case; IsBinaryGltfPath: in .glb. For outputs as for inputs.
bool HasGltfExtension(const std::string& path);
bool IsBinaryGltfPath(const std::string& path);
// True when HasGltfExtension, or the file is a regular file whose first bytes are those of a binary glTF (.glb).
bool IsGltfFile(const std::string& path);

// The scene in `path`: glTF (IsGltfFile) or else OBJ. Errors: InputError naming file:line (mesh/errors.h).
LoadedScene LoadScene(const std::string& path, const LoadOptions& options = {});

}  // namespace pb
