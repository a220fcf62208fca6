// granflow-dem's stopping rule for strain.target_error (docs/dem_dataset.md, "Error-targeted run
// length"). Rank 0 keeps the observables of every sample exactly as series.tsv holds them
// (series_output.hpp, as_written: 10 significant digits read back as the kind reads them) and,
// every gf_check_every steps, evaluates the steady window and its errors with the functions the
// kind applies to series.tsv afterwards (kind/steady_checks.hpp: steady_window, target_status). The
// run stops at the check where the window has been steady with every error within its target at
// targets.confirm_checks consecutive checks (strain.confirm_checks, TargetConfirmation); the kind's
// analysis of the same series then finds the same window, errors and flags, so there is one
// definition of "steady" and of each error. main.cpp broadcasts rank 0's decision.
#pragma once

#include <string>

#include "dem_coupling/deck/driver_parameters.hpp"
#include "dem_coupling/driver/series_output.hpp"
#include "dem_coupling/extraction/shear_sample.hpp"
#include "dem_coupling/kind/steady_checks.hpp"

namespace granflow::dem {

class StoppingRule {
 public:
  StoppingRule(const ErrorTargets& targets, double temperature_scale);

  // Rank 0, after every sample: its observables as written to series.tsv.
  void add(const ShearSample& s);

  // Rank 0: the window and errors of the samples so far (not met with fewer than 8 samples,
  // where the kind reports no steady values either). Counts the checks, their time and the
  // consecutive checks that met the targets.
  TargetStatus check();

  // The targets have been met at the last targets.confirm_checks checks: stop.
  bool confirmed() const { return confirmation_.held >= confirmation_.needed; }

  // "strain 3.5 (...): steady, friction 0.0087 (target 0.01) met, ..., met at 2 of 3
  // consecutive checks" for the driver's output.
  std::string describe(const TargetStatus& status, double strain) const;

  long checks() const { return checks_; }
  double seconds() const { return seconds_; }  // wall time spent in check()

 private:
  ErrorTargets targets_;
  double temperature_scale_;
  SeriesColumns columns_;  // sigma_yy, tau, p, phi, e, T, Z: what steady_window reads
  bool reached_ = false;   // of the last check
  TargetConfirmation confirmation_;
  long checks_ = 0;
  double seconds_ = 0.0;
};

}  // namespace granflow::dem
