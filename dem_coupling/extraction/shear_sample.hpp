// Per-sample observables of Lees-Edwards simple shear, computed from plain particle arrays so
// they can be tested without LIGGGHTS. The driver accumulates rank-local sums (accumulate_*),
// reduces them with one MPI_Allreduce over SampleSums::data, and turns the global sums into a
// ShearSample (finalize_sample).
//
// Streaming profile of Lees-Edwards shear with `fix deform xy erate ... remap v`:
//   u(y) = (shear_rate (y - ylo), 0, 0)       (same frame as LAMMPS compute temp/deform)
// Fluctuation v' = v - u(y) - c, with c the mean of v - u(y) (mass-weighted for the stress,
// number-weighted for T), so that a uniform drift of the whole sample (which Lees-Edwards
// boundaries do not forbid) is not counted as agitation. Kinetic stress (compression positive,
// like LAMMPS pressure):
//   P^kin_ab = (1/V) sum_i m_i v'_ia v'_ib                  (e.g. Campbell 1989, eq. 2.3)
// Total stress P = P^vir + P^kin, P^vir from `compute pressure ... virial` (pair + fix virials).
// Granular temperature T = sum_i |v'_i|^2 / (3 N) (number average, docs/model/multi_regime.md §1).
// Shear stress tau = -P_xy, normal stress sigma_yy = P_yy, mu = tau / sigma_yy,
// mean pressure p = tr(P)/3, inertial number I = shear_rate d / sqrt(sigma_yy / rho_p)
// (GDR MiDi 2004), solid fraction phi = V_s / V, void ratio e = 1/phi - 1,
// coordination number Z = 2 N_contacts / N.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace granflow::dem {

// Rank-local view of the particles (pointers into LIGGGHTS' atom arrays or test arrays).
// Positions and velocities are interleaved xyz (LIGGGHTS x[0], v[0]).
struct ParticleView {
  int count = 0;                     // owned particles (nlocal)
  const double* position = nullptr;  // 3*count
  const double* velocity = nullptr;  // 3*count
  const double* mass = nullptr;      // count (rmass)
  const double* radius = nullptr;    // count
};

// The imposed streaming profile u_x = shear_rate (y - ylo) and the y extent used for bins.
struct ShearFrame {
  double shear_rate = 0.0;  // 1/s
  double ylo = 0.0;         // m
  double ly = 0.0;          // m
};

// Global sums in one contiguous buffer (one MPI_Allreduce). Layout: fixed block, then the
// velocity profile: sum of v_x per y bin, sum of v'_x per bin, particle count per bin.
class SampleSums {
 public:
  enum Index : std::size_t {
    kinetic_xx,
    kinetic_yy,
    kinetic_zz,
    kinetic_xy,
    kinetic_xz,
    kinetic_yz,      // sum m v'_a v'_b
    fluctuation_sq,  // sum |v'|^2
    momentum_x,
    momentum_y,
    momentum_z,      // sum m v' (peculiar momentum)
    particle_count,  // N
    solid_volume,    // sum 4/3 pi r^3
    diameter_sum,    // sum 2 r
    contact_count,   // contacts (pairs with ghosts weighted 1/2)
    mass_sum,        // M = sum m
    velocity_x,
    velocity_y,
    velocity_z,  // sum v' (number weighted)
    fixed_size
  };
  explicit SampleSums(int profile_bins);
  void clear();
  int profile_bins() const { return bins_; }
  double& operator[](Index i) { return data_[i]; }
  double operator[](Index i) const { return data_[i]; }
  double& bin_velocity_sum(int bin) { return data_[fixed_size + bin]; }
  double& bin_fluctuation_sum(int bin) { return data_[fixed_size + bins_ + bin]; }
  double& bin_count(int bin) { return data_[fixed_size + 2 * bins_ + bin]; }
  double bin_velocity_sum(int bin) const { return data_[fixed_size + bin]; }
  double bin_fluctuation_sum(int bin) const { return data_[fixed_size + bins_ + bin]; }
  double bin_count(int bin) const { return data_[fixed_size + 2 * bins_ + bin]; }
  double* data() { return data_.data(); }
  const double* data() const { return data_.data(); }
  int size() const { return static_cast<int>(data_.size()); }

 private:
  int bins_;
  std::vector<double> data_;
};

// Adds kinetic, momentum, volume and profile sums of the owned particles.
void accumulate_particles(const ParticleView& particles, const ShearFrame& frame, SampleSums& sums);

// Contacts on a granular half neighbour list (newton off): a pair is in contact when
// |x_i - x_j| < r_i + r_j. A pair with a ghost j is listed by both owners, so it counts 1/2.
// `neighbor_mask` strips LIGGGHTS' special-bond bits from list entries (NEIGHMASK).
struct HalfNeighborList {
  int inum = 0;
  const int* ilist = nullptr;
  const int* numneigh = nullptr;
  int* const* firstneigh = nullptr;
  int neighbor_mask = 0x3FFFFFFF;
};
void accumulate_contacts(const HalfNeighborList& list, const double* position, const double* radius,
                         int nlocal, SampleSums& sums);

// Box state of a sample (global).
struct BoxState {
  double lx = 0.0, ly = 0.0, lz = 0.0, xy = 0.0;
  double volume() const { return lx * ly * lz; }
};

struct ShearSample {
  long step = 0;
  double time = 0.0;    // s since shear start
  double strain = 0.0;  // shear_rate * time
  BoxState box;
  double shear_rate = 0.0;
  std::array<double, 6> virial_stress{};      // P^vir (xx yy zz xy xz yz), Pa
  std::array<double, 6> kinetic_stress{};     // P^kin, Pa
  std::array<double, 6> stress{};             // P = P^vir + P^kin, Pa
  double normal_stress = 0.0;                 // sigma_yy = P_yy, Pa
  double shear_stress = 0.0;                  // tau = -P_xy, Pa
  double pressure = 0.0;                      // p = tr(P)/3, Pa
  double friction = 0.0;                      // mu = tau / sigma_yy
  double temperature = 0.0;                   // T, m^2/s^2
  double solid_fraction = 0.0;                // phi
  double void_ratio = 0.0;                    // e
  double inertial_number = 0.0;               // I
  double coordination = 0.0;                  // Z
  double mean_diameter = 0.0;                 // m
  std::array<double, 3> peculiar_momentum{};  // kg m/s
  double particles = 0.0;
  std::vector<double> profile_velocity;  // mean v_x per y bin, m/s (NaN for an empty bin)
  std::vector<double> profile_y;         // bin centres relative to ylo, m
  // Deviation of the mean profile from the imposed line: count-weighted RMS over bins of
  // <v_x - u_x(y)>_bin / (shear_rate ly); exactly 0 when every particle moves with u(y).
  double profile_deviation = 0.0;
};

// Global sums + virial -> observables. `particle_density` is rho_p for I.
ShearSample finalize_sample(const SampleSums& sums, const std::array<double, 6>& virial_stress,
                            const BoxState& box, const ShearFrame& frame, double particle_density);

}  // namespace granflow::dem
