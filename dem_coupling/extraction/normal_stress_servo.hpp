// Constant-normal-stress servo for Lees-Edwards shear: an integral controller on the box height.
// Between short runs the driver measures the mean normal stress sigma_yy over the last interval
// (dry decks: the time average over every step, fix gf_stress) and sets the height to reach over
// the next interval (fix deform ... y final ... remap v):
//   d_k   = gain (sigma_yy,k - p0) / p0 + c_{k-1}               (demand, with the carry c)
//   s_k   = clamp(d_k, -max_strain, +max_strain),  L_y <- L_y (1 + s_k)
//   c_k   = clamp(d_k - s_k, -carry_limit, +carry_limit),  carry_limit = carry_updates max_strain
// (dilate when the sample is over-pressed). The loop gain is gain * d ln(sigma)/d ln(phi);
// dense flows have d ln(sigma)/d ln(phi) ~ 10-50, so gain ~ 0.01 keeps the loop over-damped
// (the study's choice, liggghts-study.md section 3.3). The clamp bounds the strain rate so the
// imposed dilation never dominates the shear. The carry pays out later what the clamp cut off:
// sigma_yy is skewed (rare spikes several times p0), and a symmetric clamp without it cuts the
// spikes' demands and not the dips', so the loop balanced the clipped errors and held the median
// (300 dry spheres: mean 15-33 % above p0). With the carry, sum_k s_k = gain sum_k e_k - c_k:
// the height stays bounded, so the mean error goes to zero (the mean, not the median, on p0).
// carry_limit bounds the wind-up of a long one-sided transient. granflow-dem uses
// carry_updates = 50 for dry decks (a 10 % height change at max_strain 0.002): on the model plant
// of tests/dem/test_servo_mean.cpp 10 still held the mean 10 % high (spikes owe more than that),
// 50 holds it within 1 %, and from a sample 10 % too loose the loop settles as fast as without
// the carry. Immersed decks (soft viscous plants, move-then-hold) use 0, the plain clamp: there
// the carry wound up on the long one-sided transient from the start φ and overshot
// (tests/dem/test_servo.cpp), and σ_yy is far less skewed.
#pragma once

namespace granflow::dem {

class NormalStressServo {
 public:
  NormalStressServo(double target_normal_stress, double gain, double max_strain_per_update,
                    double carry_updates = 0.0);
  // New box height from the current one and the interval-mean normal stress (updates the carry).
  double next_height(double height, double mean_normal_stress);
  double target() const { return target_; }
  double carry() const { return carry_; }  // relative height change still owed

 private:
  double target_, gain_, max_strain_, carry_limit_, carry_ = 0.0;
};

}  // namespace granflow::dem
