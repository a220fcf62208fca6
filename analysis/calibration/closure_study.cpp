#include "analysis/calibration/closure_study.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "analysis/calibration/calibrate_kind.hpp"
#include "continuum/multi_regime/model_sections.hpp"
#include "core/result_file.hpp"
#include "core/run.hpp"
#include "core/sweep_scheduler.hpp"

extern char** environ;

namespace granflow::calibration {

namespace fs = std::filesystem;

namespace {

// "a b, c" -> {"a", "b", "c"} (fit.parameters, data.observables, data.files)
std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(text);
  while (in >> item) {
    std::istringstream parts(item);
    std::string part;
    while (std::getline(parts, part, ','))
      if (!part.empty()) out.push_back(part);
  }
  return out;
}

std::string join(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : separator) + item;
  return out;
}

// The sections whose choice and boolean keys `closures:` may vary: the model's, not data/fit.
const std::vector<std::string> model_sections = {"material", "collisional", "liquid",
                                                 "force_chains", "steady"};

const core::Field* find_field(const core::Schema& schema, const std::string& path) {
  const core::Field* field = &schema;
  std::istringstream in(path);
  std::string part;
  while (field && std::getline(in, part, '.'))
    field = field->type() == core::ValueType::section ? field->child(part) : nullptr;
  return field == &schema ? nullptr : field;
}

std::string closure_keys(const core::Schema& schema) {
  std::vector<std::string> keys;
  for (const auto& section : model_sections)
    if (const auto* s = schema.child(section))
      for (const auto& f : s->children())
        if (f.type() == core::ValueType::choice || f.type() == core::ValueType::boolean)
          keys.push_back(section + "." + f.key());
  return join(keys, ", ");
}

[[noreturn]] void located(const fs::path& file, int line, const std::string& path,
                          const std::string& expected) {
  throw core::CaseError(fmt::format("{}:{}: {}: expected {}", file.string(), line, path, expected));
}

// "radial_distribution" for collisional.radial_distribution, "force_chains" for .enabled keys;
// the full paths when two short names coincide.
std::vector<std::string> short_names(const std::vector<std::string>& keys) {
  std::vector<std::string> out;
  for (const auto& key : keys) {
    const auto dot = key.rfind('.');
    const std::string last = key.substr(dot + 1);
    out.push_back(last == "enabled" && dot != std::string::npos ? key.substr(0, dot) : last);
  }
  if (std::set<std::string>(out.begin(), out.end()).size() != out.size()) return keys;
  return out;
}

CalibratedModel start_model(const core::Case& c) {
  CalibratedModel start;
  start.settings = continuum::read_multi_regime_settings(c);
  start.reference_liquid_viscosity = start.settings.liquid_parameters.viscosity;
  start.factors.fluctuation_dissipation = c.number("fit.fluctuation_dissipation_factor");
  start.factors.contact_production = c.number("steady.contact_production");
  return start;
}

fs::path resolve_data_path(const core::Case& c, const std::string& name) {
  const fs::path p(name);
  if (p.is_absolute() || fs::exists(p)) return p;
  const auto beside_case = fs::path(c.origin()).parent_path() / p;
  if (fs::exists(beside_case)) return beside_case;
  const auto in_source = core::source_dir() / p;
  return fs::exists(in_source) ? in_source : p;  // missing: reported by read_dem_dataset
}

}  // namespace

std::string dropped_because(const std::string& name, const core::Case& c) {
  const std::string& key = parameter_spec(name).case_key;
  if (name == "correlation_length_constant" &&
      c.string("collisional.correlation_length") != "jenkins")
    return "acts only with collisional.correlation_length: jenkins";
  if ((key.rfind("force_chains.", 0) == 0 || name == "contact_production") &&
      !c.boolean("force_chains.enabled"))
    return "a force-chain parameter: acts only with force_chains.enabled: true";
  if ((key.rfind("liquid.", 0) == 0 || name == "fluctuation_dissipation_factor") &&
      !c.boolean("liquid.enabled"))
    return "a liquid parameter: acts only with liquid.enabled: true";
  if (name == "fluctuation_dissipation_factor" && !c.boolean("liquid.fluctuation_dissipation"))
    return "acts only with liquid.fluctuation_dissipation: true";
  return "";
}

