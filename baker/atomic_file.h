// Writes an output file so that readers never see it half-written: the bytes go to "<path>.tmp-<pid>" in the
// same directory, are flushed, and the file is renamed over `path` only when complete. On any failure the
// temporary file is removed, an existing file at `path` is left untouched, and an InputError names the path.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace pb {

void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// Throws an InputError naming `path` unless its directory exists and is writable. Called before long work,
// so that a typo in an output path fails in a second, not after the bake.
void RequireWritableLocation(const std::string& path);

}  // namespace pb
