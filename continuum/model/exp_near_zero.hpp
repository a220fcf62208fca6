// exp(x) for the small arguments of a time step (volume growth exp(tr D Δt), the liquid's
// density factor exp(p/K_w)): the Taylor series
//   exp(x) = 1 + x (1 + x/2 (1 + x/3 (1 + x/4 (1 + x/5)))) + R,   |R| <= |x|⁶/720 · e^|x|,
// for |x| <= 2^-10, where R < 2e-21, far below the double's half ulp of 1 (1.1e-16): the result
// differs from std::exp by the rounding of the Horner sums (≤ 1-2 ulp); std::exp beyond.
#pragma once

#include <cmath>

namespace granflow::model {

inline double exp_near_zero(double x) {
  if (!(std::fabs(x) <= 0x1p-10)) return std::exp(x);  // (NaN too)
  return 1.0 + x * (1.0 + x * 0.5 * (1.0 + x * (1.0 / 3.0) * (1.0 + x * 0.25 * (1.0 + x * 0.2))));
}

}  // namespace granflow::model
