// What the libFuzzer targets (tests/fuzz/*_fuzz.cpp) share: the readers under test read files, so each input is
// written to a file in a directory of this process's own, and read back from there. A reader must either accept
// an input or refuse it with an InputError; any other exception, a crash, a leak or undefined behaviour is a bug.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

#include "mesh/errors.h"

namespace pb::fuzz {

// A directory of this process's own, made on first use and removed when the process exits (libFuzzer's timed run
// ends by exit; after a finding, the input is in the artifact, and the directory is left).
inline void RemoveDirectory();
inline const std::string& Directory() {
  static const std::string dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("photonbake-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  // Registered after `dir` is made, so that it runs at exit before `dir` is destroyed.
  [[maybe_unused]] static const bool removedAtExit = std::atexit(RemoveDirectory) == 0;
  return dir;
}
inline void RemoveDirectory() {
  std::error_code ignored;
  std::filesystem::remove_all(Directory(), ignored);
}

// Writes `bytes` to Directory()/name and returns its path.
inline std::string WriteInput(const std::string& name, std::string_view bytes) {
  const std::string path = Directory() + "/" + name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
  return path;
}

inline std::string_view Bytes(const uint8_t* data, size_t size) { return {reinterpret_cast<const char*>(data), size}; }

// Runs `read`, accepting an InputError: the expected refusal of malformed input, with a message naming the file.
template <typename F>
void ReadOrRefuse(F&& read) {
  try {
    read();
  } catch (const InputError&) {
  }
}

}  // namespace pb::fuzz
