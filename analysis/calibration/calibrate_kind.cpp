#include "analysis/calibration/calibrate_kind.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "analysis/calibration/calibrate_report.hpp"
#include "analysis/calibration/calibration.hpp"
#include "analysis/calibration/dem_table.hpp"
#include "analysis/calibration/model_curves.hpp"
#include "continuum/model/closures.hpp"
#include "continuum/sections/model_sections.hpp"
#include "core/file_io.hpp"

namespace granflow::calibration {

namespace {

// `text` as one comment line: line breaks (also U+0085, U+2028, U+2029) and other control
// characters become spaces, so that no text can end the comment and start YAML of its own.
std::string one_line(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = [&](std::size_t k) {
      return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u;
    };
    if (byte(i) < 0x20 || byte(i) == 0x7f) {
      out += ' ';
    } else if (byte(i) == 0xc2 && byte(i + 1) == 0x85) {  // U+0085
      out += ' ';
      i += 1;
    } else if (byte(i) == 0xe2 && byte(i + 1) == 0x80 &&
               (byte(i + 2) == 0xa8 || byte(i + 2) == 0xa9)) {  // U+2028, U+2029
      out += ' ';
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

}  // namespace

core::Schema calibrate_schema() {
  core::Schema s = core::kind_header(
      "calibrate", "",
      "Weighted least-squares fit of closure parameters to DEM steady simple-shear data "
      "(docs/calibration.md): forward model = steady REV simple shear at each DEM (γ̇, σ_yy) "
      "with the shared material description; writes calibrated.yaml.");
  s.add(continuum::material_section());
  s.add(continuum::collisional_section());
  s.add(continuum::liquid_section());
  s.add(continuum::force_chains_section(true));
  s.add(continuum::steady_section());
  auto& data = s.section("data",
                         "DEM steady data to calibrate against: granflow result.h5 files "
                         "(docs/dem_dataset.md) and/or text tables from any DEM code "
                         "(docs/calibration.md, \"Bring your own DEM data\")");
  data.string("files",
              "granflow result.h5 paths separated by spaces or commas (relative: to the working "
              "directory, then the case file's directory); the protocol is the file's own");
  data.string("table",
              "text tables (CSV or whitespace-separated, '#' comments, one header row) separated "
              "by spaces or commas (relative: to the case file's directory, then the working "
              "directory); rows numbered after those of data.files");
  data.choice("protocol", {"constant_pressure", "constant_volume"},
              "the tables' DEM control: constant_pressure (σ_yy imposed: the model predicts φ, μ, "
              "T) or constant_volume (φ imposed: the model predicts σ_yy, μ, T); absent: a table's "
              "own '# protocol:' line, or inferred when it has σ_yy or φ but not both");
  data.choice("units", {"si", "dimensionless"},
              "the tables' units: si, or dimensionless (d = ρ_p = γ̇ = 1; needs material.diameter "
              "and material.particle_density 1); absent: a table's '# units:' line, else si");
  auto& columns = data.section(
      "columns", "header name of each quantity where a table does not use granflow's name");
  auto& errors = data.section("errors",
                              "header name of each quantity's standard error (absent: NAME_err "
                              "for a column NAME, where the table has one)");
  for (const auto& q : table_quantities()) {
    columns.string(q, "column holding " + q);
    errors.string(q, "column holding the standard error of " + q);
  }
  auto& floor = data.section(
      "error_floor",
      "relative error floor per observable, added in quadrature to the data's own standard "
      "error: σ² = σ_data² + (floor·y)² (needed where a table gives no error)");
  for (const auto& o : observable_names())
    floor.number(o, "1", "relative floor of " + o).default_value("0").at_least(0);
  data.string("observables",
              "observables fitted, separated by spaces: friction, solid_fraction, "
              "scaled_temperature (T/(dγ̇)²), scaled_pressure (σ_yy/(ρ_p d² γ̇²)); each row tests "
              "those its protocol predicts; the first one is the one holdout.rel_err reports")
      .default_value("friction");
  data.number_list("points", "",
                   "indices (over all files, then tables, in order) of the rows to use; absent: "
                   "all");
  data.number("particle_friction", "",
              "use only the rows with this μ_p (a sweep over friction holds several materials; "
              "ν_c and ε depend on μ_p); also the μ_p of a table's rows when it has no "
              "particle_friction column; absent: all rows, each predicted with its own μ_p")
      .at_least(0);
  auto& fit = s.section("fit", "the least-squares problem");
  fit.string("parameters",
             "parameters to fit, separated by spaces: restitution, jamming_fraction, "
             "correlation_length_constant, correlation_length_onset, correlation_length_exponent, "
             "liquid_viscosity_factor, "
             "fluctuation_dissipation_factor; with force_chains on also critical_void_ratio, "
             "critical_state_slope, critical_state_exponent, critical_stress_ratio, "
             "contact_production, friction_rise, friction_rise_I0, viscous_dilatancy, "
             "inertial_contact, inertial_contact_power, inertial_contact_friction, viscous_contact")
      .required();
  fit.integer("max_evaluations", "largest number of residual evaluations of Levenberg-Marquardt")
      .default_value("4000")
      .at_least(10);
  fit.integer("starts",
              "number of starting points: the case's values and starts - 1 drawn around them "
              "(reproducible); the smallest χ² wins")
      .default_value("1")
      .at_least(1);
  fit.number("fluctuation_dissipation_factor", "", "starting (or fixed) factor on Λ")
      .default_value("1")
      .greater_than(0);
  auto& holdout = s.section("holdout", "out-of-sample check: fit on a subset, predict the rest");
  holdout
      .choice("mode", {"none", "every_other", "list"},
              "every_other: hold out the 2nd, 4th, ... used point; list: the indices in "
              "holdout.points")
      .default_value("every_other");
  holdout.number_list("points", "", "indices (over the used points) held out with mode: list");
  return s;
}

// More training residuals than fitted parameters, or the fit is refused at fit.parameters. A
// residual is a (point, observable) pair the point tests (its protocol predicts the observable).
static void check_training_size(const core::Case& c, const CaseData& data, std::size_t parameters,
                                const std::vector<std::string>& observable_list) {
  std::size_t residuals = 0;
  for (const auto& point : data.training)
    for (const auto& o : observable_list) residuals += tests(point, parse_observable(o)) ? 1 : 0;
  if (residuals <= parameters)
    c.fail("fit.parameters",
           fmt::format("{} parameters but only {} training residuals ({} points, observables {})",
                       parameters, residuals, data.training.size(), c.string("data.observables")));
}

void check_calibrate_case(const core::Case& c) {
  const auto names = split_names(c.string("fit.parameters"));
  if (names.empty()) c.fail("fit.parameters", "at least one parameter name");
  std::set<std::string> seen;
  for (const auto& name : names) {
    try {
      parameter_spec(name);
    } catch (const std::invalid_argument& e) {
      c.fail("fit.parameters", e.what());
    }
    if (!seen.insert(name).second) c.fail("fit.parameters", fmt::format("'{}' listed twice", name));
    const auto length = model::parse_correlation_length(c.string("collisional.correlation_length"));
    if (name == "correlation_length_constant" && length == model::CorrelationLengthKind::diameter)
      c.fail("fit.parameters",
             "correlation_length_constant only acts with a collisional.correlation_length other "
             "than the diameter");
    if ((name == "correlation_length_onset" || name == "correlation_length_exponent") &&
        length != model::CorrelationLengthKind::toward_jamming)
      c.fail("fit.parameters",
             "correlation_length_onset and _exponent only act with collisional.correlation_length: "
             "toward_jamming");
    if ((name == "liquid_viscosity_factor" || name == "fluctuation_dissipation_factor") &&
        !c.boolean("liquid.enabled"))
      c.fail("fit.parameters", fmt::format("'{}' needs liquid.enabled: true", name));
    const std::string& key = parameter_spec(name).case_key;
    if (key.rfind("force_chains.", 0) == 0 && !c.boolean("force_chains.enabled"))
      c.fail(
          "fit.parameters",
          fmt::format("'{}' is a force-chain parameter: needs force_chains.enabled: true", name));
    if (key.rfind("steady.", 0) == 0 && !c.boolean("force_chains.enabled"))
      c.fail("fit.parameters", fmt::format("'{}' needs force_chains.enabled: true", name));
    if (name == "fluctuation_dissipation_factor" && !c.boolean("liquid.fluctuation_dissipation"))
      c.fail("fit.parameters",
             "fluctuation_dissipation_factor needs liquid.fluctuation_dissipation: true");
  }
  const auto observables = split_names(c.string("data.observables"));
  if (observables.empty()) c.fail("data.observables", "at least one observable");
  for (const auto& o : observables) try {
      parse_observable(o);
    } catch (const std::invalid_argument& e) {
      c.fail("data.observables", e.what());
    }
  if (!c.boolean("collisional.enabled"))
    c.fail("collisional.enabled", "true (the forward model is the collisional steady shear)");
  if (split_names(c.has("data.files") ? c.string("data.files") : "").empty() &&
      split_names(c.has("data.table") ? c.string("data.table") : "").empty())
    c.fail("data.files", "at least one path in data.files or data.table");
  if (c.string("holdout.mode") == "list" && !c.has("holdout.points"))
    c.fail("holdout.points", "a non-empty list of indices with holdout.mode: list");
}

// The data the run will fit, read before its run directory exists: unusable data is refused
// with exit 2 and leaves nothing behind (a rerun needs no --force).
void check_calibrate_data(const core::Case& c) {
  check_training_size(c, read_case_data(c), split_names(c.string("fit.parameters")).size(),
                      split_names(c.string("data.observables")));
}

int run_calibrate_case(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  auto& log = *ctx.log;
  const CalibratedModel start = read_case_model(c);
  if (const auto caveat = in_parallel_caveat(start.settings); !caveat.empty())
    log.warn("{}", caveat);
  const auto names = split_names(c.string("fit.parameters"));
  std::vector<Observable> observables;
  for (const auto& o : split_names(c.string("data.observables")))
    observables.push_back(parse_observable(o));
  const Observable primary = observables.front();
  const std::string primary_name = observable_names()[static_cast<int>(primary)];

  // ---- data and the training / held-out split
  const CaseData data = read_case_data(c);
  for (const auto& line : data.notes) log.warn("{}", line);
  for (const auto& line : data.files) log.info("{}", line);
  for (const auto& line : data.info) log.info("{}", line);
  for (const auto& line : data.repeat_notes) log.info("{}", line);
  const std::vector<DataPoint>& used = data.used;
  const std::vector<char>& held = data.held;
  const std::vector<DataPoint>& training = data.training;
  const std::vector<DataPoint>& holdout = data.holdout;
  check_training_size(c, data, names.size(), split_names(c.string("data.observables")));
  auto& sum = ctx.summary;
  {  // the data: protocols, error model, repeats
    int volume = 0;
    for (const auto& p : used) volume += p.protocol == Protocol::constant_volume ? 1 : 0;
    sum.set("data.rows", static_cast<double>(used.size()));
    sum.set("data.rows_constant_volume", volume);
    sum.set("data.rows_constant_pressure", static_cast<double>(used.size()) - volume);
    std::string floors;
    for (const auto o : observables) {
      const std::string& on = observable_names()[static_cast<int>(o)];
      const double f = c.number("data.error_floor." + on);
      sum.set("data.error_floor." + on, f);
      floors += fmt::format("{}{} {:g}", floors.empty() ? "" : ", ", on, f);
    }
    log.info("errors used: σ² = σ_data² + (floor·y)², relative floors: {}", floors);
    sum.set("data.repeat_groups", data.repeat_groups);
    for (int k = 0; k < observable_count; ++k)
      if (std::isfinite(data.repeat_spread[k]))
        sum.set("data.repeat_spread." + observable_names()[k], data.repeat_spread[k]);
    if (data.repeat_groups > 0)
      log.info("{} repeated conditions: pooled spread / stated σ = {}", data.repeat_groups, [&] {
        std::string s;
        for (int k = 0; k < observable_count; ++k)
          if (std::isfinite(data.repeat_spread[k]))
            s += fmt::format("{}{} {:.3g}", s.empty() ? "" : ", ", observable_names()[k],
                             data.repeat_spread[k]);
        return s.empty() ? std::string("no stated errors") : s;
      }());
  }

  // ---- fit
  log.info("fitting {} on {} training points ({} held out), observables: {}",
           c.string("fit.parameters"), training.size(), holdout.size(),
           c.string("data.observables"));
  const FitResult r =
      fit(start, names, training, observables, static_cast<int>(c.integer("fit.max_evaluations")),
          static_cast<int>(c.integer("fit.starts")));
  const CalibratedModel calibrated = apply(start, names, r.estimate);
  if (!r.inside_domain) {
    std::string walls;
    for (std::size_t j = 0; j < names.size(); ++j)
      if (j < r.at_bound.size() && r.at_bound[j]) walls += (walls.empty() ? "" : ", ") + names[j];
    log.warn(
        "the estimate lies on a parameter bound ({}) or where the model cannot carry a "
        "condition: the fit did not find an interior minimum (see docs/calibration.md); values "
        "are not trustworthy",
        walls.empty() ? "none" : walls);
  }
  if (!r.identifiable)
    log.warn("Jᵀ W J is singular: the data do not constrain every parameter (standard errors NaN)");
  log.info(
      "Levenberg-Marquardt status {} after {} evaluations; χ² {:.6g} -> {:.6g}, χ²_red = {:.4g}",
      r.status, r.evaluations, r.chi2_initial, r.chi2, r.chi2_red);
  for (std::size_t j = 0; j < names.size(); ++j) {
    log.info("  {} = {:.6g} ± {:.3g} (start {:.6g})", names[j], r.estimate[j], r.standard_error[j],
             r.initial[j]);
    sum.set("fit." + names[j], r.estimate[j]);
    sum.set("fit." + names[j] + "_err", r.standard_error[j]);
    sum.set("fit." + names[j] + "_initial", r.initial[j]);
    sum.set("fit." + names[j] + "_at_bound", j < r.at_bound.size() && r.at_bound[j] ? 1 : 0);
    for (std::size_t k = j + 1; k < names.size(); ++k)
      sum.set(fmt::format("fit.corr.{}.{}", names[j], names[k]), r.correlation(j, k));
  }
  sum.set("fit.chi2", r.chi2);
  sum.set("fit.chi2_initial", r.chi2_initial);
  sum.set("fit.chi2_red", r.chi2_red);
  sum.set("fit.dof", r.dof);
  sum.set("fit.points", static_cast<double>(training.size()));
  sum.set("fit.evaluations", r.evaluations);
  sum.set("fit.status", r.status);
  sum.set("fit.identifiable", r.identifiable ? 1 : 0);
  sum.set("fit.inside_domain", r.inside_domain ? 1 : 0);
  {  // χ²_red with the data's own errors alone, at the same estimate (pairs without one left out)
    const Chi2 own = chi2_at(calibrated, training, observables, true);
    const int own_dof = own.residuals - static_cast<int>(names.size());
    const double own_red = own_dof > 0 ? own.chi2 / own_dof : NAN;
    sum.set("fit.chi2_own_errors", own.chi2);
    sum.set("fit.residuals_own_errors", own.residuals);
    sum.set("fit.residuals", static_cast<double>(r.residual_point.size()));
    sum.set("fit.chi2_red_own_errors", own_red);
    log.info(
        "χ²_red = {:.4g} with the errors the fit used (floors included, {} residuals), {:.4g} with "
        "the data's own errors alone ({} residuals have one)",
        r.chi2_red, r.residual_point.size(), own_red, own.residuals);
  }
  for (std::size_t k = 0; k < observables.size(); ++k) {
    const std::string& on = observable_names()[static_cast<int>(observables[k])];
    sum.set("train.rel_err." + on, mean_relative_error(calibrated, training, observables[k]));
    sum.set("train.rel_err_uncalibrated." + on,
            mean_relative_error(start, training, observables[k]));
  }
  if (!holdout.empty()) {
    const double after = mean_relative_error(calibrated, holdout, primary);
    const double before = mean_relative_error(start, holdout, primary);
    sum.set("holdout.rel_err", after);
    sum.set("holdout.rel_err_uncalibrated", before);
    sum.set("holdout.points", static_cast<double>(holdout.size()));
    for (const auto o : observables) {
      const std::string& on = observable_names()[static_cast<int>(o)];
      sum.set("holdout.rel_err." + on, mean_relative_error(calibrated, holdout, o));
      sum.set("holdout.rel_err_uncalibrated." + on, mean_relative_error(start, holdout, o));
    }
    log.info(
        "held-out {} ({} points): mean relative error {:.4g} calibrated vs {:.4g} uncalibrated",
        primary_name, holdout.size(), after, before);
  }

  // ---- result.h5
  auto& out = ctx.result;
  const auto col = [&](auto get) {
    std::vector<double> v;
    for (const auto& p : used) v.push_back(get(p));
    return v;
  };
  out.write("/data/shear_rate", col([](const DataPoint& p) { return p.shear_rate; }), "1/s",
            "DEM imposed shear rate γ̇");
  out.write("/data/normal_stress", col([](const DataPoint& p) { return p.normal_stress; }), "Pa",
            "DEM steady σ_yy (the continuum's imposed p)");
  out.write("/data/particle_friction", col([](const DataPoint& p) { return p.particle_friction; }),
            "1", "μ_p of the condition");
  out.write("/data/inertial_number", col([](const DataPoint& p) { return p.inertial_number; }), "1",
            "DEM I");
  out.write("/data/liquid_viscosity", col([](const DataPoint& p) { return p.liquid_viscosity; }),
            "Pa s", "liquid viscosity η0 of an immersed row (NaN: dry)");
  // Indices and flags as integers.
  const auto integers = [&](auto get) {
    std::vector<long> v;
    for (const auto& p : used) v.push_back(get(p));
    return v;
  };
  out.write("/data/source", integers([](const DataPoint& p) { return long(p.source); }), "1",
            "index of the data file (data.files order)");
  out.write("/data/row", integers([](const DataPoint& p) { return long(p.row); }), "1",
            "row in that file's /steady table (a text table: its data row)");
  out.write("/data/protocol", integers([](const DataPoint& p) {
              return p.protocol == Protocol::constant_volume ? 1L : 0L;
            }),
            "1", "0: constant pressure (σ_yy imposed), 1: constant volume (φ imposed)");
  std::vector<long> training_flag;
  for (char h : held) training_flag.push_back(h ? 0L : 1L);
  out.write("/data/training", training_flag, "1", "1: used in the fit, 0: held out");
  const char* units[] = {"1", "1", "1", "1"};
  for (int k = 0; k < observable_count; ++k) {
    const auto& on = observable_names()[k];
    out.write("/data/" + on, col([&](const DataPoint& p) { return p.value[k]; }), units[k],
              "DEM steady " + on);
    out.write("/data/" + on + "_err", col([&](const DataPoint& p) { return p.error[k]; }), units[k],
              "DEM standard error of " + on + " (0: none given)");
    out.write("/data/" + on + "_fit_err",
              col([&](const DataPoint& p) { return fit_error(p, Observable(k)); }), units[k],
              "σ the fit uses for " + on + ": sqrt(err² + (floor·y)²)");
  }
  for (const auto& [group, model] : std::map<std::string, const CalibratedModel*>{
           {"uncalibrated", &start}, {"calibrated", &calibrated}}) {
    std::vector<SteadyShearState> states;
    for (const auto& p : used) states.push_back(predict(*model, p));
    for (int k = 0; k < observable_count; ++k) {
      std::vector<double> v;
      for (const auto& s : states) v.push_back(s.ok ? predicted(s, Observable(k)) : NAN);
      out.write("/prediction/" + group + "/" + observable_names()[k], v, units[k],
                "continuum steady " + observable_names()[k] + " at the DEM condition (" + group +
                    " parameters)");
    }
    std::vector<double> I;
    for (const auto& s : states) I.push_back(s.ok ? s.inertial_number : NAN);
    out.write("/prediction/" + group + "/inertial_number", I, "1", "continuum I");
  }
  {  // The model drawn smooth: /curve/N over the swept range of each series' condition variable
     // (model_curves.hpp), and which series draws each row.
    const auto t0 = std::chrono::steady_clock::now();
    const auto member =
        write_model_curves(out, used, {{"uncalibrated", &start}, {"calibrated", &calibrated}});
    out.write("/data/curve", member, "1",
              "index N of the /curve/N series through this row's conditions (-1: none)");
    const auto drawn = std::count_if(member.begin(), member.end(), [](long m) { return m >= 0; });
    log.info("model curves: {} series through {} of {} rows, {:.3g} s",
             member.empty() ? 0 : *std::max_element(member.begin(), member.end()) + 1, drawn,
             member.size(),
             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::vector<double> residuals(training.size() * observables.size(), NAN);
  for (std::size_t j = 0; j < r.residual_point.size(); ++j)
    residuals[static_cast<std::size_t>(r.residual_point[j]) * observables.size() +
              static_cast<std::size_t>(r.residual_observable[j])] =
        r.normalised_residuals[static_cast<Eigen::Index>(j)];
  out.write_matrix(
      "/fit/normalised_residuals", residuals, training.size(), observables.size(), "1",
      "(y - f)/σ at the estimate, training points × observables (NaN: not tested, e.g. the "
      "quantity the row's protocol imposes)");
  const auto vec = [](const Eigen::VectorXd& v) {
    return std::vector<double>(v.data(), v.data() + v.size());
  };
  out.write("/fit/estimate", vec(r.estimate), "1", "fitted parameters (fit.parameters order)");
  out.write("/fit/standard_error", vec(r.standard_error), "1", "sqrt(diag((Jᵀ W J)⁻¹))");
  out.write("/fit/initial", vec(r.initial), "1", "starting values");
  std::vector<double> corr(r.correlation.data(), r.correlation.data() + r.correlation.size());
  out.write_matrix("/fit/correlation", corr, names.size(), names.size(), "1",
                   "correlation matrix of the estimates");
  out.attribute("/fit", "parameters", c.string("fit.parameters"));
  out.attribute("/fit", "observables", c.string("data.observables"));
  out.attribute("/fit", "chi2_red", r.chi2_red);

  // ---- calibrated.yaml: the fitted keys under their case sections, written by yaml-cpp's
  // emitter; the free text of the comment lines (run name, data files) is made one line.
  std::map<std::string, std::vector<std::pair<std::string, double>>> sections;
  std::vector<std::string> comments;
  comments.push_back(
      fmt::format("Calibrated parameters (granflow kind: calibrate, run '{}').", c.name()));
  const std::string files = c.has("data.files") ? c.string("data.files") : std::string(),
                    tables = c.has("data.table") ? c.string("data.table") : std::string();
  comments.push_back(fmt::format("Data: {}{}{}; observables: {}; χ²_red = {:.4g}", files,
                                 files.empty() || tables.empty() ? "" : " ", tables,
                                 c.string("data.observables"), r.chi2_red));
  for (std::size_t j = 0; j < names.size(); ++j)
    comments.push_back(
        fmt::format("{} = {:.8g} ± {:.3g}", names[j], r.estimate[j], r.standard_error[j]));
  for (std::size_t j = 0; j < names.size(); ++j) {
    const auto& spec = parameter_spec(names[j]);
    const double value = case_value(calibrated, names[j]);
    if (spec.case_key.empty()) {
      comments.push_back(
          fmt::format("{}: {:.8g} ± {:.3g} has no case key yet; it is not applied by rev/mpm cases",
                      names[j], r.estimate[j], r.standard_error[j]));
      continue;
    }
    const auto dot = spec.case_key.find('.');
    sections[spec.case_key.substr(0, dot)].push_back({spec.case_key.substr(dot + 1), value});
  }
  YAML::Emitter emitter;
  for (std::size_t i = 0; i < comments.size(); ++i) {
    if (i > 0) emitter << YAML::Newline;
    emitter << YAML::Comment(one_line(comments[i]));
  }
  emitter << YAML::BeginMap;
  for (const auto& [section, keys] : sections) {
    emitter << YAML::Key << section << YAML::Value << YAML::BeginMap;
    for (const auto& [key, value] : keys)
      emitter << YAML::Key << key << YAML::Value << fmt::format("{:.10g}", value);
    emitter << YAML::EndMap;
  }
  emitter << YAML::EndMap;
  core::write_text_file(ctx.directory / "calibrated.yaml", std::string(emitter.c_str()) + "\n");
  ctx.plot("plot_calibration.py");
  return core::exit_ok;
}

void register_calibrate_kinds(core::KindRegistry& registry) {
  core::KindEntry entry{
      "calibrate",
      "",
      "fit closure parameters to DEM steady simple-shear data (weighted least squares)",
      calibrate_schema(),
      check_calibrate_case,
      run_calibrate_case,
      "cases/calibrate/dry_mu_I.yaml",
      check_calibrate_data};
  entry.report = calibrate_report_section;
  registry.add(std::move(entry));
}

}  // namespace granflow::calibration
