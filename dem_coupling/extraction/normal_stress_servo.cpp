#include "dem_coupling/extraction/normal_stress_servo.hpp"

#include <algorithm>
#include <stdexcept>

namespace granflow::dem {

NormalStressServo::NormalStressServo(double target_normal_stress, double gain,
                                     double max_strain_per_update, double carry_updates)
    : target_(target_normal_stress),
      gain_(gain),
      max_strain_(max_strain_per_update),
      carry_limit_(carry_updates * max_strain_per_update) {
  if (!(target_ > 0.0) || !(gain_ > 0.0) || !(max_strain_ > 0.0) || !(carry_limit_ >= 0.0))
    throw std::invalid_argument(
        "NormalStressServo: target, gain and max strain must be > 0, the carry >= 0");
}

double NormalStressServo::next_height(double height, double mean_normal_stress) {
  const double demand = gain_ * (mean_normal_stress - target_) / target_ + carry_;
  const double strain = std::clamp(demand, -max_strain_, max_strain_);
  carry_ = std::clamp(demand - strain, -carry_limit_, carry_limit_);
  return height * (1.0 + strain);
}

}  // namespace granflow::dem
