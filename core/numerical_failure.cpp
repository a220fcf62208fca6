#include "core/numerical_failure.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>

namespace granflow::core {

NumericalFailure::NumericalFailure(long step_, std::string point_, std::string variable_,
                                   double value_, std::string why_)
    : std::runtime_error(fmt::format("numerical failure at step {}, {}: {} = {} ({})", step_,
                                     point_, variable_, value_, why_)),
      step(step_),
      point(std::move(point_)),
      variable(std::move(variable_)),
      value(value_),
      why(std::move(why_)) {}

void check_finite(double value, long step, const std::string& point, const std::string& variable,
                  bool non_negative) {
  if (!std::isfinite(value)) throw NumericalFailure(step, point, variable, value, "not finite");
  if (non_negative && value < 0) throw NumericalFailure(step, point, variable, value, "negative");
}

}  // namespace granflow::core