ClosureStudy load_closure_study(const fs::path& file, const std::vector<std::string>& overrides) {
  std::ifstream in(file);
  if (!in) throw core::CaseError(fmt::format("{}: cannot open the case file", file.string()));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  YAML::Node raw;
  try {
    raw = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    located(file, e.mark.line + 1, "(top level)", "valid YAML (" + e.msg + ")");
  }
  if (!raw.IsMap()) located(file, 1, "(top level)", "a map of keys");
  YAML::Node closures;
  int closures_line = 0;
  for (const auto& item : raw)
    if (item.first.IsScalar() && item.first.Scalar() == "closures") {
      closures.reset(item.second);
      closures_line = item.first.Mark().line;
    }
  ClosureStudy study;
  study.file = file;
  auto schema = std::make_shared<core::Schema>(calibrate_schema());
  study.schema = schema;
  if (!closures.IsDefined())
    located(file, 1, "closures",
            "a top-level section closures: {key.path: [values]} (keys: " + closure_keys(*schema) +
                ")");
  if (!closures.IsMap() || closures.size() == 0)
    located(file, closures_line + 1, "closures",
            "a non-empty map of choice or boolean key paths to lists of values");

  // The kind: calibrate case is the file with the closures block blanked out, line for line, so
  // that every other key keeps its file:line in messages.
  std::vector<std::string> lines;
  {
    std::istringstream text_lines(text);
    for (std::string line; std::getline(text_lines, line);) lines.push_back(line);
  }
  for (std::size_t j = static_cast<std::size_t>(closures_line); j < lines.size(); ++j) {
    const bool top_level = !lines[j].empty() && lines[j][0] != ' ' && lines[j][0] != '\t' &&
                           lines[j][0] != '#';
    if (j > static_cast<std::size_t>(closures_line) && top_level) break;
    lines[j].clear();
  }
  std::string case_text;
  for (const auto& line : lines) case_text += line + "\n";

  // ---- the closures entries
  std::set<std::string> user_keys;
  for (const auto& o : overrides) user_keys.insert(o.substr(0, o.find('=')));
  for (const auto& item : closures) {
    const std::string key = item.first.Scalar();
    const int line = item.first.Mark().line + 1;
    const std::string path = "closures." + key;
    const core::Field* field = find_field(*schema, key);
    const std::string section = key.substr(0, key.find('.'));
    if (!field || std::find(model_sections.begin(), model_sections.end(), section) ==
                      model_sections.end())
      located(file, line, path,
              "a choice or boolean key path of the model sections (one of: " +
                  closure_keys(*schema) + ")");
    if (field->type() != core::ValueType::choice && field->type() != core::ValueType::boolean)
      located(file, line, path,
              fmt::format("a choice or boolean key ({} is a {}; one of: {})", key,
                          core::to_string(field->type()), closure_keys(*schema)));
    if (std::find(study.keys.begin(), study.keys.end(), key) != study.keys.end())
      located(file, line, path, "each key once");
    if (user_keys.count(key))
      located(file, line, path, "no --set of a key the study varies (--set " + key + "=...)");
    const bool boolean = field->type() == core::ValueType::boolean;
    const std::string expected =
        boolean ? std::string("true or false") : field->expectation();
    if (!item.second.IsSequence() || item.second.size() == 0)
      located(file, line, path, "a non-empty list of values, " + expected + ", e.g. [a, b]");
    std::vector<std::string> values;
    for (std::size_t i = 0; i < item.second.size(); ++i) {
      const YAML::Node v = item.second[i];
      const std::string at = fmt::format("{}[{}]", path, i);
      const int value_line = v.Mark().line + 1;
      bool flag = false;
      std::string value = v.IsScalar() ? v.Scalar() : std::string("(not a scalar)");
      if (boolean) {
        if (!v.IsScalar() || !YAML::convert<bool>::decode(v, flag))
          located(file, value_line, at, fmt::format("{}; got '{}'", expected, value));
        value = flag ? "true" : "false";
      } else if (!v.IsScalar() || std::find(field->choice_names().begin(),
                                            field->choice_names().end(),
                                            value) == field->choice_names().end()) {
        located(file, value_line, at, fmt::format("{}; got '{}'", expected, value));
      }
      if (std::find(values.begin(), values.end(), value) != values.end())
        located(file, value_line, at, fmt::format("distinct values ('{}' listed twice)", value));
      values.push_back(value);
    }
    study.keys.push_back(key);
    study.options.push_back(values);
  }

  // ---- the base case (case.yaml) and every combination, built as the run will use it
  auto base = core::Case::parse(case_text, file.string(), overrides, *schema);
  study.name = base.name().empty() ? file.stem().string() : base.name();
  if (base.name().empty()) {
    auto named = overrides;
    named.push_back("name=" + study.name);
    base = core::Case::parse(case_text, file.string(), named, *schema);
  }
  study.base = std::make_shared<const core::Case>(base);
  study.parameters = split_names(base.string("fit.parameters"));
  for (const auto& name : study.parameters) try {
      parameter_spec(name);
    } catch (const std::invalid_argument& e) {
      base.fail("fit.parameters", e.what());
    }
  for (const auto& o : split_names(base.string("data.observables"))) try {
      study.observables.push_back(parse_observable(o));
    } catch (const std::invalid_argument& e) {
      base.fail("data.observables", e.what());
    }
  const auto names = short_names(study.keys);
  std::size_t count = 1;
  for (const auto& values : study.options) count *= values.size();
  for (std::size_t n = 0; n < count; ++n) {
    ClosureCombination comb;
    std::vector<std::string> sets = overrides;
    std::size_t rest = n;
    comb.values.resize(study.keys.size());
    for (std::size_t j = study.keys.size(); j-- > 0;) {  // last key varies fastest
      comb.values[j] = study.options[j][rest % study.options[j].size()];
      rest /= study.options[j].size();
    }
    for (std::size_t j = 0; j < study.keys.size(); ++j) {
      sets.push_back(study.keys[j] + "=" + comb.values[j]);
      comb.label += (j ? ", " : "") + names[j] + "=" + comb.values[j];
    }
    try {
      const auto options_only = core::Case::parse(case_text, file.string(), sets, *schema);
      for (const auto& p : study.parameters)
        (dropped_because(p, options_only).empty() ? comb.parameters : comb.dropped).push_back(p);
      if (comb.parameters.empty())
        options_only.fail("fit.parameters",
                          "at least one parameter that acts (all of them are dropped)");
      sets.push_back("fit.parameters=" + join(comb.parameters, " "));
      auto c = std::make_shared<const core::Case>(
          core::Case::parse(case_text, file.string(), sets, *schema));
      check_calibrate_case(*c);
      continuum::read_multi_regime_settings(*c);  // its own cross-field checks
      comb.run_case = std::move(c);
    } catch (const core::CaseError& e) {
      throw core::CaseError(fmt::format("{} (in combination {}: {})", e.what(), n, comb.label));
    }
    study.combinations.push_back(std::move(comb));
  }
  return study;
}

