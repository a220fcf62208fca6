#include "analysis/calibration/closure_study.hpp"

// `granflow study closures`: validation, data, the fits shared over the ranks (closure_study.hpp).
#include <fmt/format.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include "analysis/calibration/calibrate_kind.hpp"
#include "continuum/sections/model_sections.hpp"
#include "core/file_io.hpp"
#include "core/interrupt.hpp"
#include "core/run.hpp"
#include "core/sweep_scheduler.hpp"

namespace granflow::calibration {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

CalibratedModel start_model(const core::Case& c) { return read_case_model(c); }

std::string dropped_because(const std::string& name, const core::Case& c) {
  const std::string& key = parameter_spec(name).case_key;
  if (name.rfind("correlation_length_", 0) == 0 &&
      model::parse_correlation_length(c.string("collisional.correlation_length")) ==
          model::CorrelationLengthKind::diameter)
    return "acts only with a correlation length other than the diameter";
  if ((name == "correlation_length_onset" || name == "correlation_length_exponent") &&
      model::parse_correlation_length(c.string("collisional.correlation_length")) !=
          model::CorrelationLengthKind::toward_jamming)
    return "acts only with collisional.correlation_length: toward_jamming";
  // steady.* (contact production, friction rise) are terms of the force chains' steady state
  if ((key.rfind("force_chains.", 0) == 0 || key.rfind("steady.", 0) == 0 ||
       name == "contact_production") &&
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
    located(
        file, 1, "closures",
        "a top-level section closures: {key.path: [values]} (keys: " + closure_keys(*schema) + ")");
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
    const bool top_level =
        !lines[j].empty() && lines[j][0] != ' ' && lines[j][0] != '\t' && lines[j][0] != '#';
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
    if (!field ||
        std::find(model_sections.begin(), model_sections.end(), section) == model_sections.end())
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
      located(file, line, path, "a key not also set on the command line (--set " + key + "=...)");
    const bool boolean = field->type() == core::ValueType::boolean;
    const std::string expected = boolean ? std::string("true or false") : field->expectation();
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
      } else if (!v.IsScalar() ||
                 std::find(field->choice_names().begin(), field->choice_names().end(), value) ==
                     field->choice_names().end()) {
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
  study.short_keys = short_names(study.keys);
  const auto& names = study.short_keys;
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

StudyData read_study_data(const core::Case& c) { return read_case_data(c); }

std::string join(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : separator) + item;
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
                            static_cast<int>(c.integer("fit.max_evaluations")),
                            static_cast<int>(c.integer("fit.starts")));
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
    for (const auto& point : data.used)
      out.no_steady_state += predict(calibrated, point).ok ? 0 : 1;
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
  for (const int v : {f.k, f.dof, f.residuals, f.evaluations, f.status, f.no_steady_state})
    p.integer(v);
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
  for (double* v : {&f.chi2, &f.chi2_red, &f.aic, &f.aicc}) *v = u.number();
  for (int* v : {&f.k, &f.dof, &f.residuals, &f.evaluations, &f.status, &f.no_steady_state})
    *v = static_cast<int>(u.integer());
  f.identifiable = u.integer() != 0;
  f.inside_domain = u.integer() != 0;
  f.holdout_rel_err = u.numbers();
  f.train_rel_err = u.numbers();
  return f;
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
    std::size_t residuals = 0;  // the (point, observable) pairs the points test
    for (const auto& point : data.training)
      for (const auto o : study.observables) residuals += tests(point, o) ? 1 : 0;
    for (const auto& comb : study.combinations)
      if (residuals <= comb.parameters.size())
        comb.run_case->fail(
            "fit.parameters",
            fmt::format("fewer parameters than training residuals ({} parameters, {} residuals "
                        "of {} points × {} observables) in combination {}",
                        comb.parameters.size(), residuals, data.training.size(),
                        study.observables.size(), comb.label));
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
    cc.log->info(
        "combination {}/{} ({}): {}", cc.index + 1, count, study.combinations[cc.index].label,
        f.ok ? fmt::format("χ² = {:.6g}, χ²_red = {:.4g}, AIC = {:.6g}", f.chi2, f.chi2_red, f.aic)
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

  const fs::path dir =
      command.out_dir.empty() ? fs::path("runs") / (study.name + "_closures") : command.out_dir;
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
  core::write_text_file(dir / closure_study_marker,
                        "granflow study closures " + study.file.string() + "\n");
  auto& log = *ctx->log;
  int code = core::exit_ok;
  try {
    log.info("granflow study closures {} -> {}: {} combinations of {}", study.file.string(),
             dir.string(), count, join(study.keys, ", "));
    for (const auto& note : data.notes) log.warn("{}", note);
    log.info("{} DEM points: {} fitted, {} held out; fit.parameters {}", data.used.size(),
             data.training.size(), data.holdout.size(), join(study.parameters, " "));
    for (const auto& comb : study.combinations) {  // as pair and calibrate warn
      const auto& m = start_model(*comb.run_case).settings;
      if (m.force_chains &&
          1 / (1 + m.force_chain_parameters.e_Gamma) >= m.collisional_parameters.jamming_fraction)
        log.warn(
            "{}: 1/(1+e_Γ) ≥ ν_c at the start: the force chains carry no load and the fit "
            "cannot move them (start collisional.jamming_fraction above 1/(1+e_Γ))",
            comb.label);
    }
    core::run_conditions(*ctx, count, compute, absorb);
    if (core::interrupted()) {
      log.warn("interrupted by {}: no ranking written (it needs every combination)",
               core::interrupt_name());
      code = core::interrupt_exit_code();
    } else {
      write_closure_study({study, data, fits, rank_fits(fits)}, dir, command.plot, log, started);
    }
  } catch (const core::IoError& e) {
    log.error("{}", e.what());
    code = core::exit_io;
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
