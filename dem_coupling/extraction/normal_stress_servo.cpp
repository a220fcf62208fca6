#include "dem_coupling/extraction/normal_stress_servo.hpp"

#include <algorithm>
#include <stdexcept>

namespace granflow::dem {

NormalStressServo::NormalStressServo(double target_normal_stress, double gain,
                                     double max_strain_per_update)
    : target_(target_normal_stress), gain_(gain), max_strain_(max_strain_per_update) {
  if (!(target_ > 0.0) || !(gain_ > 0.0) || !(max_strain_ > 0.0))
    throw std::invalid_argument("NormalStressServo: target, gain and max strain must be > 0");
}

double NormalStressServo::next_height(double height, double mean_normal_stress) const {
  const double strain =
      std::clamp(gain_ * (mean_normal_stress - target_) / target_, -max_strain_, max_strain_);
  return height * (1.0 + strain);
}

}  // namespace granflow::dem
