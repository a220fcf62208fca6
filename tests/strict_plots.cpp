// Linked into every test program (granflow_add_test): the granflow runs a test starts inherit
// GRANFLOW_STRICT_PLOTS=1, so a plot script that fails makes the run exit 4 and the test fail,
// where a user's run only warns (core/run.hpp, strict_plots). An explicit setting is kept.
#include <cstdlib>

namespace {
const int strict_plots_set = ::setenv("GRANFLOW_STRICT_PLOTS", "1", /*overwrite=*/0);
}  // namespace
