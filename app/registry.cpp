#include "app/registry.hpp"

#include "continuum/rev/rev_kind.hpp"
#ifdef GRANFLOW_HAVE_MPM_KIND
#include "continuum/mpm/mpm_kind.hpp"
#endif
#ifdef GRANFLOW_HAVE_DEM_KIND
#include "dem_coupling/dem_kind.hpp"
#endif
#ifdef GRANFLOW_HAVE_CALIBRATE_KIND
#include "analysis/calibration/calibrate_kind.hpp"
#endif
#ifdef GRANFLOW_HAVE_PAIR_KIND
#include "analysis/pair/pair_kind.hpp"
#endif
#ifdef GRANFLOW_HAVE_TRANSIENT_PAIR_KIND
#include "analysis/transient_pair/transient_pair_kind.hpp"
#endif

namespace granflow::app {

core::KindRegistry make_registry() {
  core::KindRegistry registry;
  rev::register_rev_kinds(registry);
#ifdef GRANFLOW_HAVE_MPM_KIND
  mpm::register_mpm_kinds(registry);
#endif
#ifdef GRANFLOW_HAVE_DEM_KIND
  dem::register_dem_kinds(registry);
#endif
#ifdef GRANFLOW_HAVE_CALIBRATE_KIND
  calibration::register_calibrate_kinds(registry);
#endif
#ifdef GRANFLOW_HAVE_PAIR_KIND
  pair::register_pair_kinds(registry);
#endif
#ifdef GRANFLOW_HAVE_TRANSIENT_PAIR_KIND
  transient_pair::register_transient_pair_kinds(registry);
#endif
  return registry;
}

}  // namespace granflow::app
