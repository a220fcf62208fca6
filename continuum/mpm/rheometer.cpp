#include "continuum/mpm/rheometer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <variant>
#include <vector>

#include "continuum/mpm/setup.hpp"

namespace granflow::mpm {

Rheometer make_rheometer(const RheometerSpec& spec) {
  if (!(spec.outer_radius > spec.inner_radius) || !(spec.inner_radius > 0))
    throw std::invalid_argument("rheometer: need 0 < inner_radius < outer_radius");
  const PolarGrid g(spec.inner_radius, spec.outer_radius, spec.cells_r, spec.cells_theta);
  Rheometer r;
  r.solver = std::make_unique<Solver>(g, spec.options, spec.liquid);
  Solver& s = *r.solver;
  // The rheometer is the multi-regime model's problem: its material is built from the typed
  // settings of the case's model sections and the initial state (not a `solid.material` choice).
  auto material = std::make_unique<MultiRegimeMaterial>(
      spec.model,
      MultiRegimeInitialState{spec.effective_pressure, spec.ocr, spec.initial_temperature});
  r.material = material.get();
  const int mat = s.add_material(std::move(material));
  const double n0 = spec.void_ratio / (1.0 + spec.void_ratio);
  const int ppc = spec.points_per_cell;
  add_solid_annulus(s, g, 0, spec.cells_r, ppc, ppc, mat, n0);
  add_liquid_annulus(s, g, 0, spec.cells_r, ppc, ppc, n0, spec.pore_pressure);
  // (ii)-(iii): v_θ(R_out) = a t up to v_max, then held (the solver's linear ramp from t = 0);
  // inner ring fixed; v_r = 0 on both rings; both phases (impermeable, no-slip walls).
  const double ramp = spec.max_velocity / spec.acceleration;
  for (int j = 0; j < g.cells_theta(); ++j) {
    for (Phase ph : {Phase::solid, Phase::liquid}) {
      s.fix_velocity(ph, g.node(0, j), Frame::polar, 0, 0.0);
      s.fix_velocity(ph, g.node(0, j), Frame::polar, 1, 0.0);
      s.fix_velocity(ph, g.node(spec.cells_r, j), Frame::polar, 0, 0.0);
      s.fix_velocity(ph, g.node(spec.cells_r, j), Frame::polar, 1, spec.max_velocity, ramp);
    }
  }
  s.initialize();
  r.material->initialize(s.solid());
  return r;
}

void accumulate_shear_strain(const Solver& solver, std::vector<double>& gamma) {
  const SolidPoints& sp = solver.solid();
  gamma.resize(sp.size(), 0.0);
  const double dt = solver.dt();
  const long n = static_cast<long>(sp.size());
  // per point, no sums: the same for any thread count
#pragma omp parallel for schedule(static) num_threads(solver.threads()) if (solver.threads() > 1)
  for (long p = 0; p < n; ++p) {
    // D_rθ = (D_yy - D_xx) c s + D_xy (c² - s²), c = x/r, s = y/r: with c s = x y / r² and
    // c² - s² = (x² - y²) / r², no square root per point and step
    const double x = sp.x[p], y = sp.y[p];
    const double Dxy = 0.5 * (sp.Lxy[p] + sp.Lyx[p]);
    const double D_rt = ((sp.Lyy[p] - sp.Lxx[p]) * x * y + Dxy * (x * x - y * y)) / (x * x + y * y);
    gamma[p] += 2.0 * D_rt * dt;
  }
}

RheometerAverages rheometer_averages(const Solver& solver, const MultiRegimeMaterial& material,
                                     const std::vector<double>& gamma) {
  const SolidPoints& sp = solver.solid();
  RheometerAverages a;
  double V = 0, n_mean = 0, n2 = 0, vr2 = 0;
  const double fluid_rc = material.point().settings().force_chains
                              ? material.point().settings().force_chain_parameters.fluidization_size
                              : 0.0;
  for (std::size_t p = 0; p < sp.size(); ++p) {
    const double r = std::hypot(sp.x[p], sp.y[p]);
    const double c = sp.x[p] / r, s = sp.y[p] / r;
    const double s_rt = (sp.syy[p] - sp.sxx[p]) * c * s + sp.sxy[p] * (c * c - s * s);
    const double Dxy = 0.5 * (sp.Lxy[p] + sp.Lyx[p]);
    const double D_rt = (sp.Lyy[p] - sp.Lxx[p]) * c * s + Dxy * (c * c - s * s);
    const double v = sp.volume[p];
    V += v;
    a.shear_stress += v * s_rt;
    a.normal_stress += -v * (sp.sxx[p] + sp.syy[p] + sp.szz[p]) / 3.0;
    a.shear_strain += v * (p < gamma.size() ? gamma[p] : 0.0);
    a.shear_rate += v * 2.0 * D_rt;
    n_mean += v * sp.porosity[p];
    n2 += v * sp.porosity[p] * sp.porosity[p];
    const double v_r = sp.vx[p] * c + sp.vy[p] * s;
    vr2 += v * v_r * v_r;
    const std::size_t k = p - material.begin();
    if (p >= material.begin() && p < material.end() && material.locus_size()[k] < fluid_rc)
      a.fluidized_fraction += v;
  }
  a.mixture_volume = V;
  a.shear_stress /= V;
  a.normal_stress /= V;
  a.shear_strain /= V;
  a.shear_rate /= V;
  a.fluidized_fraction /= V;
  n_mean /= V;
  a.porosity_std = std::sqrt(std::max(0.0, n2 / V - n_mean * n_mean));
  a.radial_velocity_rms = std::sqrt(vr2 / V);
  const LiquidPoints& lp = solver.liquid();
  // Rings of the radial cells: p about its ring mean measures the θ-dependent part only (the
  // radial profile of p is physical).
  const auto* grid = std::get_if<PolarGrid>(&solver.grid());
  const int rings = grid ? grid->cells_r() : 1;
  auto ring = [&](std::size_t p) {
    if (!grid) return 0;
    const double r = std::hypot(lp.x[p], lp.y[p]);
    return std::clamp(static_cast<int>((r - grid->inner_radius()) / grid->dr()), 0, rings - 1);
  };
  std::vector<double> ring_V(rings, 0.0), ring_p(rings, 0.0), ring_p2(rings, 0.0);
  for (std::size_t p = 0; p < lp.size(); ++p) {
    const int k = ring(p);
    ring_V[k] += lp.volume[p];
    ring_p[k] += lp.volume[p] * lp.pressure[p];
    ring_p2[k] += lp.volume[p] * lp.pressure[p] * lp.pressure[p];
  }
  double VL = 0, pL = 0, var = 0;
  for (int k = 0; k < rings; ++k) {
    VL += ring_V[k];
    pL += ring_p[k];
    if (ring_V[k] > 0) var += ring_p2[k] - ring_p[k] * ring_p[k] / ring_V[k];
  }
  a.pore_pressure = VL > 0 ? pL / VL : 0.0;
  a.pore_pressure_std = VL > 0 ? std::sqrt(std::max(0.0, var / VL)) : 0.0;
  return a;
}

RheometerProfiles rheometer_profiles(const Solver& solver, const MultiRegimeMaterial& material,
                                     const RheometerSpec& spec, const std::vector<double>& gamma,
                                     int bins) {
  const SolidPoints& sp = solver.solid();
  const double R1 = spec.inner_radius, dr = (spec.outer_radius - R1) / bins;
  const double fluid_rc = material.point().settings().force_chains
                              ? material.point().settings().force_chain_parameters.fluidization_size
                              : 0.0;
  std::vector<double> w(bins, 0.0);
  RheometerProfiles out;
  for (auto* v : {&out.radius, &out.shear_strain, &out.velocity, &out.shear_stress, &out.porosity,
                  &out.locus_size, &out.fluidized_fraction})
    v->assign(bins, 0.0);
  for (std::size_t p = 0; p < sp.size(); ++p) {
    const double r = std::hypot(sp.x[p], sp.y[p]);
    const double c = sp.x[p] / r, s = sp.y[p] / r;
    const int b = std::clamp(static_cast<int>((r - R1) / dr), 0, bins - 1);
    const double V = sp.volume[p];
    w[b] += V;
    out.shear_strain[b] += V * (p < gamma.size() ? gamma[p] : 0.0);
    out.velocity[b] += V * (-sp.vx[p] * s + sp.vy[p] * c);
    out.shear_stress[b] += V * ((sp.syy[p] - sp.sxx[p]) * c * s + sp.sxy[p] * (c * c - s * s));
    out.porosity[b] += V * sp.porosity[p];
    if (p >= material.begin() && p < material.end()) {
      const double rc = material.locus_size()[p - material.begin()];
      out.locus_size[b] += V * rc;
      if (rc < fluid_rc) out.fluidized_fraction[b] += V;
    }
  }
  for (int b = 0; b < bins; ++b) {
    out.radius[b] = R1 + (b + 0.5) * dr;
    if (w[b] > 0)
      for (auto* v : {&out.shear_strain, &out.velocity, &out.shear_stress, &out.porosity,
                      &out.locus_size, &out.fluidized_fraction})
        (*v)[b] /= w[b];
  }
  return out;
}

double inertial_shear_stress(const RheometerSpec& spec) {
  const double R1 = spec.inner_radius, R2 = spec.outer_radius;
  const double nu = 1.0 / (1.0 + spec.void_ratio);
  const double rho = nu * spec.model.collisional_parameters.particle_density +
                     (1.0 - nu) * spec.model.liquid_parameters.density;
  // ∫ r² (r − R1) dr over [R1, R2]
  const double moment =
      (std::pow(R2, 4) - std::pow(R1, 4)) / 4.0 - R1 * (std::pow(R2, 3) - std::pow(R1, 3)) / 3.0;
  return rho * spec.acceleration * moment / ((R2 - R1) * (R2 * R2 - R1 * R1));
}

}  // namespace granflow::mpm
