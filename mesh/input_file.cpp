#include "mesh/input_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include "mesh/errors.h"

namespace pb {

uint64_t RequireRegularFile(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, 0, "cannot open " + what + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw InputError(path, 0, "cannot open " + what + ": it is a folder");
  if (!S_ISREG(st.st_mode))
    throw InputError(path, 0, "cannot open " + what + ": not a regular file (a device, FIFO or socket)");
  return uint64_t(st.st_size);
}

}  // namespace pb
