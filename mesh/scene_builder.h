// What every scene loader does once it has read positions and faces: keeps world positions [m] in double while
// the file is read, drops zero-area triangles and exact repeats (counted in the Scene), and finally stores the
// positions in float about a local origin chosen for precision (mesh/scene.h, Scene::origin). Used by the OBJ and
// the glTF loader, so that both treat geometry alike.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "mesh/scene.h"

namespace pb {

using Position = std::array<double, 3>;  // world [m], as read

class SceneBuilder {
 public:
  explicit SceneBuilder(Scene& scene) : scene_(scene) {}

  uint32_t AddPosition(const Position& p) {
    positions_.push_back(p);
    return uint32_t(positions_.size() - 1);
  }
  const Position& position(size_t i) const { return positions_[i]; }
  size_t PositionCount() const { return positions_.size(); }

  // Why a triangle was not kept.
  enum class Skipped { kNone, kZeroArea, kRepeat };
  struct Outcome {
    Skipped skipped = Skipped::kNone;
    uint32_t repeatedTag = 0;  // for kRepeat: the tag of the kept triangle it repeats
  };
  // Appends t to the scene unless it has zero area or repeats a kept triangle (the same corner positions, facing
  // the same side; a back-to-back copy is kept). `tag` names where t came from (an OBJ line, a glTF primitive),
  // for the message about a later repeat of it.
  Outcome AddTriangle(const Triangle& t, uint32_t tag);

  // Chooses the local origin and stores every position relative to it in float, then drops the triangles whose
  // normal float cannot hold (counted as zero-area). InputError naming `path` when the scene spans more than
  // kMaxSceneSize.
  void StorePositions(const std::string& path);

  // The largest scene [m]: its triangles' area vectors (up to its size squared) keep a finite squared length in
  // float (about 3e38).
  static constexpr double kMaxSceneSize = 1e9;

 private:
  using Key = std::array<Position, 3>;
  struct KeyHash {
    size_t operator()(const Key& k) const;
  };
  Key FaceKey(const Triangle& t) const;
  void DropTrianglesWithoutAFloatNormal();

  Scene& scene_;
  std::vector<Position> positions_;
  std::unordered_map<Key, uint32_t, KeyHash> kept_;  // each kept triangle -> its tag
};

}  // namespace pb
