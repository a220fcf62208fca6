// The interface through which a constitutive model updates the effective stress of solid points.
// One call per step per material, over a contiguous range of points in SoA form, so the virtual
// call is paid once per step, never per point. The multi-regime model plugs in here too: it keeps
// its state variables (e, T, hardening ...) in its own arrays indexed by point - begin. A case
// selects a material by name (`solid.material`) through material_registry.hpp.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace granflow::mpm {

// Views of the solid-point arrays a stress update reads and writes (tension-positive stresses,
// docs/model/conventions.md).
struct StressUpdateView {
  const double* Lxx;  // velocity gradient ∂v_x/∂x ...
  const double* Lxy;
  const double* Lyx;
  const double* Lyy;
  const double* porosity;  // current n
  double* temperature;     // T (a model with a T equation updates it)
  double* sxx;
  double* syy;
  double* szz;
  double* sxy;
  int threads;  // OpenMP threads the solver runs with (a material may parallelize its loop)
  // Conductivity κ_T of q = -κ_T ∇T per point, kg/(m s), written by a material with a T
  // equation when the solver conducts T with material conductivities; nullptr otherwise.
  double* conductivity = nullptr;
  // Point positions (m) and mixture volumes V (m²) at the stress update, for a material with
  // a non-local (internal length) law; nullptr when the solver does not pass them.
  const double* x = nullptr;
  const double* y = nullptr;
  const double* volume = nullptr;
};

class SolidMaterial {
 public:
  virtual ~SolidMaterial() = default;
  virtual const std::string& name() const = 0;
  virtual double grain_density() const = 0;  // ρ_s, kg/m³
  // Largest constrained (P-wave) modulus the material can have now, Pa (for the CFL limit).
  virtual double p_wave_modulus() const = 0;
  // Called once when the points [begin, end) are assigned to the material.
  virtual void attach(std::size_t begin, std::size_t end) {
    begin_ = begin;
    end_ = end;
  }
  // Update the stress of all its points for a step dt, given L at the points.
  virtual void update_stress(const StressUpdateView& view, double dt) = 0;
  // A material whose point updates are independent (each reads and writes its own point only,
  // its per-point results combined by finish_ranges) may instead be updated from inside the
  // solver's parallel region, with no fork/join of its own: begin_ranges(T) once, then
  // update_range(view, dt, b, e, t) on every thread t over its part [b, e) of the material's
  // points, then finish_ranges(view) once, which combines the threads' results and throws a
  // failure (update_range must not throw). The same points give the same results either way.
  virtual bool updates_points_independently() const { return false; }
  virtual void begin_ranges(int /*threads*/) {}
  virtual void update_range(const StressUpdateView& /*view*/, double /*dt*/, std::size_t /*b*/,
                            std::size_t /*e*/, int /*t*/) {}
  virtual void finish_ranges(const StressUpdateView& /*view*/) {}
  // Internal state arrays (one value per point of the range), by name, for checkpoint/restart
  // and field output; none for a material without history.
  virtual std::vector<std::pair<std::string, std::vector<double>*>> state() { return {}; }
  std::size_t begin() const { return begin_; }
  std::size_t end() const { return end_; }

 protected:
  std::size_t begin_ = 0, end_ = 0;
};

}  // namespace granflow::mpm
