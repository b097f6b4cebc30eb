// Memory a run may use, and estimates of what its heaviest options cost, so that an option that would exhaust the
// machine is refused up front with the estimate, not after minutes of work by the kernel's out-of-memory killer.
// Bytes throughout.
#pragma once

#include <string>

namespace pb {

// The machine's physical memory (sysconf); 0 if unknown.
double PhysicalMemoryBytes();

// InputError naming `option` when `bytes` exceeds 80% of the physical memory, with the estimate and `what` it is for.
void RequireMemory(const std::string& option, double bytes, const std::string& what);

}  // namespace pb
