#include "mesh/memory_budget.h"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

#include "mesh/errors.h"

namespace pb {
namespace {

// A limit at or above this is no limit (cgroup v1 writes 2^63 rounded down to a page; v2 writes "max").
constexpr double kNoLimit = 0x1p60;

struct Limit {
  double bytes = 0;  // 0: none known
  const char* name = "";
  bool addressSpace = false;  // counts the address space mapped, not the memory touched
};

Limit Physical() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return {pages > 0 && size > 0 ? double(pages) * double(size) : 0.0, "this machine's"};
}

Limit AddressSpace() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return {};
  return {double(limit.rlim_cur), "the process's ulimit -v", true};
}

// The first number in the first of the control group files that holds one below kNoLimit.
Limit ControlGroup() {
  for (const char* path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(path);
    std::string text;
    if (!(in >> text) || text == "max") continue;
    try {
      const double bytes = std::stod(text);
      if (bytes > 0 && bytes < kNoLimit) return {bytes, "the control group's"};
    } catch (const std::exception&) {  // not a number: no limit read
    }
  }
  return {};
}

Limit Tightest() {
  Limit best = Physical();
  for (const Limit& l : {AddressSpace(), ControlGroup()})
    if (l.bytes > 0 && (best.bytes <= 0 || l.bytes < best.bytes)) best = l;
  return best;
}

// A "Vm...:  N kB" line of /proc/self/status [bytes]; 0 if absent.
double StatusBytes(const std::string& field) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field + ":", 0) == 0) return 1024.0 * std::atof(line.c_str() + field.size() + 1);
  return 0;
}

}  // namespace

double MemoryLimitBytes() { return Tightest().bytes; }
double MemoryInUseBytes() { return StatusBytes(Tightest().addressSpace ? "VmSize" : "VmRSS"); }
// The kernel updates the high-water marks lazily: VmHWM read 40.89 MB beside a VmRSS of 40.93 MB under
// AddressSanitizer. The peak is never below what is in use now.
double PeakMemoryBytes() {
  const bool space = Tightest().addressSpace;
  return std::max(StatusBytes(space ? "VmPeak" : "VmHWM"), StatusBytes(space ? "VmSize" : "VmRSS"));
}
std::string MemoryLimitName() { return Tightest().name; }

void RequireMemory(const std::string& option, double bytes, const std::string& what) {
  const Limit memory = Tightest();
  if (memory.bytes <= 0 || bytes <= kUsableMemoryShare * memory.bytes) return;
  throw InputError(option, 0, fmt::format("{} needs about {:.1f} GB, more than the {:.0f}% of {} {:.1f} GB a run may "
                                          "use", what, bytes / 1e9, 100 * kUsableMemoryShare, memory.name, memory.bytes / 1e9));
}

}  // namespace pb
