// Memory a run may use, and estimates of what its heaviest options cost, so that an option that would exhaust the
// memory is refused up front with the estimate, not after minutes of work by the kernel's out-of-memory killer or
// an allocation that fails. Bytes throughout.
#pragma once

#include <string>

namespace pb {

// The memory this process may use: the machine's physical memory (sysconf), or less where a limit says so: the
// address space of `ulimit -v` (RLIMIT_AS) or the control group's (a container's, a systemd unit's) memory limit
// (cgroup v2 memory.max, v1 memory.limit_in_bytes). 0 if none is known.
double MemoryLimitBytes();
// What MemoryLimitBytes reads: "this machine's", "the process's ulimit -v", "the control group's".
std::string MemoryLimitName();
// The memory in use now, and the most held so far, in the measure that limit counts: the address space mapped
// (VmSize, VmPeak) under ulimit -v, which counts what is reserved and not yet touched (a bake's threads, arenas and
// photon blocks: 1.96 GB mapped for 0.58 GB resident at 12M photons on the box), else the memory resident (VmRSS,
// VmHWM). 0 where /proc does not say.
double MemoryInUseBytes();
double PeakMemoryBytes();

// The share of MemoryLimitBytes a run may grow to: what the options' estimates and the rounds are held to.
inline constexpr double kUsableMemoryShare = 0.8;

// InputError naming `option` when `bytes` exceeds kUsableMemoryShare of MemoryLimitBytes, with the estimate and
// `what` it is for.
void RequireMemory(const std::string& option, double bytes, const std::string& what);

}  // namespace pb