StudyData read_study_data(const core::Case& c) {
  StudyData out;
  std::vector<DataPoint> all;
  const auto files = split_names(c.string("data.files"));
  const auto& col = continuum::read_multi_regime_settings(c).collisional_parameters;
  for (std::size_t f = 0; f < files.size(); ++f) {
    const auto path = resolve_data_path(c, files[f]);
    DemDataset set;
    try {
      set = read_dem_dataset(path, static_cast<int>(f));
    } catch (const std::exception& e) {
      c.fail("data.files", e.what());
    }
    for (const auto& why : set.skipped) out.notes.push_back("skipped " + why);
    if (std::abs(set.diameter / col.diameter - 1) > 0.05 ||
        std::abs(set.particle_density / col.particle_density - 1) > 1e-6)
      out.notes.push_back(fmt::format(
          "{}: DEM d = {:g} m, ρ_p = {:g} kg/m³ differ from the case's material; the case's is used",
          path.string(), set.diameter, set.particle_density));
    for (const auto& point : set.points)
      if (!c.has("data.particle_friction") ||
          std::abs(point.particle_friction - c.number("data.particle_friction")) < 1e-12)
        all.push_back(point);
  }
  if (all.empty())
    c.fail("data.files", "datasets with usable rows (and data.particle_friction matching one)");
  if (!c.has("data.points")) out.used = all;
  if (c.has("data.points"))
    for (double v : c.number_list("data.points")) {
      const auto i = static_cast<long>(v);
      if (i < 0 || i >= static_cast<long>(all.size()) || static_cast<double>(i) != v)
        c.fail("data.points", fmt::format("integer indices in [0, {})", all.size()));
      out.used.push_back(all[static_cast<std::size_t>(i)]);
    }
  // every_other holds out the 2nd, 4th, ... used point, as kind: calibrate
  out.held.assign(out.used.size(), 0);
  const std::string mode = c.string("holdout.mode");
  if (mode == "every_other")
    for (std::size_t i = 1; i < out.used.size(); i += 2) out.held[i] = 1;
  if (mode == "list")
    for (double v : c.number_list("holdout.points")) {
      const auto i = static_cast<long>(v);
      if (i < 0 || i >= static_cast<long>(out.used.size()))
        c.fail("holdout.points", fmt::format("indices in [0, {})", out.used.size()));
      out.held[static_cast<std::size_t>(i)] = 1;
    }
  for (std::size_t i = 0; i < out.used.size(); ++i)
    (out.held[i] ? out.holdout : out.training).push_back(out.used[i]);
  return out;
}

double akaike(double chi2, int k) { return chi2 + 2.0 * k; }

double akaike_corrected(double chi2, int k, int n) {
  if (n - k - 1 <= 0) return NAN;
  return akaike(chi2, k) + 2.0 * k * (k + 1) / static_cast<double>(n - k - 1);
}

std::vector<std::size_t> rank_fits(const std::vector<ClosureFit>& fits) {
  std::vector<std::size_t> order(fits.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto usable = [&](std::size_t i) { return fits[i].ok && std::isfinite(fits[i].aic); };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (usable(a) != usable(b)) return usable(a);
    if (!usable(a)) return false;
    if (fits[a].aic != fits[b].aic) return fits[a].aic < fits[b].aic;
    return fits[a].chi2_red < fits[b].chi2_red;
  });
  return order;
}

