// Input files as a baker meets them in a pipeline: written by other programs, sometimes hostile. Only regular
// files are read (a FIFO would hang the bake, /dev/zero would read until memory runs out, a folder gives a
// misleading message), and text files may carry a UTF-8 byte order mark, CR, LF or CRLF line ends, but no NUL.
#pragma once

#include <cstdint>
#include <string>

namespace pb {

// The file's size in bytes. InputError(path) naming `what` ("scene file", "texture", ...) when it cannot be
// opened or is not a regular file.
uint64_t RequireRegularFile(const std::string& path, const std::string& what);

}  // namespace pb
