// Constant-normal-stress servo for Lees-Edwards shear: an integral controller on the box height.
// Between short runs the driver measures the mean normal stress sigma_yy over the last interval
// and sets the height to reach over the next interval (fix deform ... y final ... remap v):
//   L_y <- L_y (1 + clamp(gain (sigma_yy - p0) / p0, -max_strain, +max_strain))
// (dilate when the sample is over-pressed). The loop gain is gain * d ln(sigma)/d ln(phi);
// dense flows have d ln(sigma)/d ln(phi) ~ 10-50, so gain ~ 0.01 keeps the loop over-damped
// (the study's choice, liggghts-study.md section 3.3). The clamp bounds the strain rate so the
// imposed dilation never dominates the shear.
#pragma once

namespace granflow::dem {

class NormalStressServo {
 public:
  NormalStressServo(double target_normal_stress, double gain, double max_strain_per_update);
  // New box height from the current one and the interval-mean normal stress.
  double next_height(double height, double mean_normal_stress) const;
  double target() const { return target_; }

 private:
  double target_, gain_, max_strain_;
};

}  // namespace granflow::dem
