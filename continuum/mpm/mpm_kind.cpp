// The `mpm` case kind's side of the case files: the schemas of its problems, their checks and
// their registration. The runs: kind_terzaghi.cpp, kind_couette.cpp, kind_column.cpp,
// kind_rheometer.cpp (kind_run.hpp has what they share).
#include "continuum/mpm/mpm_kind.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "continuum/model/closures.hpp"
#include "continuum/mpm/kind_geometry.hpp"
#include "continuum/mpm/kind_run.hpp"
#include "continuum/mpm/material_registry.hpp"
#include "continuum/sections/model_sections.hpp"

namespace granflow::mpm {

namespace {

// ---- schema -------------------------------------------------------------------------------------

struct NumericsDefaults {
  const char* local_damping = "0.0";
  const char* smoothing = "false";
};

void add_numerics(core::Schema& s, NumericsDefaults d) {
  auto& n = s.section("numerics", "MPM algorithm choices (docs/mpm.md)");
  n.choice("shape", {"linear", "gimp"}, "shape functions (gimp: Cartesian grids only)")
      .default_value("linear");
  n.choice("scheme", {"musl", "usl"}, "update scheme: modified USL or USL").default_value("musl");
  n.number("flip", "1",
           "FLIP fraction of each step's point velocity update (1 FLIP, 0 PIC); 1 when neither "
           "it nor pic_relaxation_time is given")
      .at_least(0)
      .at_most(1);
  n.number("pic_relaxation_time", "s",
           "PIC relaxation time t_PIC instead of flip: per-step FLIP fraction exp(−Δt/t_PIC), "
           "so the PIC damping per unit time does not depend on Δt (docs/mpm.md)")
      .greater_than(0);
  n.number("local_damping", "1", "Cundall local damping coefficient α")
      .default_value(d.local_damping)
      .at_least(0)
      .less_than(1);
  n.number("cfl_factor", "1", "Δt = factor × critical step (CFL over both phases, viscous, drag)")
      .default_value("0.5")
      .greater_than(0)
      .at_most(1);
  n.number("time_step", "s", "fixed Δt (0: from the critical step); the critical one is reported")
      .default_value("0")
      .at_least(0);
  n.number("mass_scaling", "1", "inertial masses × this factor (a reported modelling choice)")
      .default_value("1")
      .at_least(1);
  n.choice("drag_integration", {"semi_implicit", "explicit"},
           "nodal drag: backward Euler in the drag (stable for any β) or explicit Euler "
           "(then Δt also obeys the drag time scale)")
      .default_value("semi_implicit");
  n.boolean("liquid_volumetric_smoothing",
            "cell-averaged volumetric rate and cell-constant liquid pressure (linear shapes)")
      .default_value(d.smoothing);
  n.number("pressure_relaxation_time", "s",
           "t_p: the pore pressure relaxes towards its nodal average at the rate 1/t_p (removes "
           "the cell-to-cell checkerboard of p; 0 = off; linear shapes; docs/mpm.md)")
      .default_value("0")
      .at_least(0);
  n.integer("threads", "OpenMP threads (0: one per 10,000 points, at most OMP_NUM_THREADS)")
      .default_value("0")
      .at_least(0);
  auto& o = s.section("output", "field files and checkpoint");
  o.integer("frames", "HDF5+XDMF field outputs evenly spaced in time, plus t = 0 (0: none)")
      .default_value("10")
      .at_least(0);
  o.boolean("checkpoint", "write checkpoint.h5 (all point arrays and the clock) at the end")
      .default_value("false");
  o.string("restart_from", "checkpoint file to continue from (same case)");
}

core::Schema terzaghi_schema() {
  core::Schema s = core::kind_header(
      "mpm", "terzaghi",
      "Terzaghi 1D consolidation with the two-phase double-point MPM: drained top, impermeable "
      "base, pore pressure isochrones and settlement against the analytic series.");
  kind::box_geometry(s, {"0.1", "1.0", "0.1", "layer"});
  auto& m = s.section("solid", "solid skeleton (solid points)");
  material_registry().declare(
      m, {{"young_modulus", "1.0e7"}, {"poisson_ratio", "0.0"}, {"density", "2650"}});
  m.number("porosity", "1", "n").default_value("0.3").greater_than(0).less_than(1);
  auto& l = s.section("liquid", "pore liquid (liquid points)");
  l.number("density", "kg/m^3", "ρ_w").default_value("1000").greater_than(0);
  l.number("bulk_modulus", "Pa", "K_w (2.2e9 for water; a reduced value is a reported choice)")
      .default_value("1.0e8")
      .greater_than(0);
  l.number("hydraulic_conductivity", "m/s", "Darcy k_D: β = n² ρ_w g / k_D")
      .default_value("1.0e-3")
      .greater_than(0);
  l.number("darcy_gravity", "m/s^2", "g in γ_w = ρ_w g of k_D")
      .default_value("9.81")
      .greater_than(0);
  l.choice("drag_law", {"darcy", "closure"},
           "darcy: β = n² γ_w / k_D; closure: β = η0 n / κ(ν) of model::drag_coefficient (the "
           "REV/DEM closure; the analytic check uses the equivalent k_D = n γ_w κ / η0)")
      .default_value("darcy");
  l.number("viscosity", "Pa s", "η0 (closure drag)").default_value("1.0e-3").greater_than(0);
  l.number("grain_diameter", "m", "d of the permeability closure")
      .default_value("1.0e-3")
      .greater_than(0);
  l.choice("permeability", model::permeability_names(),
           "permeability closure (docs/model/closures.md)")
      .default_value("seed_eq26");
  l.number("sphericity", "1", "A of seed Eq. 26").default_value("1.0").greater_than(0);
  auto& ld = s.section("loading", "surface load");
  ld.number("load", "Pa", "total-stress load q on the top").default_value("1.0e4").greater_than(0);
  ld.boolean("undrained_start",
             "start from the undrained state at t = 0+ (Terzaghi's initial condition); false: "
             "sudden load on an unstressed column")
      .default_value("true");
  auto& r = s.section("run", "duration and checks");
  r.number_list("isochrones", "1",
                "time factors T_v = c_v t / H² of the checked isochrones; the "
                "run ends at the last")
      .default_value("[0.05, 0.2, 0.5]")
      .greater_than(0);
  add_numerics(s, {});
  return s;
}

core::Schema couette_schema() {
  core::Schema s = core::kind_header(
      "mpm", "couette",
      "Couette flow of a Newtonian liquid alone between two cylinders on the polar O-grid: the "
      "steady v_θ = A r + B / r.");
  kind::annulus_geometry(s, {"1.0", "2.0", "10", "64", "fixed wall", "moving wall", 1, false});
  auto& l = s.section("liquid", "liquid points");
  l.number("density", "kg/m^3", "ρ_w").default_value("1000").greater_than(0);
  l.number("viscosity", "Pa s", "Newtonian viscosity η0").default_value("1000").greater_than(0);
  l.number("bulk_modulus", "Pa", "K_w (reduced: a reported choice)")
      .default_value("1.0e6")
      .greater_than(0);
  auto& ld = s.section("loading", "wall motion");
  ld.number("wall_velocity", "m/s", "v_θ of the outer wall").default_value("1.0").greater_than(0);
  auto& r = s.section("run", "duration and checks");
  r.number("end_time", "s", "simulated time").default_value("2.0").greater_than(0);
  r.number("average_from", "s", "grid velocity averaged from this time to the end")
      .default_value("1.5")
      .at_least(0);
  add_numerics(s, {"0.0", "true"});
  return s;
}

core::Schema column_schema() {
  core::Schema s = core::kind_header(
      "mpm", "elastic_column",
      "Elastic column under gravity on a fixed base with roller sides, brought to rest with local "
      "damping: σ_yy = -ρ g (H - y) at the points.");
  kind::box_geometry(s, {"0.2", "1.0", "0.05", "column"});
  auto& m = s.section("solid", "solid points");
  material_registry().declare(
      m, {{"young_modulus", "1.0e6"}, {"poisson_ratio", "0.3"}, {"density", "2000"}});
  auto& ld = s.section("loading", "body force");
  ld.number("gravity", "m/s^2", "g").default_value("9.81").greater_than(0);
  auto& r = s.section("run", "duration");
  r.number("end_time", "s", "simulated time").default_value("1.5").greater_than(0);
  add_numerics(s, {"0.3", "false"});
  return s;
}

// ---- checks ------------------------------------------------------------------------------------

void check_common(const core::Case& c) {
  if (c.has("numerics.flip") && c.has("numerics.pic_relaxation_time"))
    c.fail("numerics.pic_relaxation_time",
           "either numerics.flip (per step) or numerics.pic_relaxation_time (per unit time), "
           "not both");
  if (c.boolean("numerics.liquid_volumetric_smoothing") && c.string("numerics.shape") == "gimp")
    c.fail("numerics.liquid_volumetric_smoothing", "false with gimp (cell averaging needs linear)");
  if (c.number("numerics.pressure_relaxation_time") > 0 && c.string("numerics.shape") == "gimp")
    c.fail("numerics.pressure_relaxation_time", "0 with gimp (nodal averaging with linear shapes)");
}

// terzaghi and elastic_column
void check_box_problem(const core::Case& c) {
  check_common(c);
  kind::check_box(c);
}

void check_couette(const core::Case& c) {
  check_common(c);
  kind::check_annulus(c);
  if (!(c.number("run.average_from") < c.number("run.end_time")))
    c.fail("run.average_from", "a time < run.end_time");
  // The error is measured at the interior node rings (the two walls are prescribed).
  if (c.integer("geometry.cells_r") < 2)
    c.fail("geometry.cells_r",
           "at least 2 (the velocity error is measured at the interior node rings; one radial "
           "cell has none)");
}

// ---- rheometer (docs/rheometer.md) -------------------------------------------------------------

core::Schema rheometer_schema() {
  core::Schema s = core::kind_header(
      "mpm", "rheometer",
      "The seed's undrained constant-volume annular rheometer (section 6) with the double-point "
      "MPM and the multi-regime material: outer ring v_θ = a t up to v_max, inner ring fixed.");
  kind::annulus_geometry(s, {"0.08", "0.11", "8", "96", "fixed ring", "moving ring", 2, true});
  s.add(continuum::material_section());
  s.add(continuum::force_chains_section());
  s.add(continuum::collisional_section());
  s.add(continuum::liquid_section());
  auto& sl = s.section("solid", "internal length of the skeleton's softening (docs/rheometer.md)");
  sl.number("internal_length", "m",
            "ℓ of the non-local average of the locus softening, w = exp(-(r/ℓ)²) over 2.5 ℓ "
            "(Bažant & Jirásek 2002); 0 = local model")
      .default_value("0")
      .at_least(0);
  sl.number("overnonlocal", "1",
            "m of r_c ← r_c (1 + m δ̄ + (1 − m) δ): 1 non-local, > 1 over-nonlocal (Vermeer & "
            "Brinkgreve 1994; m = 1 still localizes into one spacing, docs/rheometer.md)")
      .default_value("2")
      .at_least(1);
  auto& i = s.section("initial", "state after the drained isotropic consolidation (phase i)");
  i.number("void_ratio", "1", "e0").default_value("0.818").greater_than(0);
  i.number("effective_pressure", "Pa", "p'0 (σ_FC = p'0 I)").default_value("50.0e3").at_least(0);
  i.number("pore_pressure", "Pa", "u_w0").default_value("50.0e3").at_least(0);
  i.number("ocr", "1", "r_c / (√3 p'0)").default_value("1.0").at_least(1);
  i.number("temperature", "m^2/s^2", "T0").default_value("0").at_least(0);
  auto& ld = s.section("loading", "outer ring (phases ii and iii)");
  ld.number("acceleration", "m/s^2", "a of v_θ = a t").default_value("333").greater_than(0);
  ld.number("max_velocity", "m/s", "v_max held in phase iii")
      .default_value("1.0")
      .greater_than(0)
      .sweepable();
  auto& r = s.section("run", "duration and output");
  r.number("end_time", "s", "simulated time").default_value("0.02").greater_than(0);
  r.number_list("profile_times", "s", "times of the radial profiles (γ, v_θ)")
      .default_value("[0.002, 0.005, 0.01, 0.02]")
      .greater_than(0);
  r.integer("profile_bins", "radial bins of the profiles").default_value("16").at_least(2);
  r.integer("sample_every", "steps between samples of the averaged series")
      .default_value("20")
      .at_least(1);
  r.boolean("conduct_temperature",
            "conduct T through the nodes with the collisional conductivity ρ_p d f4 T^½")
      .default_value("true");
  r.boolean("closed_domain",
            "remove the volume-weighted mean of the liquid's volumetric rate (closed rigid "
            "annulus: its exact integral is zero; point quadrature leaves a drift of p̄)")
      .default_value("false");
  r.number("steady_fraction", "1", "steady values: means over this last fraction of the run")
      .default_value("0.2")
      .greater_than(0)
      .at_most(1);
  add_numerics(s, {"0.0", "true"});
  return s;
}

void check_rheometer(const core::Case& c) {
  check_common(c);
  kind::check_annulus(c);
  if (!c.boolean("force_chains.enabled"))
    c.fail("force_chains.enabled", "true (the rheometer needs the skeleton)");
  // The initial solid fraction below the packing limits of the closures, as the REV tests.
  const auto settings = continuum::read_multi_regime_settings(c);
  const double nu0 = 1.0 / (1.0 + c.number("initial.void_ratio"));
  if (settings.collisional && nu0 >= model::maximum_solid_fraction(settings.collisional_parameters))
    c.fail(
        "initial.void_ratio",
        fmt::format("solid fraction 1/(1+e0) = {:.6g} is at or beyond collisional."
                    "jamming_fraction {:.6g} where g0 diverges; expected e0 > {:.6g} or a larger "
                    "jamming fraction",
                    nu0, settings.collisional_parameters.jamming_fraction,
                    1.0 / settings.collisional_parameters.jamming_fraction - 1.0));
  if (settings.liquid && nu0 >= model::maximum_mixture_solid_fraction(settings.liquid_parameters))
    c.fail("initial.void_ratio",
           fmt::format("solid fraction 1/(1+e0) = {:.6g} is at or beyond liquid.maximum_packing "
                       "{:.6g} where η(ν) diverges; expected e0 > {:.6g}",
                       nu0, settings.liquid_parameters.maximum_packing,
                       1.0 / settings.liquid_parameters.maximum_packing - 1.0));
}

}  // namespace

void register_mpm_kinds(core::KindRegistry& registry) {
  registry.add({"mpm", "terzaghi", "Terzaghi consolidation, two-phase double-point MPM",
                terzaghi_schema(), check_box_problem, kind::run_terzaghi, "cases/mpm/terzaghi.yaml",
                kind::terzaghi_inputs});
  registry.add({"mpm", "couette", "Couette flow of the liquid in an annulus (polar grid)",
                couette_schema(), check_couette, kind::run_couette, "cases/mpm/couette.yaml",
                kind::couette_inputs});
  registry.add({"mpm", "elastic_column", "elastic column under gravity, at rest", column_schema(),
                check_box_problem, kind::run_column, "cases/mpm/elastic_column.yaml",
                kind::column_inputs});
  core::KindEntry rheometer{
      "mpm",
      "rheometer",
      "undrained constant-volume annular rheometer with the multi-regime material",
      rheometer_schema(),
      check_rheometer,
      kind::run_rheometer,
      "cases/mpm/rheometer_test1.yaml",
      kind::rheometer_inputs};
  rheometer.convergence_study = "analysis/rheometer_study.py";
  registry.add(std::move(rheometer));
}

}  // namespace granflow::mpm
