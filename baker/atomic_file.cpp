#include "baker/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "mesh/errors.h"

namespace pb {

void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string temporary = path + ".tmp-" + std::to_string(getpid());
  try {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, 0, "cannot create output file: " + std::string(std::strerror(errno)));
    write(out);
    out.flush();
    if (!out) throw InputError(path, 0, "write failed: " + std::string(std::strerror(errno)));
    out.close();
    if (std::rename(temporary.c_str(), path.c_str()) != 0)
      throw InputError(path, 0, "cannot move output into place: " + std::string(std::strerror(errno)));
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

void RequireWritableLocation(const std::string& path) {
  if (path.empty()) throw InputError("<output>", 0, "no output path given");
  const size_t slash = path.find_last_of('/');
  const std::string directory = slash == std::string::npos ? "." : path.substr(0, slash + 1);
  if (access(directory.c_str(), W_OK) != 0)
    throw InputError(path, 0, "cannot write here: " + std::string(std::strerror(errno)));
}

}  // namespace pb
