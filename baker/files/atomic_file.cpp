#include "baker/files/atomic_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <streambuf>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_map>

#include "baker/runtime/interrupt.h"
#include "mesh/errors.h"

namespace pb {
namespace {

std::string ErrnoText() { return std::strerror(errno); }

// PB_FAIL_WRITES_AFTER in bytes, or -1 for no limit.
int64_t WriteLimit() {
  const char* limit = std::getenv("PB_FAIL_WRITES_AFTER");
  return limit ? std::max<int64_t>(std::strtoll(limit, nullptr, 10), 0) : int64_t(-1);
}

// PB_PAUSE_BEFORE_COMMIT_MS: how long Commit holds the staged outputs before it renames them (tests send signals
// then); 0 when unset.
void PauseBeforeCommit() {
  const char* pause = std::getenv("PB_PAUSE_BEFORE_COMMIT_MS");
  if (pause != nullptr) std::this_thread::sleep_for(std::chrono::milliseconds(std::max(std::atoll(pause), 0LL)));
}

// ::write, failing with ENOSPC once the process has written PB_FAIL_WRITES_AFTER bytes.
ssize_t WriteSome(int fd, const char* data, size_t size) {
  static const int64_t limit = WriteLimit();
  static std::atomic<int64_t> left{limit};
  if (limit >= 0 && left.fetch_sub(int64_t(size)) < int64_t(size)) {
    errno = ENOSPC;
    return -1;
  }
  return ::write(fd, data, size);
}

// An output stream buffer over a file descriptor, so that the file opened with O_EXCL | O_NOFOLLOW is the one
// written (std::ofstream would open the path again).
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof buffer_); }
  ~DescriptorBuffer() override { sync(); }
  int sync() override { return Drain() ? 0 : -1; }
  // OpenEXR asks for the position and seeks back to write its offset tables.
  pos_type seekoff(off_type offset, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    if (!Drain()) return pos_type(off_type(-1));
    const int whence = dir == std::ios_base::beg ? SEEK_SET : dir == std::ios_base::cur ? SEEK_CUR : SEEK_END;
    const off_t at = ::lseek(fd_, off_t(offset), whence);
    return at < 0 ? pos_type(off_type(-1)) : pos_type(off_type(at));
  }
  pos_type seekpos(pos_type position, std::ios_base::openmode mode) override {
    return seekoff(off_type(position), std::ios_base::beg, mode);
  }

 protected:
  int_type overflow(int_type c) override {
    if (!Drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) sputc(traits_type::to_char_type(c));
    return traits_type::not_eof(c);
  }

 private:
  bool Drain() {
    for (char* p = pbase(); p < pptr();) {
      const ssize_t n = WriteSome(fd_, p, size_t(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      p += n;
    }
    setp(buffer_, buffer_ + sizeof buffer_);
    return true;
  }
  int fd_;
  char buffer_[1 << 16];
};

std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

// A temporary's name: "<output>.tmp-<pid>-<n>", which TemporaryOf reads back.
constexpr std::string_view kTemporaryMark = ".tmp-";
std::string TemporaryName(const std::string& path, pid_t pid, uint64_t n) {
  return path + std::string(kTemporaryMark) + std::to_string(pid) + "-" + std::to_string(n);
}

// Creates a new temporary file beside `path`; returns its name and descriptor.
std::pair<std::string, int> CreateTemporary(const std::string& path) {
  static std::atomic<uint64_t> counter{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string name = TemporaryName(path, getpid(), counter++);
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0) return {name, fd};
    if (errno != EEXIST) throw InputError(path, 0, "cannot create output file: " + ErrnoText());
  }
  throw InputError(path, 0, "cannot create output file: 100 temporary names in use");
}

void SyncDirectory(const std::string& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);  // best effort: some file systems refuse to sync directories
  ::close(fd);
}

// The file a path names, for comparing paths: (device, inode) when it exists, else its resolved path.
struct FileIdentity {
  std::optional<std::pair<dev_t, ino_t>> node;
  std::string resolved;
  // Equal keys name the same file: the node where the file exists, else the resolved path.
  std::string Key() const {
    return node ? "node " + std::to_string(node->first) + ":" + std::to_string(node->second) : "path " + resolved;
  }
};
FileIdentity IdentityOf(const std::string& path) {
  FileIdentity id;
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) id.node = std::pair{st.st_dev, st.st_ino};
  std::error_code error;
  id.resolved = std::filesystem::weakly_canonical(path, error).string();
  if (error) id.resolved = path;
  return id;
}

}  // namespace

