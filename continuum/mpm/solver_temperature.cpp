// Conduction of the granular temperature among the solid points through the nodes (seed section
// 5): q = -κ_T ∇T with a constant κ_T or the one each material reports per point.
#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

template <class G, ShapeKind S>
void Solver::conduct_temperature(const G& grid) {
  const int nn = nn_;
  const double kappa = options_.temperature_conductivity, dt = dt_;
  SolidPoints& sp = solid_;
  scatter(2, [&](double* acc, int t, int T) {
    std::size_t b, e;
    chunk(sp.size(), t, T, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;  // caught in the next map
      const double c = 1.5 * sp.mass[p], cT = c * sp.temperature[p];
      for (int k = 0; k < st.count; ++k) {
        acc[st.node[k]] += st.N[k] * c;
        acc[nn + st.node[k]] += st.N[k] * cT;
      }
    }
  });
  cache_[0].valid = true;
  std::vector<double>& A = acc_;
  std::vector<double>& nodal_T = nodal_temperature_;
  std::vector<double>& capacity = heat_capacity_;
  for (int a = 0; a < nn; ++a) {
    capacity[a] = A[a];
    nodal_T[a] = A[a] > 0 ? A[nn + a] / A[a] : 0.0;
  }
  const long np = static_cast<long>(sp.size());
#pragma omp parallel num_threads(threads_) if (threads_ > 1)
  {
    Stencil st{};
#pragma omp for schedule(static)
    for (long p = 0; p < np; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;
      double gx = 0, gy = 0;
      for (int k = 0; k < st.count; ++k) {
        gx += st.dNdx[k] * nodal_T[st.node[k]];
        gy += st.dNdy[k] * nodal_T[st.node[k]];
      }
      temperature_gradient_x_[p] = gx;
      temperature_gradient_y_[p] = gy;
    }
  }
  scatter(1, [&](double* acc, int t, int T) {
    std::size_t b, e;
    chunk(sp.size(), t, T, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;
      const double kappa_p = options_.material_conductivity ? point_conductivity_[p] : kappa;
      const double qx = kappa_p * temperature_gradient_x_[p] * sp.volume[p];
      const double qy = kappa_p * temperature_gradient_y_[p] * sp.volume[p];
      for (int k = 0; k < st.count; ++k) acc[st.node[k]] -= st.dNdx[k] * qx + st.dNdy[k] * qy;
    }
  });
  for (int a = 0; a < nn; ++a) A[a] = capacity[a] > 0 ? dt * A[a] / capacity[a] : 0.0;  // ΔT_a
  long negative = -1;
#pragma omp parallel num_threads(threads_) if (threads_ > 1) reduction(max : negative)
  {
    Stencil st{};
#pragma omp for schedule(static)
    for (long p = 0; p < np; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;
      // Remap of the nodal change ΔT_a to the points. Heating: N_a ΔT_a (additive). Cooling:
      // each point gives up its share in proportion to its own T, N_a ΔT_a T_p / T_a, with T_a the
      // capacity-weighted nodal T. Both conserve the energy of node a exactly
      // (Σ_p c_p N_a ΔT_a T_p / T_a = ΔT_a C_a), and a cooling point keeps T_p ≥ 0 whenever the
      // nodal update keeps T_a + ΔT_a ≥ 0 (the explicit conduction limit), which the additive form
      // does not guarantee for a cold point next to hot ones.
      const double Tp = sp.temperature[p];
      double dT = 0;
      for (int k = 0; k < st.count; ++k) {
        const int a = st.node[k];
        const double dTa = A[a];
        if (dTa >= 0.0)
          dT += st.N[k] * dTa;
        else if (nodal_T[a] > 0.0)
          dT += st.N[k] * dTa * (Tp / nodal_T[a]);
      }
      sp.temperature[p] = Tp + dT;
      if (!(sp.temperature[p] >= 0.0)) negative = std::max(negative, p);
    }
  }
  if (negative >= 0) {
    throw core::NumericalFailure(step_ + 1, fmt::format("solid point {}", negative), "temperature",
                                 sp.temperature[negative],
                                 "negative or non-finite granular temperature");
  }
}

// For the grids and shapes step() runs (solver_maps.cpp).
template void Solver::conduct_temperature<CartesianGrid, ShapeKind::linear>(const CartesianGrid&);
template void Solver::conduct_temperature<CartesianGrid, ShapeKind::gimp>(const CartesianGrid&);
template void Solver::conduct_temperature<PolarGrid, ShapeKind::linear>(const PolarGrid&);

}  // namespace granflow::mpm
