#include "dem_coupling/driver/stopping_rule.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>

namespace granflow::dem {

StoppingRule::StoppingRule(const ErrorTargets& targets, double temperature_scale)
    : targets_(targets), temperature_scale_(temperature_scale) {
  confirmation_.needed = targets.confirm_checks;
  for (const char* name : {"sigma_yy", "tau", "p", "phi", "e", "T", "Z"}) columns_[name];
}

void StoppingRule::add(const ShearSample& s) {
  // The series.tsv columns of the same names (main.cpp, write_series_row).
  columns_["sigma_yy"].push_back(as_written(s.normal_stress));
  columns_["tau"].push_back(as_written(s.shear_stress));
  columns_["p"].push_back(as_written(s.pressure));
  columns_["phi"].push_back(as_written(s.solid_fraction));
  columns_["e"].push_back(as_written(s.void_ratio));
  columns_["T"].push_back(as_written(s.temperature));
  columns_["Z"].push_back(as_written(s.coordination));
}

TargetStatus StoppingRule::check() {
  const auto t0 = std::chrono::steady_clock::now();
  TargetStatus status;
  status.achieved.fill(std::numeric_limits<double>::quiet_NaN());
  reached_ = false;
  if (columns_.at("sigma_yy").size() >= 8) {  // point_analysis.cpp: no steady values below 8
    const SteadyWindow window = steady_window(columns_, temperature_scale_);
    status = target_status(window, targets_);
    reached_ = window.reached;
  }
  confirmation_.update(status);
  ++checks_;
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return status;
}

std::string StoppingRule::describe(const TargetStatus& status, double strain) const {
  std::string line = fmt::format("strain {:.6g} ({} samples, at least {} to stop): {}", strain,
                                 columns_.at("sigma_yy").size(), min_target_samples,
                                 reached_ ? "steady" : "not steady");
  for (std::size_t k = 0; k < target_observables.size(); ++k)
    if (targets_.error[k] > 0.0)
      line += fmt::format(", {} {:.4g} (target {:g}) {}", target_observables[k], status.achieved[k],
                          targets_.error[k], status.met[k] ? "met" : "missed");
  return line + fmt::format("; met at {} of {} consecutive checks", confirmation_.held,
                            confirmation_.needed);
}

}  // namespace granflow::dem
