#include "baker/runtime/threads.h"

#include <pmmintrin.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_scheduler_observer.h>
#include <xmmintrin.h>

namespace pb {
namespace {

void SetFlushToZero() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

class FlushToZeroObserver : public tbb::task_scheduler_observer {
 public:
  FlushToZeroObserver() { observe(true); }
  ~FlushToZeroObserver() override { observe(false); }
  void on_scheduler_entry(bool) override { SetFlushToZero(); }
};

}  // namespace

struct ThreadScope::Impl {
  explicit Impl(unsigned threads) : control(tbb::global_control::max_allowed_parallelism, threads) {}
  tbb::global_control control;
  FlushToZeroObserver observer;
};

ThreadScope::ThreadScope(unsigned threads)
    : count_(threads ? threads : unsigned(tbb::info::default_concurrency())) {
  SetFlushToZero();  // the calling thread takes part in parallel loops too.
  impl_ = std::make_unique<Impl>(count_);
}

ThreadScope::~ThreadScope() = default;

}  // namespace pb
