// The class of fix fluid/le, shared by its source files (internal to granflow-dem; the style is
// created by name through create_fix_fluid_le, fix_fluid_le.hpp):
//   fix_fluid_le.cpp              init, setup, the per-step forces (drag, rotation), the vector
//   fix_fluid_le_arguments.cpp    the fix's arguments
//   fix_fluid_le_reach.cpp        pairs within reach: the neighbour-list reach for h_max and the
//                                 lubrication candidates of this rank
//   fix_fluid_le_lubrication.cpp  the pair lubrication passes
#pragma once

#include <array>
#include <cstring>
#include <string>
#include <vector>

#include "dem_coupling/fixes/fix_fluid_le.hpp"
#include "dem_coupling/fixes/fluid_time_step.hpp"
#include "dem_coupling/fixes/lubrication.hpp"
#include "error.h"
#include "fix.h"
#include "lmptype.h"
#include "neighbor.h"

namespace granflow::dem::fluid_le_detail {

namespace vec = fluid_le_vector;

class FixFluidLE : public LAMMPS_NS::Fix {
 public:
  FixFluidLE(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg);
  ~FixFluidLE() override {  // `unfix` gives the deck its own skin back (reach skin)
    if (reach_by_skin_ && neighbor->skin == raised_skin_) neighbor->skin = deck_skin_;
  }
  int setmask() override {
    return LAMMPS_NS::FixConst::POST_FORCE |
           (reach_by_skin_ ? LAMMPS_NS::FixConst::POST_INTEGRATE : 0);
  }
  void post_integrate() override;
  void init() override;
  void setup(int vflag) override;
  void post_force(int vflag) override;
  double compute_vector(int n) override;
  const FluidForceSettings& settings() const { return settings_; }

 private:
  // Streaming (fluid) velocity gradient L = H_rate H⁻¹ of the deforming box and the vorticity/2.
  struct Flow {
    double L[3][3];
    double rate_lo[3];
    double spin[3];  // Ω = (1/2) curl u
  };
  Flow current_flow() const;
  void fail(const std::string& message) const { error->all(FLERR, message.c_str()); }
  bool parse_yes_no(const char* keyword, const char* value) const;

  FluidForceSettings settings_;
  double solid_volume_ = 0.0;  // Σ π d³/6 of the group, m³ (set in setup)
  double smallest_radius_ = 0.0, largest_radius_ = 0.0, smallest_density_ = 0.0;
  std::array<double, vec::size> local_{};   // this rank's sums (kinetic part filled on demand)
  std::array<double, vec::size> global_{};  // reduced over ranks
  LAMMPS_NS::bigint last_reduce_ = -1;
  bool report_time_scales_ = true;
  // This step's pairs within h_max (grow-only buffers, structure of arrays, sized by the list):
  // pairs with an owned j at [0, owned), pairs with a ghost j at [capacity - ghost, capacity).
  // Layout after selection: [0, owned) owned j; [owned, owned + images) ghost j that is a
  // periodic image of an atom owned here (target = that atom); [top - ghost, top - ghost + half)
  // ghost j owned by another rank. Capacity 2 × entries keeps the regions apart.
  struct LubricatedPairs {
    std::vector<int> i, j, target;
    std::vector<double> inverse_distance, normal, tangential, log_argument;
    void grow(std::size_t entries) {
      if (2 * entries <= i.size()) return;
      const std::size_t n = 3 * entries;  // grows with the list, not in steady state
      for (auto* a : {&i, &j, &target}) a->resize(n);
      for (auto* a : {&inverse_distance, &normal, &tangential, &log_argument}) a->resize(n);
    }
  };
  LubricatedPairs pairs_;
  // Candidate pairs of this rank (update_candidates), rebuilt with the neighbour list.
  struct Candidate {
    int i, j, target;  // target: where j's force goes (j, its owned image, or -1: other rank)
  };
  struct Candidates {
    std::vector<Candidate> owned, images, remote, all;  // all = owned, images, remote in order
    std::size_t end[3] = {0, 0, 0};                     // ends of the three kinds in all
    LAMMPS_NS::bigint build = -1;
  };
  Candidates candidates_;
  void update_candidates();
  // `sums sampled`: virials, dissipation and pair count only on the steps that read them (a
  // compute tallies the virial, the last step of a run, setup); `sums every`: every step.
  bool sums_every_step_ = true;
  bool setup_pending_ = false;
  LAMMPS_NS::bigint sums_step_ = -1;
  // For each ghost (index - nlocal): the local index of the owned atom it is a periodic image
  // of, or -1 if the atom is owned by another rank; rebuilt when the ghosts are (with every
  // neighbour build: neighbor->ncalls counts them).
  std::vector<int> ghost_owner_;
  LAMMPS_NS::bigint ghost_owner_build_ = -1;
  void update_ghost_owners();

  // `reach skin`: the list reach for h_max comes from the skin (raised by h_max when the fix is
  // created) instead of contact_distance_factor, and the fix forces a rebuild once an atom has
  // moved half the deck's own skin (less the box corners' motion, as LAMMPS' check), so every
  // pair with h < h_max stays listed. Positions and box corners at the last build:
  bool reach_by_skin_ = false;
  double deck_skin_ = 0.0, raised_skin_ = 0.0;
  std::vector<double> x_at_build_;
  double corners_at_build_[8][3] = {};
  LAMMPS_NS::bigint hold_build_ = -1;
  void hold_build_positions();
  void lubrication_forces(std::array<double, fluid_le_vector::size>& acc, bool sums);
};

}  // namespace granflow::dem::fluid_le_detail
