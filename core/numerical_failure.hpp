// The one numerical-failure type of granflow: a run (or a solver inside it) stops with a message
// naming the step, the point and the variable, "numerical failure at step S, P: V = X (why)";
// the CLI exits 3 and whatever the run wrote before stays on disk. Self-contained (no case, log
// or HDF5 code), so the solvers below the case layer throw it too.
#pragma once

#include <stdexcept>
#include <string>

namespace granflow::core {

class NumericalFailure : public std::runtime_error {
 public:
  NumericalFailure(long step, std::string point, std::string variable, double value,
                   std::string why);
  long step;  // the step being taken; -1 when the thrower does not know it (a material's update:
              // the solver that called it rethrows with its step)
  std::string point, variable;
  double value;
  std::string why;
};

// Throws NumericalFailure if `value` is NaN/Inf (or negative when `non_negative`).
void check_finite(double value, long step, const std::string& point, const std::string& variable,
                  bool non_negative = false);

}  // namespace granflow::core