OutputFiles::~OutputFiles() {
  for (const Staged& s : staged_) std::remove(s.temporary.c_str()), ReleaseTemporary(s.held);
  // Innermost first; rmdir leaves a folder that is not empty (something else was put there).
  for (auto d = createdDirectories_.rbegin(); d != createdDirectories_.rend(); ++d)
    ::rmdir(d->path.c_str()), ReleaseTemporary(d->held);
}

void OutputFiles::MakeDirectory(const std::string& path) {
  std::error_code error;
  if (std::filesystem::exists(path, error) && !std::filesystem::is_directory(path, error))
    throw InputError(path, 0, "is not a folder; name a folder to write the maps into");
  std::vector<std::string> missing;  // innermost first
  for (std::filesystem::path p = std::filesystem::path(path).lexically_normal(); !p.empty() && p != p.root_path();
       p = p.parent_path()) {
    std::error_code ec;
    if (std::filesystem::exists(p, ec)) break;
    missing.push_back(p.string());
  }
  for (auto d = missing.rbegin(); d != missing.rend(); ++d) {
    if (::mkdir(d->c_str(), 0777) != 0 && errno != EEXIST)
      throw InputError(path, 0, "cannot create the folder " + *d + ": " + ErrnoText());
    const std::lock_guard lock(mutex_);  // Write makes a folder gone since the run began from any thread
    createdDirectories_.push_back({*d, HoldCreatedFolder(*d)});
  }
}

void OutputFiles::Write(const std::string& path, const std::function<void(std::ostream&)>& write) {
  // The folder was there when the run began; another run that created it, failing, may have removed it since (it
  // was empty): made again, and removed with this run's if this one fails.
  if (std::error_code ec; !std::filesystem::exists(DirectoryOf(path), ec)) MakeDirectory(DirectoryOf(path));
  const auto [temporary, fd] = CreateTemporary(path);
  const int held = HoldTemporary(temporary);
  try {
    {
      DescriptorBuffer buffer(fd);
      std::ostream out(&buffer);
      write(out);
      out.flush();
      if (!out) throw InputError(path, 0, "write failed: " + ErrnoText());
    }
    if (::fsync(fd) != 0) throw InputError(path, 0, "write failed: " + ErrnoText());
    if (::close(fd) != 0) throw InputError(path, 0, "write failed: " + ErrnoText());
  } catch (...) {
    ::close(fd);
    std::remove(temporary.c_str());
    ReleaseTemporary(held);
    throw;
  }
  const std::lock_guard lock(mutex_);
  staged_.push_back({temporary, path, held});
}

namespace {

// Before the first rename: each temporary is still there and each target can be replaced (not a folder, in a folder
// still writable), so that a commit that fails for a reason it can see fails before it has replaced any output.
void RequireReplaceable(const std::string& path, const std::string& temporary) {
  struct stat target{};
  if (::lstat(path.c_str(), &target) == 0 && S_ISDIR(target.st_mode))
    throw InputError(path, 0, "cannot move output into place: a folder has its name; no output was replaced");
  if (::access(DirectoryOf(path).c_str(), W_OK | X_OK) != 0)
    throw InputError(path, 0, "cannot move output into place: its folder: " + ErrnoText() + "; no output was replaced");
  struct stat staged{};
  if (::lstat(temporary.c_str(), &staged) != 0 || !S_ISREG(staged.st_mode))
    throw InputError(path, 0, "cannot move output into place: its temporary " + temporary + " is gone; no output was "
                              "replaced");
}

}  // namespace

void OutputFiles::Commit() {
  PauseBeforeCommit();
  for (const Staged& s : staged_) RequireReplaceable(s.path, s.temporary);
  std::vector<std::string> directories;
  for (const Staged& s : staged_) {
    if (std::rename(s.temporary.c_str(), s.path.c_str()) != 0)
      throw InputError(s.path, 0, "cannot move output into place: " + ErrnoText());
    ReleaseTemporary(s.held);
    directories.push_back(DirectoryOf(s.path));
  }
  staged_.clear();
  for (const Created& d : createdDirectories_) ReleaseTemporary(d.held);
  createdDirectories_.clear();
  for (const std::string& d : directories) SyncDirectory(d);
}

