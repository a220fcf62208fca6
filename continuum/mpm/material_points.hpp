// Material points stored as one array per field, per phase (structure of arrays, as in Karamelo):
// no per-point objects, so the particle loops stream through contiguous memory.
// Sign convention inside the solver: stresses tension-positive; the pore pressure p is
// compression-positive (total stress σ = σ' - p I). The constitutive model is compression-
// positive: docs/model/conventions.md (multi_regime_material.cpp converts).
#pragma once

#include <cstddef>
#include <vector>

namespace granflow::mpm {

// Fields common to both phases.
struct PointFields {
  std::vector<double> x, y;                // position, m
  std::vector<double> vx, vy;              // velocity, m/s
  std::vector<double> mass;                // phase mass carried by the point, kg per m thickness
  std::vector<double> volume;              // mixture volume represented by the point, m² (per m)
  std::vector<double> fx_ext, fy_ext;      // point loads (tractions x boundary length), N per m
  std::vector<double> Lxx, Lxy, Lyx, Lyy;  // velocity gradient ∂v_i/∂x_j at the point, 1/s
  std::size_t size() const { return x.size(); }
};

// Solid points: solid mass, effective stress σ' and model state, porosity, T.
struct SolidPoints : PointFields {
  std::vector<double> sxx, syy, szz, sxy;  // effective stress σ' (plane strain: szz), Pa
  std::vector<double> solid_volume;        // V_s = m / ρ_s (incompressible grains), m²
  std::vector<double> porosity;            // n = 1 - V_s / V
  std::vector<double> temperature;         // granular temperature T, m²/s² (carried)
  std::vector<double> x0, y0;              // initial position (displacements, settlement)
  std::vector<int> material;               // index into the solver's material list
  void resize(std::size_t n);
};

// Liquid points: liquid mass and pore pressure; viscous stress; porosity seen at the point.
struct LiquidPoints : PointFields {
  std::vector<double> pressure;            // p, compression-positive, Pa
  std::vector<double> txx, tyy, tzz, txy;  // viscous (deviatoric) stress 2 η dev(D_L), Pa
  std::vector<double> porosity;            // n interpolated from the nodes at the point
  std::vector<double> drag;                // β(n) at the point, kg/(m³ s)
  std::vector<double> x0, y0;
  void resize(std::size_t n);
};

}  // namespace granflow::mpm
