// The worker threads of one bake: caps TBB's parallelism for the scope's lifetime and sets flush-to-zero and
// denormals-are-zero in every worker (as Embree asks, for speed). Determinism does not depend on the count:
// work is cut into fixed blocks whose results are combined in block order.
#pragma once

#include <memory>

namespace pb {

class ThreadScope {
 public:
  explicit ThreadScope(unsigned threads);  // 0 = all cores
  ~ThreadScope();
  unsigned Count() const { return count_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  unsigned count_;
};

}  // namespace pb
