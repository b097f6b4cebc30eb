#include "mesh/input_file.h"

#include <sys/stat.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "mesh/errors.h"

namespace pb {
namespace {

namespace fs = std::filesystem;

bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec) && !fs::is_directory(p, ec);
}

std::string Lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// `path` with each component that does not exist replaced by the folder's entry that equals it ignoring case.
std::optional<fs::path> MatchIgnoringCase(const fs::path& path) {
  fs::path at = path.is_absolute() ? path.root_path() : fs::path(".");
  for (const fs::path& part : path.relative_path()) {
    std::error_code ec;
    if (part == "." || part == ".." || fs::exists(at / part, ec)) {
      at /= part;
      continue;
    }
    std::optional<fs::path> found;
    for (fs::directory_iterator it(at, ec), end; !ec && it != end; it.increment(ec))
      if (Lower(it->path().filename().string()) == Lower(part.string())) {
        found = it->path().filename();
        break;
      }
    if (!found) return std::nullopt;
    at /= *found;
  }
  return at;
}

}  // namespace

uint64_t RequireRegularFile(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, 0, "cannot open " + what + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw InputError(path, 0, "cannot open " + what + ": it is a folder");
  if (!S_ISREG(st.st_mode))
    throw InputError(path, 0, "cannot open " + what + ": not a regular file (a device, FIFO or socket)");
  return uint64_t(st.st_size);
}

std::string ReadRegularFile(const std::string& path, const std::string& what) {
  const uint64_t size = RequireRegularFile(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open " + what + ": " + std::strerror(errno));
  std::string bytes(size, '\0');
  in.read(bytes.data(), std::streamsize(size));
  if (uint64_t(in.gcount()) != size) throw InputError(path, 0, "cannot read " + what + ": it changed while being read");
  return bytes;
}

}  // namespace pb

namespace pb {

std::optional<std::string> FindNamedFile(const std::string& from, const std::string& name, int* how) {
  if (name.empty()) return std::nullopt;
  const fs::path folder = fs::path(from).parent_path();
  const auto beside = [&](const std::string& n) { return n[0] == '/' ? fs::path(n) : folder / n; };
  std::string slashes = name;
  for (char& c : slashes)
    if (c == '\\') c = '/';
  const auto found = [&](const fs::path& p, int rule) -> std::optional<std::string> {
    if (how) *how = rule;
    return p.string();
  };
  if (IsFile(beside(name))) return found(beside(name), 1);
  if (IsFile(beside(slashes))) return found(beside(slashes), 2);
  if (const auto matched = MatchIgnoringCase(beside(slashes)); matched && IsFile(*matched)) return found(*matched, 3);
  const fs::path last = fs::path(slashes).filename();
  if (!last.empty() && IsFile(folder / last)) return found(folder / last, 4);
  if (!last.empty())
    if (const auto matched = MatchIgnoringCase(folder / last); matched && IsFile(*matched)) return found(*matched, 4);
  return std::nullopt;
}

}  // namespace pb