ClosureFit fit_combination(const ClosureStudy& study, std::size_t index, const StudyData& data) {
  const auto& comb = study.combinations.at(index);
  const core::Case& c = *comb.run_case;
  ClosureFit out;
  out.k = static_cast<int>(comb.parameters.size());
  try {
    const CalibratedModel start = start_model(c);
    const FitResult r = fit(start, comb.parameters, data.training, study.observables,
                            static_cast<int>(c.integer("fit.max_evaluations")));
    const CalibratedModel calibrated = apply(start, comb.parameters, r.estimate);
    out.ok = std::isfinite(r.chi2);
    if (!out.ok) out.error = "χ² is not finite at the estimate";
    out.estimate.assign(r.estimate.data(), r.estimate.data() + r.estimate.size());
    out.standard_error.assign(r.standard_error.data(),
                              r.standard_error.data() + r.standard_error.size());
    for (std::size_t j = 0; j < comb.parameters.size(); ++j)
      out.at_bound.push_back(j < r.at_bound.size() && r.at_bound[j] ? 1.0 : 0.0);
    out.chi2 = r.chi2;
    out.chi2_red = r.chi2_red;
    out.dof = r.dof;
    out.residuals = r.residual_count;
    out.aic = akaike(r.chi2, out.k);
    out.aicc = akaike_corrected(r.chi2, out.k, r.residual_count);
    out.evaluations = r.evaluations;
    out.status = r.status;
    out.identifiable = r.identifiable;
    out.inside_domain = r.inside_domain;
    for (const auto o : study.observables) {
      out.holdout_rel_err.push_back(mean_relative_error(calibrated, data.holdout, o));
      out.train_rel_err.push_back(mean_relative_error(calibrated, data.training, o));
    }
  } catch (const std::exception& e) {
    out.ok = false;
    out.error = e.what();
  }
  return out;
}

