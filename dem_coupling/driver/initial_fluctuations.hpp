// The velocity fluctuations a shear stage starts with (gf_initial_temperature of the deck).
#pragma once

#include <cstdint>

namespace granflow::dem {

// Adds c_i to every velocity: c_i Gaussian (Box-Muller on mt19937_64 seeded by (seed, atom id),
// so that an atom's fluctuation does not depend on which rank holds it), shifted so that
// Σ m_i c_i = 0 and scaled so that Σ |c_i|² / (3 N) = T0 exactly (the number average of
// extraction/shear_sample.hpp). Rotation untouched. Collective. Returns the T0 applied (0 when
// T0 <= 0 or there is nothing to scale).
double add_fluctuations(void* handle, double temperature, std::uint64_t seed);

}  // namespace granflow::dem
