// Input files as a baker meets them in a pipeline: written by other programs, sometimes hostile. Only regular
// files are read (a FIFO would hang the bake, /dev/zero would read until memory runs out, a folder gives a
// misleading message), and text files may carry a UTF-8 byte order mark, CR, LF or CRLF line ends, but no NUL.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace pb {

// The file's size in bytes. InputError(path) naming `what` ("scene file", "texture", ...) when it cannot be
// opened or is not a regular file.
uint64_t RequireRegularFile(const std::string& path, const std::string& what);

// The whole file's bytes, after RequireRegularFile. InputError naming `what` when it cannot be read.
std::string ReadRegularFile(const std::string& path, const std::string& what);

// The file that `name`, written in the file `from` (an 'mtllib' or 'map_Kd' argument), refers to, found as other
// programs write such names:
//   1. as given: an absolute path, or a path relative to the folder of `from`;
//   2. with '\' read as '/' (Windows exporters);
//   3. with letter case that differs from the names on disk, component by component (Windows and macOS file
//      systems ignore case, so files exported there often do);
//   4. for a path that leads nowhere (an absolute path from another machine, or a folder not shipped), the file
//      of that last name in the folder of `from`.
// The first that is an existing file, and in `how` which rule found it (1-4); nullopt when none does.
std::optional<std::string> FindNamedFile(const std::string& from, const std::string& name, int* how = nullptr);

}  // namespace pb