namespace {

std::string pack(const ClosureFit& f) {
  core::Packer p;
  p.integer(f.ok).text(f.error).numbers(f.estimate).numbers(f.standard_error).numbers(f.at_bound);
  p.number(f.chi2).number(f.chi2_red).number(f.aic).number(f.aicc);
  for (const int v : {f.k, f.dof, f.residuals, f.evaluations, f.status}) p.integer(v);
  p.integer(f.identifiable).integer(f.inside_domain);
  p.numbers(f.holdout_rel_err).numbers(f.train_rel_err);
  return p.take();
}

ClosureFit unpack(const std::string& bytes) {
  core::Unpacker u(bytes);
  ClosureFit f;
  f.ok = u.integer() != 0;
  f.error = u.text();
  f.estimate = u.numbers();
  f.standard_error = u.numbers();
  f.at_bound = u.numbers();
  f.chi2 = u.number();
  f.chi2_red = u.number();
  f.aic = u.number();
  f.aicc = u.number();
  for (int* v : {&f.k, &f.dof, &f.residuals, &f.evaluations, &f.status})
    *v = static_cast<int>(u.integer());
  f.identifiable = u.integer() != 0;
  f.inside_domain = u.integer() != 0;
  f.holdout_rel_err = u.numbers();
  f.train_rel_err = u.numbers();
  return f;
}

std::string num(double v, const char* format = "{:.6g}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string();
}

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

struct Outputs {
  const ClosureStudy& study;
  const StudyData& data;
  const std::vector<ClosureFit>& fits;
  std::vector<std::size_t> order;
  std::vector<double> delta, weight;  // ΔAIC to the best, Akaike weight
  double wall_s = 0;
};

// Akaike weights w_i = exp(-Δ_i/2) / Σ_j exp(-Δ_j/2), Δ_i = AIC_i - min AIC (Burnham & Anderson
// 2002, §2.9): the relative likelihood of each combination given the set.
void weigh(Outputs& o) {
  o.delta.assign(o.fits.size(), NAN);
  o.weight.assign(o.fits.size(), NAN);
  const double best = o.fits.empty() ? NAN : o.fits[o.order.front()].aic;
  double sum = 0;
  for (std::size_t i = 0; i < o.fits.size(); ++i)
    if (o.fits[i].ok && std::isfinite(o.fits[i].aic)) {
      o.delta[i] = o.fits[i].aic - best;
      sum += std::exp(-o.delta[i] / 2);
    }
  for (std::size_t i = 0; i < o.fits.size(); ++i)
    if (std::isfinite(o.delta[i])) o.weight[i] = std::exp(-o.delta[i] / 2) / sum;
}

std::string observable(Observable o) { return observable_names()[static_cast<int>(o)]; }

void write_csv(const Outputs& o, const fs::path& file) {
  const auto& s = o.study;
  std::ofstream out(file);
  out << "rank,combination";
  for (const auto& key : s.keys) out << "," << key;
  out << ",k,parameters,dropped";
  for (const auto& p : s.parameters) out << "," << p << "," << p << "_err";
  out << ",chi2,chi2_red,dof,residuals,aic,aicc,delta_aic,akaike_weight";
  for (const auto ob : s.observables) out << ",holdout_rel_err_" << observable(ob);
  for (const auto ob : s.observables) out << ",train_rel_err_" << observable(ob);
  out << ",inside_domain,identifiable,status,evaluations,error\n";
  for (std::size_t r = 0; r < o.order.size(); ++r) {
    const std::size_t i = o.order[r];
    const auto& comb = s.combinations[i];
    const auto& f = o.fits[i];
    out << r + 1 << "," << i;
    for (const auto& v : comb.values) out << "," << v;
    out << "," << f.k << "," << join(comb.parameters, ";") << "," << join(comb.dropped, ";");
    for (const auto& p : s.parameters) {
      const auto at = std::find(comb.parameters.begin(), comb.parameters.end(), p);
      const auto j = static_cast<std::size_t>(at - comb.parameters.begin());
      const bool have = at != comb.parameters.end() && j < f.estimate.size();
      out << "," << (have ? num(f.estimate[j], "{:.10g}") : "") << ","
          << (have ? num(f.standard_error[j], "{:.4g}") : "");
    }
    out << "," << num(f.chi2, "{:.10g}") << "," << num(f.chi2_red, "{:.10g}") << "," << f.dof
        << "," << f.residuals << "," << num(f.aic, "{:.10g}") << "," << num(f.aicc, "{:.10g}")
        << "," << num(o.delta[i], "{:.10g}") << "," << num(o.weight[i], "{:.4g}");
    for (const double v : f.holdout_rel_err) out << "," << num(v);
    for (std::size_t k = f.holdout_rel_err.size(); k < s.observables.size(); ++k) out << ",";
    for (const double v : f.train_rel_err) out << "," << num(v);
    for (std::size_t k = f.train_rel_err.size(); k < s.observables.size(); ++k) out << ",";
    out << "," << (f.ok ? int(f.inside_domain) : 0) << "," << (f.ok ? int(f.identifiable) : 0)
        << "," << f.status << "," << f.evaluations << "," << csv_text(f.error) << "\n";
  }
}

void write_json(const Outputs& o, const fs::path& file) {
  const auto& s = o.study;
  core::Summary sum;  // flat name: number, NaN/Inf written as null
  sum.set("study.combinations", static_cast<double>(s.combinations.size()));
  sum.set("study.points", static_cast<double>(o.data.used.size()));
  sum.set("study.training_points", static_cast<double>(o.data.training.size()));
  sum.set("study.holdout_points", static_cast<double>(o.data.holdout.size()));
  sum.set("study.wall_s", o.wall_s);
  sum.set("study.best", static_cast<double>(o.order.front()));
  for (std::size_t r = 0; r < o.order.size(); ++r)
    sum.set(fmt::format("rank.{}", r + 1), static_cast<double>(o.order[r]));
  for (std::size_t i = 0; i < s.combinations.size(); ++i) {
    const auto& comb = s.combinations[i];
    const auto& f = o.fits[i];
    const std::string p = fmt::format("combination.{}.", i);
    const auto rank = std::find(o.order.begin(), o.order.end(), i) - o.order.begin() + 1;
    sum.set(p + "rank", static_cast<double>(rank));
    // options: the index of the value in the closures list of the key (booleans: 1 = true)
    for (std::size_t j = 0; j < s.keys.size(); ++j) {
      const auto& list = s.options[j];
      const auto at = std::find(list.begin(), list.end(), comb.values[j]) - list.begin();
      const bool flag = comb.values[j] == "true" || comb.values[j] == "false";
      sum.set(p + "option." + s.keys[j],
              flag ? (comb.values[j] == "true" ? 1.0 : 0.0) : static_cast<double>(at));
    }
    sum.set(p + "ok", f.ok ? 1 : 0);
    sum.set(p + "k", f.k);
    for (const auto& [key, v] : std::vector<std::pair<std::string, double>>{
             {"chi2", f.chi2}, {"chi2_red", f.chi2_red}, {"dof", f.dof}, {"aic", f.aic},
             {"aicc", f.aicc}, {"delta_aic", o.delta[i]}, {"akaike_weight", o.weight[i]}})
      sum.set(p + key, f.ok ? v : NAN);
    sum.set(p + "fit.inside_domain", f.ok && f.inside_domain ? 1 : 0);
    sum.set(p + "fit.identifiable", f.ok && f.identifiable ? 1 : 0);
    for (std::size_t j = 0; j < comb.parameters.size() && j < f.estimate.size(); ++j) {
      sum.set(p + "fit." + comb.parameters[j], f.estimate[j]);
      sum.set(p + "fit." + comb.parameters[j] + "_err", f.standard_error[j]);
    }
    for (std::size_t k = 0; k < f.holdout_rel_err.size(); ++k)
      sum.set(p + "holdout.rel_err." + observable(s.observables[k]), f.holdout_rel_err[k]);
  }
  sum.write(file);
}

void write_report(const Outputs& o, const fs::path& file, bool have_plot) {
  const auto& s = o.study;
  const auto& base = *s.base;
  const auto names = short_names(s.keys);
  std::ofstream out(file);
  out << "# Closure study: " << s.name << "\n\n"
      << fmt::format("Case `{}`, data `{}`: {} points, {} fitted, {} held out (holdout.mode: {}); "
                     "observables {}; fit.parameters `{}`. {} combinations in {:.1f} s.\n\n",
                     s.file.string(), base.string("data.files"), o.data.used.size(),
                     o.data.training.size(), o.data.holdout.size(), base.string("holdout.mode"),
                     base.string("data.observables"), base.string("fit.parameters"),
                     s.combinations.size(), o.wall_s)
      << "Ranked by AIC = χ² + 2k (Akaike 1974; k fitted parameters, χ² with the DEM error "
         "bars), ties by χ²_red. AICc = AIC + 2k(k+1)/(n−k−1), n residuals (Hurvich & Tsai "
         "1989). ΔAIC to the best; weight = exp(−ΔAIC/2)/Σ (Burnham & Anderson 2002). "
         "Held-out: mean |f − y|/|y| on the held-out points. inside: fit.inside_domain, "
         "ident.: fit.identifiable.\n\n| rank |";
  for (const auto& n : names) out << " " << n << " |";
  out << " k | χ² | χ²_red | dof | AIC | AICc | ΔAIC | weight |";
  for (const auto ob : s.observables) out << " held-out " << observable(ob) << " |";
  out << " inside | ident. | not fitted |\n|";
  for (std::size_t j = 0; j < names.size() + 12 + s.observables.size(); ++j) out << "---|";
  out << "\n";
  for (std::size_t r = 0; r < o.order.size(); ++r) {
    const std::size_t i = o.order[r];
    const auto& f = o.fits[i];
    out << "| " << r + 1 << " |";
    for (const auto& v : s.combinations[i].values) out << " " << v << " |";
    out << fmt::format(" {} | {} | {} | {} | {} | {} | {} | {} |", f.k, num(f.chi2, "{:.4g}"),
                       num(f.chi2_red, "{:.4g}"), f.dof, num(f.aic, "{:.5g}"),
                       num(f.aicc, "{:.5g}"), num(o.delta[i], "{:.3g}"),
                       num(o.weight[i], "{:.2g}"));
    for (std::size_t k = 0; k < s.observables.size(); ++k)
      out << " " << (k < f.holdout_rel_err.size() ? num(100 * f.holdout_rel_err[k], "{:.3g} %")
                                                   : "")
          << " |";
    out << fmt::format(" {} | {} | {} |\n", f.ok && f.inside_domain ? "yes" : "**no**",
                       f.ok && f.identifiable ? "yes" : "**no**",
                       f.ok ? join(s.combinations[i].dropped, ", ") : "fit failed: " + f.error);
  }
  out << "\n## Parameters not fitted\n\n";
  std::map<std::string, std::pair<std::string, int>> dropped;  // name -> (why, count)
  for (const auto& comb : s.combinations)
    for (const auto& p : comb.dropped) {
      auto& entry = dropped[p];
      entry.first = dropped_because(p, *comb.run_case);
      ++entry.second;
    }
  if (dropped.empty()) out << "Every combination fits every parameter of fit.parameters.\n";
  for (const auto& [p, why] : dropped)
    out << fmt::format("- `{}` is not fitted in {} of {} combinations ({}); it keeps the case's "
                       "value there and does not count in k.\n",
                       p, why.second, s.combinations.size(), why.first);
  const std::size_t best = o.order.front();
  const auto& f = o.fits[best];
  const auto& comb = s.combinations[best];
  out << "\n## Best model\n\n" << comb.label << fmt::format(" (combination {}): ", best);
  if (!f.ok) {
    out << "no combination could be fitted.\n";
    return;
  }
  out << fmt::format("χ² = {:.4g}, χ²_red = {:.4g} ({} dof), AIC = {:.5g}.\n\n", f.chi2,
                     f.chi2_red, f.dof, f.aic)
      << "| parameter | case key | estimate | standard error | on a bound |\n|---|---|---|---|---|\n";
  for (std::size_t j = 0; j < comb.parameters.size(); ++j)
    out << fmt::format("| {} | `{}` | {:.6g} | {} | {} |\n", comb.parameters[j],
                       parameter_spec(comb.parameters[j]).case_key, f.estimate[j],
                       num(f.standard_error[j], "{:.3g}"), f.at_bound[j] > 0 ? "yes" : "no");
  if (have_plot)
    out << "\n![The best three combinations against the DEM data](closures.png)\n";
}

// The DEM points and the smooth predictions of the best three combinations over I at the mean
// DEM σ_yy (γ̇ = I √(σ_yy/ρ_p)/d), for plot_closures.py.
void write_curves(const Outputs& o, const fs::path& file) {
  const auto& s = o.study;
  const auto& used = o.data.used;
  core::ResultFile h5(file);
  const auto column = [&](auto get) {
    std::vector<double> v;
    for (const auto& p : used) v.push_back(get(p));
    return v;
  };
  const auto material = start_model(*s.base).settings.collisional_parameters;
  const double d = material.diameter, rho = material.particle_density;
  const auto inertial = [&](const DataPoint& p) {
    return std::isfinite(p.inertial_number) && p.inertial_number > 0
               ? p.inertial_number
               : p.shear_rate * d / std::sqrt(p.normal_stress / rho);
  };
  h5.write("/data/inertial_number", column(inertial), "1", "DEM I");
  h5.write("/data/normal_stress", column([](const DataPoint& p) { return p.normal_stress; }), "Pa",
           "DEM σ_yy");
  std::vector<double> training;
  for (char held : o.data.held) training.push_back(held ? 0.0 : 1.0);
  h5.write("/data/training", training, "1", "1: fitted, 0: held out");
  for (int k = 0; k < observable_count; ++k) {
    const std::string& n = observable_names()[k];
    h5.write("/data/" + n, column([&](const DataPoint& p) { return p.value[k]; }), "1", "DEM " + n);
    h5.write("/data/" + n + "_err", column([&](const DataPoint& p) { return p.error[k]; }), "1",
             "DEM standard error of " + n);
  }
  double lo = INFINITY, hi = 0, p_mean = 0;
  for (const auto& p : used) {
    lo = std::min(lo, inertial(p));
    hi = std::max(hi, inertial(p));
    p_mean += p.normal_stress / static_cast<double>(used.size());
  }
  const int n_grid = 80;
  std::vector<double> grid;
  for (int g = 0; g < n_grid; ++g)
    grid.push_back(lo / 1.5 * std::pow(hi * 1.5 / (lo / 1.5), g / double(n_grid - 1)));
  h5.write("/curves/inertial_number", grid, "1", "I of the curves");
  h5.attribute("/curves", "normal_stress", p_mean);
  int written = 0;
  for (std::size_t r = 0; r < o.order.size() && written < 3; ++r) {
    const std::size_t i = o.order[r];
    const auto& f = o.fits[i];
    if (!f.ok) break;
    const auto& comb = s.combinations[i];
    const Eigen::VectorXd estimate =
        Eigen::Map<const Eigen::VectorXd>(f.estimate.data(), Eigen::Index(f.estimate.size()));
    const CalibratedModel m = apply(start_model(*comb.run_case), comb.parameters, estimate);
    std::vector<std::vector<double>> curves(observable_count);
    for (const double I : grid) {
      DataPoint point;
      point.shear_rate = I * std::sqrt(p_mean / rho) / d;
      point.normal_stress = p_mean;
      point.particle_friction = comb.run_case->has("data.particle_friction")
                                    ? comb.run_case->number("data.particle_friction")
                                    : NAN;
      const auto state = predict(m, point);
      for (int k = 0; k < observable_count; ++k)
        curves[k].push_back(state.ok ? predicted(state, Observable(k)) : NAN);
    }
    const std::string group = fmt::format("/curves/{}", ++written);
    for (int k = 0; k < observable_count; ++k)
      h5.write(group + "/" + observable_names()[k], curves[k], "1",
               "continuum steady " + observable_names()[k] + ", rank " + std::to_string(written));
    h5.attribute(group, "label", comb.label);
    h5.attribute(group, "aic", f.aic);
    h5.attribute(group, "chi2_red", f.chi2_red);
  }
  h5.attribute("/curves", "count", static_cast<double>(written));
  h5.flush();
}

// analysis/plots/plot_closures.py DIR, started from an argument vector (no shell), its output
// appended to log.txt. False (and a warning) when it cannot run.
bool run_plot(const fs::path& dir, spdlog::logger& log) {
  const auto script = core::source_dir() / "analysis" / "plots" / "plot_closures.py";
  if (!fs::exists(script)) {
    log.warn("plot script {} not found; no closures.png", script.string());
    return false;
  }
  std::vector<std::string> args = {core::python_interpreter(), script.string(), dir.string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log_file = (dir / "log.txt").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log_file.c_str(), O_WRONLY | O_APPEND | O_CREAT,
                                   0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  if (rc == 0)
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
  if (rc != 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    log.warn("{} {} failed (python3-matplotlib and python3-h5py installed?); data in closures.h5",
             args[0], script.string());
    return false;
  }
  return true;
}

}  // namespace

int run_closure_study_command(const ClosureStudyCommand& command, int rank) {
  const auto started = std::chrono::steady_clock::now();
  const bool lead = rank == 0;
  ClosureStudy study;
  StudyData data;
  try {
    study = load_closure_study(command.case_file, command.overrides);
    data = read_study_data(*study.combinations.front().run_case);
    for (const auto& comb : study.combinations)
      if (data.training.size() * study.observables.size() <= comb.parameters.size())
        comb.run_case->fail(
            "fit.parameters",
            fmt::format("fewer parameters than training residuals ({} parameters, {} points × {} "
                        "observables) in combination {}",
                        comb.parameters.size(), data.training.size(), study.observables.size(),
                        comb.label));
  } catch (const core::CaseError& e) {
    if (lead) std::cerr << "error: " << e.what() << "\n";
    return core::exit_bad_input;
  } catch (const std::exception& e) {
    if (lead) std::cerr << "error: " << command.case_file.string() << ": " << e.what() << "\n";
    return core::exit_bad_input;
  }
  const std::size_t count = study.combinations.size();
  std::vector<ClosureFit> fits(count);
  const core::ComputeCondition compute = [&](const core::ConditionContext& cc) {
    const ClosureFit f = fit_combination(study, cc.index, data);
    cc.log->info("combination {}/{} ({}): {}", cc.index + 1, count,
                 study.combinations[cc.index].label,
                 f.ok ? fmt::format("χ² = {:.6g}, χ²_red = {:.4g}, AIC = {:.6g}", f.chi2,
                                    f.chi2_red, f.aic)
                      : "fit failed: " + f.error);
    return pack(f);
  };
  const core::AbsorbCondition absorb = [&](std::size_t n, const std::string& bytes) {
    fits[n] = unpack(bytes);
  };
  if (!lead) {  // a rank > 0 of an mpirun: computes what rank 0 hands out, keeps nothing
    const fs::path scratch =
        fs::temp_directory_path() / fmt::format("granflow-study-rank{}-{}", rank, ::getpid());
    int code = core::exit_ok;
    try {
      core::RunContext ctx(*study.base, scratch, true, true);
      core::run_conditions(ctx, count, compute, absorb);
    } catch (const std::exception& e) {
      std::cerr << fmt::format("error: rank {}: {}\n", rank, e.what());
      code = core::exit_failure;
    }
    std::error_code ignored;
    fs::remove_all(scratch, ignored);
    return code;
  }

  const fs::path dir = command.out_dir.empty() ? fs::path("runs") / (study.name + "_closures")
                                               : command.out_dir;
  if (fs::exists(dir)) {
    if (!command.force) {
      std::cerr << "error: " << dir.string()
                << ": the study directory exists; choose --out DIR or pass --force\n";
      return core::exit_bad_input;
    }
    if (!fs::is_directory(dir) || !fs::exists(dir / closure_study_marker)) {
      std::cerr << "error: " << dir.string() << ": exists but has no " << closure_study_marker
                << " marker, so it was not made by `granflow study closures`; --force replaces "
                   "only study directories (remove it yourself or choose --out DIR)\n";
      return core::exit_bad_input;
    }
    fs::remove_all(dir);
  }
  std::unique_ptr<core::RunContext> ctx;
  try {
    ctx = std::make_unique<core::RunContext>(*study.base, dir, false, command.quiet);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return core::exit_bad_input;
  }
  std::ofstream(dir / closure_study_marker) << "granflow study closures " << study.file.string()
                                            << "\n";
  auto& log = *ctx->log;
  int code = core::exit_ok;
  try {
    log.info("granflow study closures {} -> {}: {} combinations of {}", study.file.string(),
             dir.string(), count, join(study.keys, ", "));
    for (const auto& note : data.notes) log.warn("{}", note);
    log.info("{} DEM points: {} fitted, {} held out; fit.parameters {}", data.used.size(),
             data.training.size(), data.holdout.size(), join(study.parameters, " "));
    core::run_conditions(*ctx, count, compute, absorb);
    Outputs out{study, data, fits, rank_fits(fits), {}, {}, 0};
    weigh(out);
    write_curves(out, dir / "closures.h5");
    const bool plotted = command.plot && run_plot(dir, log);
    out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    write_csv(out, dir / "closures.csv");
    write_json(out, dir / "study.json");
    write_report(out, dir / "report.md", plotted);
    for (std::size_t r = 0; r < std::min<std::size_t>(5, count); ++r) {
      const auto& f = fits[out.order[r]];
      log.info("rank {}: {}: k = {}, χ²_red = {}, AIC = {}", r + 1,
               study.combinations[out.order[r]].label, f.k, num(f.chi2_red, "{:.4g}"),
               num(f.aic, "{:.6g}"));
    }
    log.info("finished in {:.3f} s; results in {}", out.wall_s, dir.string());
  } catch (const std::exception& e) {
    log.error("internal error: {}", e.what());
    code = core::exit_failure;
  }
  ctx.reset();
  std::error_code ignored;
  fs::remove(dir / "result.h5", ignored);  // the run context's; the study's data is closures.h5
  return code;
}

}  // namespace granflow::calibration
