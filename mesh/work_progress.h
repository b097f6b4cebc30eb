// A long computation's progress, told to whoever shows it: `done` more units of work since the last call, of
// `total` in all (the unit is the computation's: bytes read, triangles placed). The layers below baker/ take one
// so that they need not know how progress is shown (baker/runtime/progress.h shows it).
#pragma once

#include <cstdint>
#include <functional>

namespace pb {

using WorkProgress = std::function<void(uint64_t done, uint64_t total)>;

}  // namespace pb
