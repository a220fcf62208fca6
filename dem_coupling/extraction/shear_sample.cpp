#include "dem_coupling/extraction/shear_sample.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace granflow::dem {

SampleSums::SampleSums(int profile_bins)
    : bins_(std::max(profile_bins, 1)), data_(fixed_size + 3 * std::size_t(bins_), 0.0) {}

void SampleSums::clear() { std::fill(data_.begin(), data_.end(), 0.0); }

namespace {
int bin_of(double y, const ShearFrame& frame, int bins) {
  // Atoms may sit slightly outside [ylo, ylo+ly) between re-neighbourings: clamp to the box.
  const int bin = static_cast<int>(std::floor((y - frame.ylo) / frame.ly * bins));
  return std::clamp(bin, 0, bins - 1);
}
}  // namespace

void accumulate_particles(const ParticleView& particles, const ShearFrame& frame,
                          SampleSums& sums) {
  constexpr double sphere_volume_factor = 4.0 / 3.0 * std::numbers::pi;
  const int bins = sums.profile_bins();
  double k[6] = {0, 0, 0, 0, 0, 0};
  double fluct = 0.0, px = 0.0, py = 0.0, pz = 0.0, vs = 0.0, dsum = 0.0, msum = 0.0;
  double sx = 0.0, sy = 0.0, sz = 0.0;
  for (int i = 0; i < particles.count; ++i) {
    const double* x = particles.position + 3 * i;
    const double* v = particles.velocity + 3 * i;
    const double m = particles.mass[i];
    const double r = particles.radius[i];
    // v' = v - u(y), u_x = shear_rate (y - ylo)
    const double dvx = v[0] - frame.shear_rate * (x[1] - frame.ylo);
    const double dvy = v[1];
    const double dvz = v[2];
    k[0] += m * dvx * dvx;
    k[1] += m * dvy * dvy;
    k[2] += m * dvz * dvz;
    k[3] += m * dvx * dvy;
    k[4] += m * dvx * dvz;
    k[5] += m * dvy * dvz;
    fluct += dvx * dvx + dvy * dvy + dvz * dvz;
    px += m * dvx;
    py += m * dvy;
    pz += m * dvz;
    msum += m;
    sx += dvx;
    sy += dvy;
    sz += dvz;
    vs += sphere_volume_factor * r * r * r;
    dsum += 2.0 * r;
    const int b = bin_of(x[1], frame, bins);
    sums.bin_velocity_sum(b) += v[0];
    sums.bin_fluctuation_sum(b) += dvx;
    sums.bin_count(b) += 1.0;
  }
  for (int a = 0; a < 6; ++a) sums[SampleSums::Index(SampleSums::kinetic_xx + a)] += k[a];
  sums[SampleSums::fluctuation_sq] += fluct;
  sums[SampleSums::momentum_x] += px;
  sums[SampleSums::momentum_y] += py;
  sums[SampleSums::momentum_z] += pz;
  sums[SampleSums::particle_count] += particles.count;
  sums[SampleSums::solid_volume] += vs;
  sums[SampleSums::diameter_sum] += dsum;
  sums[SampleSums::mass_sum] += msum;
  sums[SampleSums::velocity_x] += sx;
  sums[SampleSums::velocity_y] += sy;
  sums[SampleSums::velocity_z] += sz;
}

void accumulate_contacts(const HalfNeighborList& list, const double* position, const double* radius,
                         int nlocal, SampleSums& sums) {
  double contacts = 0.0;
  for (int ii = 0; ii < list.inum; ++ii) {
    const int i = list.ilist[ii];
    const double* xi = position + 3 * i;
    const int* jlist = list.firstneigh[i];
    for (int jj = 0; jj < list.numneigh[i]; ++jj) {
      const int j = jlist[jj] & list.neighbor_mask;
      const double* xj = position + 3 * j;
      const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
      const double contact = radius[i] + radius[j];
      if (dx * dx + dy * dy + dz * dz < contact * contact) contacts += (j < nlocal) ? 1.0 : 0.5;
    }
  }
  sums[SampleSums::contact_count] += contacts;
}

ShearSample finalize_sample(const SampleSums& sums, const std::array<double, 6>& virial_stress,
                            const BoxState& box, const ShearFrame& frame, double particle_density) {
  ShearSample s;
  s.box = box;
  s.shear_rate = frame.shear_rate;
  const double volume = box.volume();
  const double n = sums[SampleSums::particle_count];
  s.particles = n;
  s.virial_stress = virial_stress;
  // Remove the uniform drift: sum m (v'-c)_a (v'-c)_b = sum m v'_a v'_b - P_a P_b / M
  // (parallel-axis theorem), sum |v' - c|^2 = sum |v'|^2 - |S|^2 / N with S = sum v'.
  const double mass = sums[SampleSums::mass_sum];
  const double p[3] = {sums[SampleSums::momentum_x], sums[SampleSums::momentum_y],
                       sums[SampleSums::momentum_z]};
  const int pair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  for (int a = 0; a < 6; ++a) {
    const double drift = mass > 0.0 ? p[pair[a][0]] * p[pair[a][1]] / mass : 0.0;
    s.kinetic_stress[a] = (sums[SampleSums::Index(SampleSums::kinetic_xx + a)] - drift) / volume;
    s.stress[a] = virial_stress[a] + s.kinetic_stress[a];
  }
  s.normal_stress = s.stress[1];
  s.shear_stress = -s.stress[3];
  s.pressure = (s.stress[0] + s.stress[1] + s.stress[2]) / 3.0;
  s.friction = s.shear_stress / s.normal_stress;
  const double sv[3] = {sums[SampleSums::velocity_x], sums[SampleSums::velocity_y],
                        sums[SampleSums::velocity_z]};
  s.temperature =
      (sums[SampleSums::fluctuation_sq] - (sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2]) / n) /
      (3.0 * n);
  s.solid_fraction = sums[SampleSums::solid_volume] / volume;
  s.void_ratio = 1.0 / s.solid_fraction - 1.0;
  s.mean_diameter = sums[SampleSums::diameter_sum] / n;
  // I = shear_rate d / sqrt(sigma_yy / rho_p); NaN when sigma_yy <= 0 (no contact network).
  s.inertial_number = s.normal_stress > 0.0 ? frame.shear_rate * s.mean_diameter /
                                                  std::sqrt(s.normal_stress / particle_density)
                                            : std::numeric_limits<double>::quiet_NaN();
  s.coordination = 2.0 * sums[SampleSums::contact_count] / n;
  s.peculiar_momentum = {sums[SampleSums::momentum_x], sums[SampleSums::momentum_y],
                         sums[SampleSums::momentum_z]};
  const int bins = sums.profile_bins();
  s.profile_velocity.assign(bins, std::numeric_limits<double>::quiet_NaN());
  s.profile_y.resize(bins);
  double dev2 = 0.0, counted = 0.0;
  for (int b = 0; b < bins; ++b) {
    s.profile_y[b] = (b + 0.5) * frame.ly / bins;
    const double c = sums.bin_count(b);
    if (c <= 0.0) continue;
    s.profile_velocity[b] = sums.bin_velocity_sum(b) / c;
    const double scale = frame.shear_rate * frame.ly;
    const double rel = scale != 0.0 ? sums.bin_fluctuation_sum(b) / c / scale : 0.0;
    dev2 += c * rel * rel;
    counted += c;
  }
  s.profile_deviation = counted > 0.0 ? std::sqrt(dev2 / counted) : 0.0;
  return s;
}

}  // namespace granflow::dem
