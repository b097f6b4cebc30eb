// Closed-form test scenes written as OBJ + MTL into a fresh temporary directory, and small helpers to load them.
// All lengths in metres, radiance in W/(m^2 sr).
#pragma once

#include <string>

namespace pb::test {

// A fresh, empty directory under the system temp dir, unique to this process and `name`.
std::string TempDirectory(const std::string& name);

// Writes `text` to `path` (overwriting).
void WriteText(const std::string& path, const std::string& text);

// A square light of side `lightSide` and radiance `radiance` (grey), facing down at height `height`, centred
// over a black (Kd 0) square floor of side `floorSide` in the plane y = 0, both centred on the y axis.
// The floor is cut into `floorCells` x `floorCells` quads. Returns the OBJ path.
std::string WriteSquareLightOverFloor(const std::string& directory, float lightSide, float radiance, float height,
                                      float floorSide, int floorCells);

// A closed cube of side `side` whose six inward-facing walls have grey albedo `albedo`, with a small square
// light of side `lightSide` and radiance `radiance` facing down just below the ceiling. Returns the OBJ path.
std::string WriteClosedBox(const std::string& directory, float side, float albedo, float lightSide, float radiance);

}  // namespace pb::test
