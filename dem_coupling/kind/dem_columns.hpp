// The DEM kind's result tables, defined once (docs/results.md): each row maps the key of a steady
// value (PointResult::values, the steady.KEY of summary.json) or a granflow-dem series column
// (series.tsv) to its dataset name, unit and meaning in result.h5 (core/result_columns.hpp). The
// writer (dem_kind.cpp, point_analysis.cpp), the readers (dem_fits_file.hpp, analysis/calibration)
// and `granflow results --markdown` use these tables; Python reads the names from the file.
//   /steady               one row per point: dem_steady_columns (+ dem_wet_steady_columns)
//   /conditions/N/steady  the same names as attributes, plus dem_point_columns
//   /conditions/N/series  dem_series_columns (+ dem_wet_series_columns)
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "core/result_columns.hpp"

namespace granflow::dem {

struct DemColumn {
  const char* key;     // PointResult::values key (summary.json steady.KEY) or series.tsv column
  core::Column column;  // dataset name, unit, meaning
  bool error = false;    // a standard error KEY_err is written as NAME_err, same unit
  bool integer = false;  // a count or a flag: written as an integer
};

namespace dem_columns {
using core::columns::described;
namespace c = core::columns;

inline constexpr DemColumn steady[] = {
    {"mu", described(c::friction, "μ = <τ>/<σ_yy> (ratio of the steady means; error by the delta "
                                  "method on τ − μ σ_yy)"),
     true},
    {"phi", c::solid_fraction, true},
    {"e", c::void_ratio, true},
    {"T", described(c::granular_temperature, "T about the Lees-Edwards streaming profile"), true},
    {"T_scaled", c::scaled_temperature},
    {"p", described(c::normal_stress, "normal stress σ_yy = P_yy (the stress that μ, I and J use)"),
     true},
    {"p_mean", described(c::mean_stress, "mean stress tr(P)/3"), true},
    {"tau", described(c::shear_stress, "shear stress τ = −P_xy"), true},
    {"I", described(c::inertial_number, "I = γ̇ d / √(<σ_yy>/ρ_p), d the mean diameter"), true},
    {"Z", c::coordination_number, true},
    {"start_strain", described(c::steady_start_strain,
                               "strain where the steady window starts (latest MSER-5 truncation "
                               "of σ_yy, τ, φ, T)")},
    {"reached", described(c::steady_reached,
                          "1 when no observable drifts by more than 3 standard errors over the "
                          "window (and T is not frozen), else 0"),
     false, true},
    {"drift_max",
     {"drift_max", "1",
      "largest |second half − first half| of the window over the observables, in standard errors"}},
    {"profile_deviation",
     {"profile_deviation", "1", "RMS deviation of the mean v_x profile from the line / (γ̇ L_y)"}},
};

inline constexpr DemColumn wet_steady[] = {
    {"eta", c::liquid_viscosity},
    {"St", c::stokes_number},
    {"J", described(c::viscous_number, "J = η0 γ̇ / <σ_yy>"), true},
    {"K", described(c::mixed_number, "K = J + α I² (α = liquid.trulsson_alpha) [Trulsson2012]"),
     true},
    {"tau_contact", {"shear_stress_contact", "Pa", "contact part of τ"}, true},
    {"tau_lub", {"shear_stress_lubrication", "Pa", "lubrication part of τ"}, true},
    {"tau_drag", {"shear_stress_drag", "Pa", "drag part of τ"}, true},
    {"tau_kin", {"shear_stress_kinetic", "Pa", "kinetic part of τ"}, true},
    {"mu_contact",
     {"friction_contact", "1", "τ_contact/σ_yy (ratio of the steady means; delta-method error)"},
     true},
    {"mu_lub",
     {"friction_lubrication", "1", "τ_lub/σ_yy (ratio of the steady means; delta-method error)"},
     true},
};

// The imposed conditions and costs of each point (/steady).
inline constexpr core::Column shear_rate = c::shear_rate;
inline constexpr core::Column particle_friction = c::particle_friction;
inline constexpr core::Column normal_stress_target = c::normal_stress_target;
inline constexpr core::Column solid_fraction_target = c::solid_fraction_target;
inline constexpr core::Column time_step{"time_step", "s", "DEM time step Δt"};
inline constexpr core::Column wall_time{"wall_time", "s", "wall-clock time of the point"};

// Only in /conditions/N/steady (attributes); drift.KEY is written as drift_NAME.
inline constexpr DemColumn point[] = {
    {"overlap", {"relative_overlap", "1", "mean overlap <δ>/d of the touching pairs"}, true},
    {"end_strain", {"steady_end_strain", "1", "strain of the last sample"}},
    {"samples", {"steady_samples", "1", "samples in the steady window"}, false, true},
    {"tau_int_mu",
     {"friction_correlation_samples", "1",
      "integrated autocorrelation time of τ − μ σ_yy, in samples"}},
    {"p_rel_dev",
     {"normal_stress_relative_deviation", "1", "<σ_yy>/σ_yy,target − 1 (constant_pressure)"}},
    {"normal_stress_miss_se",
     {"normal_stress_miss", "1", "(<σ_yy> − σ_yy,target) / se(<σ_yy>) (constant_pressure)"}},
    {"normal_stress_on_target",
     {"normal_stress_on_target", "1", "1 when |normal_stress_miss| <= 2, else 0"}, false, true},
    {"frozen",
     {"frozen", "1", "1 when T/(d γ̇)² < 1e-4: spheres on streamlines without collisions"},
     false, true},
};

// strain.target_error (docs/dem_dataset.md, "Error-targeted run length"): the run-length keys of
// a point (PointResult::run_length, summary.json strain.KEY) and their names, as /conditions/N
// attributes (point_analysis.cpp) and /steady columns (dem_kind.cpp: strain_used, target_met,
// achieved_error_NAME, target_met_NAME). Per observable NAME of target_observables
// (deck/driver_parameters.hpp) the key PREFIX.NAME is named NAME_PREFIX_NAME: the second table
// holds the key prefix and the name prefix.
inline constexpr DemColumn run_length[] = {
    {"used", {"strain_used", "1", "shear strain the point ran (strain.target_error)"}},
    {"max", {"strain_max", "1", "largest shear strain of the point (strain.max)"}},
    {"target_met",
     {"target_met", "1",
      "1 when the window is steady and every target of strain.target_error is met at the end, "
      "else 0"},
     false, true},
};
inline constexpr DemColumn run_length_per_observable[] = {
    {"target_error.", {"target_error_", "1", "error target of the observable"}},
    {"achieved_error.",
     {"achieved_error_", "1",
      "standard error of the observable as strain.target_error measures it (se(μ)/μ, se(φ), "
      "se(T)/T)"}},
    {"target_met.",
     {"target_met_", "1", "1 when the error target of the observable is met, else 0"}, false, true},
};

// The contact network without rattlers (extraction/contact_network.hpp), one definition for the
// preparation, the transient series and their seed bands.
inline constexpr core::Column coordination_number_nonrattler{
    "coordination_number_nonrattler", "1",
    "coordination number Z* without rattlers (< 2 contacts, removed repeatedly)"};
inline constexpr core::Column nonrattler_fraction{
    "nonrattler_fraction", "1", "fraction of the particles that are not rattlers"};
inline constexpr core::Column fabric_anisotropy{"fabric_anisotropy", "1",
                                                "fabric anisotropy sqrt(3/2 F':F')"};
// series.tsv columns of a run from a preparation (/conditions/N/series).
inline constexpr DemColumn network_series[] = {
    {"Z_nr", coordination_number_nonrattler},
    {"nonrattler_fraction", nonrattler_fraction},
    {"fabric_xy", {"fabric_xy", "1", "xy entry of the trace-free fabric <n n> − I/3"}},
    {"anisotropy", fabric_anisotropy},
};

// A preparation (kind: dem_prepare, driver/prepare_stage.cpp): the columns of prepared.tsv (the
// state at rest, one row; /prepared, one row per seed) and of prepare.tsv (the compression
// history, one row per servo update; /seeds/K/series), and their dataset names.
inline constexpr DemColumn preparation[] = {
    {"phi", described(c::solid_fraction, "solid fraction φ0")},
    {"p", described(c::mean_stress, "mean stress p0 = tr(P)/3")},
    {"sigma_yy", described(c::normal_stress, "normal stress σ_yy = P_yy")},
    {"Z", described(c::coordination_number, "coordination number Z = 2 N_c / N")},
    {"Z_nr", coordination_number_nonrattler},
    {"nonrattler_fraction", nonrattler_fraction},
    {"fabric_xx", {"fabric_xx", "1", "trace-free fabric <n n> − I/3 of the non-rattler contacts, xx"}},
    {"fabric_yy", {"fabric_yy", "1", "trace-free fabric, yy"}},
    {"fabric_zz", {"fabric_zz", "1", "trace-free fabric, zz"}},
    {"fabric_xy", {"fabric_xy", "1", "trace-free fabric, xy"}},
    {"fabric_xz", {"fabric_xz", "1", "trace-free fabric, xz"}},
    {"fabric_yz", {"fabric_yz", "1", "trace-free fabric, yz"}},
    {"anisotropy", fabric_anisotropy},
    {"energy_ratio", {"kinetic_elastic_energy_ratio", "1",
                      "kinetic (translation + rotation) / elastic energy of the contacts"}},
    {"kinetic_energy", {"kinetic_energy", "J", "kinetic energy, translation + rotation"}},
    {"elastic_energy", {"elastic_energy", "J", "normal elastic energy of the contacts"}},
    {"overlap", {"mean_overlap", "m", "mean overlap <δ> of the touching pairs"}},
    {"d_mean", {"mean_diameter", "m", "number-mean particle diameter"}},
    {"lx", {"box_length_x", "m", "box edge L_x"}},
    {"ly", {"box_length_y", "m", "box edge L_y"}},
    {"lz", {"box_length_z", "m", "box edge L_z"}},
    {"volume", {"box_volume", "m^3", "box volume"}},
    {"P_xx", {"stress_xx", "Pa", "total stress P_xx (compression positive)"}},
    {"P_yy", {"stress_yy", "Pa", "total stress P_yy"}},
    {"P_zz", {"stress_zz", "Pa", "total stress P_zz"}},
    {"P_xy", {"stress_xy", "Pa", "total stress P_xy"}},
    {"P_xz", {"stress_xz", "Pa", "total stress P_xz"}},
    {"P_yz", {"stress_yz", "Pa", "total stress P_yz"}},
    {"at_target", {"at_target", "1", "1 when |p − p0| <= tolerance p0 at this update"}},
    {"at_rest", {"at_rest", "1", "1 when the kinetic/elastic energy ratio is at most its limit"}},
    {"particles", {"particles", "1", "number of spheres"}},
    {"step", {"step", "1", "LIGGGHTS time step number"}},
    {"time", described(c::time, "time since the start of the compression")},
};

// granflow-dem's series.tsv columns (dem_coupling/driver) and their datasets in
// /conditions/N/series.
inline constexpr DemColumn series[] = {
    {"step", {"step", "1", "LIGGGHTS time step number"}},
    {"time", described(c::time, "time since the start of shear")},
    {"strain", c::strain},
    {"ly", {"box_height", "m", "box height L_y"}},
    {"xy", {"box_tilt", "m", "tilt of the Lees-Edwards box"}},
    {"volume", {"box_volume", "m^3", "box volume"}},
    {"Pvir_yy", {"contact_normal_stress", "Pa", "contact (virial) normal stress P^vir_yy"}},
    {"Pvir_xy", {"contact_stress_xy", "Pa", "contact (virial) shear component P^vir_xy"}},
    {"Pkin_yy", {"kinetic_normal_stress", "Pa", "kinetic normal stress about the profile"}},
    {"Pkin_xy", {"kinetic_stress_xy", "Pa", "kinetic shear component about the profile"}},
    {"P_xx", {"stress_xx", "Pa", "total stress P_xx (compression positive)"}},
    {"P_yy", {"stress_yy", "Pa", "total stress P_yy"}},
    {"P_zz", {"stress_zz", "Pa", "total stress P_zz"}},
    {"P_xy", {"stress_xy", "Pa", "total stress P_xy"}},
    {"sigma_yy", described(c::normal_stress, "normal stress σ_yy = P_yy")},
    {"tau", described(c::shear_stress, "shear stress τ = −P_xy")},
    {"p", described(c::mean_stress, "mean stress tr(P)/3")},
    {"mu", described(c::friction, "stress ratio τ/σ_yy of the sample")},
    {"T", described(c::granular_temperature, "T about the Lees-Edwards streaming profile")},
    {"phi", c::solid_fraction},
    {"e", c::void_ratio},
    {"I", described(c::inertial_number, "I = γ̇ d / √(σ_yy/ρ_p) of the sample")},
    {"Z", c::coordination_number},
    {"momentum_x", {"momentum_x", "kg m/s", "peculiar momentum Σ m (v_x − u_x(y))"}},
    {"momentum_y", {"momentum_y", "kg m/s", "momentum Σ m v_y"}},
    {"momentum_z", {"momentum_z", "kg m/s", "momentum Σ m v_z"}},
    {"profile_deviation",
     {"profile_deviation", "1", "RMS deviation of the mean v_x profile from the line / (γ̇ L_y)"}},
    {"overlap", {"mean_overlap", "m", "mean overlap <δ> of the touching pairs"}},
};

// Immersed runs only: the shear-stress split (docs/dem_fluid.md; the parts sum to τ).
inline constexpr DemColumn wet_series[] = {
    {"tau_contact", {"shear_stress_contact", "Pa", "contact shear stress −P^vir_xy − τ_lub − τ_drag"}},
    {"tau_lub", {"shear_stress_lubrication", "Pa", "lubrication shear stress −(P_lub,n,xy + P_lub,t,xy)"}},
    {"tau_drag", {"shear_stress_drag", "Pa", "drag shear stress −P_drag,xy"}},
    {"tau_kin", {"shear_stress_kinetic", "Pa", "kinetic shear stress −P^kin_xy"}},
    {"lubricated_pairs", {"lubricated_pairs", "1", "number of pairs with h < h_max"}},
};

// A transient from a prepared packing (dem_coupling/kind/transient.hpp): the series.tsv columns
// whose seed mean and band are written to /transient/group_G as NAME_mean, NAME_min, NAME_max.
// The first two rows are the ones the transient metrics use (p', τ).
inline constexpr DemColumn transient_band[] = {
    {"p", described(c::mean_stress,
                    "effective mean stress p' = tr(P)/3 (immersed: without the hydrodynamic part)")},
    {"tau", described(c::shear_stress, "shear stress τ = −P_xy")},
    {"sigma_yy", described(c::normal_stress, "normal stress σ_yy = P_yy")},
    {"T", described(c::granular_temperature, "T about the Lees-Edwards streaming profile")},
    {"Z_nr", coordination_number_nonrattler},
    {"nonrattler_fraction", nonrattler_fraction},
    {"phi", c::solid_fraction},
};
inline constexpr const char* band_mean = "_mean";  // seed mean, sample by sample
inline constexpr const char* band_min = "_min";    // lowest seed
inline constexpr const char* band_max = "_max";    // highest seed

}  // namespace dem_columns

// The row of `key` in `table`, or nullptr.
inline const DemColumn* find_dem_column(std::span<const DemColumn> table, std::string_view key) {
  for (const DemColumn& column : table)
    if (key == column.key) return &column;
  return nullptr;
}

// The dataset name of a steady value (steady, wet_steady and point tables; KEY_err is NAME_err,
// drift.KEY is drift_NAME); a key of none of them keeps its own name.
inline std::string dem_steady_name(std::string_view key) {
  if (key.starts_with("drift.")) return "drift_" + dem_steady_name(key.substr(6));
  for (std::span<const DemColumn> table :
       {std::span<const DemColumn>(dem_columns::steady),
        std::span<const DemColumn>(dem_columns::wet_steady),
        std::span<const DemColumn>(dem_columns::point)}) {
    if (const DemColumn* c = find_dem_column(table, key)) return c->column.name;
    if (key.ends_with("_err"))
      if (const DemColumn* c = find_dem_column(table, key.substr(0, key.size() - 4));
          c && c->error)
        return std::string(c->column.name) + "_err";
  }
  return std::string(key);
}

// The name of a run-length key (run_length tables): "used" -> strain_used, "achieved_error.phi"
// style keys PREFIX.NAME -> NAME_PREFIX + NAME; a key of neither keeps its own name.
inline std::string dem_run_length_name(std::string_view key) {
  if (const DemColumn* c = find_dem_column(dem_columns::run_length, key)) return c->column.name;
  for (const DemColumn& c : dem_columns::run_length_per_observable)
    if (key.starts_with(c.key))
      return std::string(c.column.name) + std::string(key.substr(std::string_view(c.key).size()));
  return std::string(key);
}

// The dataset name of a granflow-dem series column (series and wet_series tables).
inline std::string dem_series_name(std::string_view key) {
  if (const DemColumn* c = find_dem_column(dem_columns::series, key)) return c->column.name;
  if (const DemColumn* c = find_dem_column(dem_columns::wet_series, key)) return c->column.name;
  return std::string(key);
}

// Whether the steady value `key` is a count or a flag (written as an integer).
inline bool dem_steady_integer(std::string_view key) {
  for (std::span<const DemColumn> table :
       {std::span<const DemColumn>(dem_columns::steady),
        std::span<const DemColumn>(dem_columns::wet_steady),
        std::span<const DemColumn>(dem_columns::point)})
    if (const DemColumn* c = find_dem_column(table, key)) return c->integer;
  return false;
}

}  // namespace granflow::dem
