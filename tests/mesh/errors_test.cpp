// The two kinds of error (mesh/errors.h): a broken invariant aborts and says which, printing the operands of a
// comparison; bad input is an InputError that names file:line. PB_DCHECK runs only where NDEBUG is not defined.
#include <gtest/gtest.h>

#include "mesh/errors.h"

namespace pb {
namespace {

TEST(ErrorsDeathTest, ComparisonChecksPrintBothOperands) {
  const size_t photons = 3, fluxes = 4;
  EXPECT_DEATH(PB_CHECK_EQ(photons, fluxes), "CHECK\\(photons == fluxes\\) failed: left 3, right 4");
  EXPECT_DEATH(PB_CHECK_LT(2.5, 1.0), "CHECK\\(2.5 < 1.0\\) failed: left 2.5, right 1");
  PB_CHECK_LE(photons, fluxes);  // passes: no abort
}

TEST(ErrorsDeathTest, DebugChecksRunOnlyInDebugBuilds) {
#ifdef NDEBUG
  PB_DCHECK_EQ(1, 2);  // compiled out: no abort
  PB_DCHECK(false, "compiled out");
#else
  EXPECT_DEATH(PB_DCHECK_EQ(1, 2), "left 1, right 2");
#endif
}

TEST(Errors, InputErrorNamesFileAndLine) {
  const InputError e("scene.obj", 12, "malformed number 'x'");
  EXPECT_STREQ(e.what(), "scene.obj:12: error: malformed number 'x'");
  EXPECT_STREQ(InputError("--h", 0, "must be > 0").what(), "--h: error: must be > 0");
}

}  // namespace
}  // namespace pb
