#include "baker/runtime/memory_budget.h"

#include <fmt/format.h>
#include <unistd.h>

#include "mesh/errors.h"

namespace pb {

double PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? double(pages) * double(size) : 0.0;
}

void RequireMemory(const std::string& option, double bytes, const std::string& what) {
  constexpr double kUsable = 0.8;
  const double memory = PhysicalMemoryBytes();
  if (memory <= 0 || bytes <= kUsable * memory) return;
  throw InputError(option, 0, fmt::format("{} needs about {:.1f} GB, more than the {:.0f}% of this machine's {:.1f} GB "
                                          "a run may use", what, bytes / 1e9, 100 * kUsable, memory / 1e9));
}

}  // namespace pb
