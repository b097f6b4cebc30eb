// Camera files (mesh/camera.h) as hostile input (issue 16): a number that overflows double, a position beyond
// float's metres, and an `up` of any length are answered with the right reason, never an abort.
#include "mesh/camera.h"

#include <gtest/gtest.h>

#include "mesh/errors.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

std::string CameraFile(const std::string& dir, const std::string& position, const std::string& up) {
  const std::string path = dir + "/c.camera.json";
  test::WriteText(path, "{\"position_m\": " + position + ",\n \"look_at_m\": [0, 0, 0],\n \"up\": " + up +
                            ",\n \"vertical_fov_deg\": 40}\n");
  return path;
}

std::string Refusal(const std::string& path) {
  try {
    LoadCamera(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Camera, HostileNumbersAreRefusedForTheRightReason) {
  const std::string dir = test::TempDirectory("camera-hostile");
  EXPECT_NE(Refusal(CameraFile(dir, "[0, 0, 1e400]", "[0, 1, 0]")).find("unreadable JSON"), std::string::npos);
  EXPECT_NE(Refusal(CameraFile(dir, "[0, 0, 1e30]", "[0, 1, 0]")).find("c.camera.json:1: error: 'position_m' must "
                                                                        "hold finite numbers within 1e9 m"),
            std::string::npos);
  EXPECT_NE(Refusal(CameraFile(dir, "[0, 0, 5]", "[0, 0, 0]")).find("c.camera.json:3: error: 'up' is zero or parallel"),
            std::string::npos);
  EXPECT_NE(Refusal(CameraFile(dir, "[0, 0, 5]", "[0, 0, 1e30]")).find("'up' is zero or parallel"), std::string::npos);
  // Any length of a good `up` is a direction: huge and tiny both load, pointing the same way.
  for (const std::string up : {"[0, 1e30, 0]", "[0, 1e-30, 0]"}) {
    const Camera c = LoadCamera(CameraFile(dir, "[0, 0, 5]", up));
    EXPECT_FLOAT_EQ(c.up.y, 1.0f) << up;
  }
}

}  // namespace
}  // namespace pb