void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  OutputFiles file;
  file.Write(path, write);
  file.Commit();
}

namespace {

// The output's name and the pid of a temporary's name (TemporaryName); nothing for any other name.
std::optional<std::pair<std::string, pid_t>> TemporaryOf(const std::string& name) {
  const size_t mark = name.rfind(kTemporaryMark);
  if (mark == std::string::npos || mark == 0) return std::nullopt;
  const std::string rest = name.substr(mark + kTemporaryMark.size());
  const size_t dash = rest.find('-');
  const auto digits = [](const std::string& t) {
    return !t.empty() && t.size() <= 9 && std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (dash == std::string::npos || !digits(rest.substr(0, dash)) || !digits(rest.substr(dash + 1))) return std::nullopt;
  return std::pair{name.substr(0, mark), pid_t(std::stol(rest.substr(0, dash)))};  // at most 9 digits: an int
}

bool Running(pid_t pid) { return pid > 0 && (::kill(pid, 0) == 0 || errno != ESRCH); }

}  // namespace

std::vector<std::pair<std::string, long>> RemoveStaleTemporaries(
    const std::string& directory, const std::function<bool(const std::string& name)>& isOutput) {
  std::vector<std::pair<std::string, long>> removed;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    const auto temporary = TemporaryOf(name);
    if (!temporary || !isOutput(temporary->first) || Running(temporary->second)) continue;
    if (!entry.is_regular_file(error) || entry.is_symlink(error)) continue;
    if (std::remove(entry.path().c_str()) == 0)
      removed.emplace_back(entry.path().string(), long(temporary->second));
  }
  std::sort(removed.begin(), removed.end());
  return removed;
}

void RequireWritableLocation(const std::string& path) {
  if (path.empty()) throw InputError("<output>", 0, "no output path given");
  if (path.back() == '/') throw InputError(path, 0, "is a directory; name a file to write");
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw InputError(path, 0, "is a directory; name a file to write");
    if (!S_ISREG(st.st_mode))
      throw InputError(path, 0, "is not a regular file (a device, FIFO or socket); it would be replaced by one");
  }
  const std::string directory = DirectoryOf(path);
  if (::access(directory.c_str(), W_OK) != 0) throw InputError(path, 0, "cannot write here: " + ErrnoText());
  // The temporary's name must fit the folder's limit too (NAME_MAX, 255 on most file systems), or the bake would
  // fail after all its work: its longest, with the largest pid and a counter of 9 digits.
  const long most = ::pathconf(directory.c_str(), _PC_NAME_MAX);
  const size_t slash = path.find_last_of('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const size_t longest = TemporaryName(name, pid_t(4194304), 999'999'999).size();
  if (most > 0 && longest > size_t(most))
    throw InputError(path, 0, fmt::format("the file name is {} characters long: with its temporary's suffix ({}) "
                                          "it passes this folder's limit of {}; choose a name of at most {}",
                                          name.size(), longest - name.size(), most, size_t(most) - (longest - name.size())));
}

void RequireDistinctFiles(const std::vector<std::pair<std::string, std::string>>& outputs,
                          const std::vector<std::pair<std::string, std::string>>& inputs) {
  // By identity, hashed, so that thousands of --maps files against hundreds of textures cost one stat each.
  std::unordered_map<std::string, std::pair<std::string, std::string>> inputAt;  // identity -> (input, path)
  for (const auto& [input, path] : inputs)
    if (!path.empty()) inputAt.emplace(IdentityOf(path).Key(), std::pair{input, path});
  std::unordered_map<std::string, std::string> outputAt;  // identity -> option
  for (const auto& [option, path] : outputs) {
    if (path.empty()) continue;
    const std::string key = IdentityOf(path).Key();
    if (const auto it = outputAt.find(key); it != outputAt.end())
      throw InputError(path, 0, option + " and " + it->second + " name the same file");
    if (const auto it = inputAt.find(key); it != inputAt.end())
      throw InputError(path, 0, option + " would overwrite the input " + it->second.first + " (" + it->second.second + ")");
    outputAt.emplace(key, option);
  }
}

}  // namespace pb
