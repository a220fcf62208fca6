#include "continuum/mpm/restart.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <utility>

namespace granflow::mpm {

namespace {

using Leaves = std::vector<std::pair<std::string, YAML::Node>>;

// key.path -> value (a scalar, a list or null), in document order.
void flatten(const YAML::Node& node, const std::string& prefix, Leaves& out) {
  if (node.IsMap()) {
    for (const auto& item : node) {
      const std::string key = item.first.as<std::string>();
      flatten(item.second, prefix.empty() ? key : prefix + "." + key, out);
    }
  } else {
    out.emplace_back(prefix, node);
  }
}

bool as_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end && *end == '\0';
}

bool same_scalar(const YAML::Node& a, const YAML::Node& b) {
  double x, y;
  if (as_number(a.Scalar(), x) && as_number(b.Scalar(), y)) return x == y;
  bool p, q;
  if (YAML::convert<bool>::decode(a, p) && YAML::convert<bool>::decode(b, q)) return p == q;
  return a.Scalar() == b.Scalar();
}

bool same(const YAML::Node& a, const YAML::Node& b) {
  if (a.IsNull() || b.IsNull()) return a.IsNull() && b.IsNull();
  if (a.IsScalar() && b.IsScalar()) return same_scalar(a, b);
  if (a.IsSequence() && b.IsSequence()) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!same(a[i], b[i])) return false;
    return true;
  }
  return false;
}

std::string text(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "null";
  if (n.IsScalar()) return n.Scalar();
  if (n.IsSequence()) {
    std::string s = "[";
    for (std::size_t i = 0; i < n.size(); ++i) s += (i ? ", " : "") + text(n[i]);
    return s + "]";
  }
  return "{...}";
}

std::string join(const std::vector<double>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += fmt::format("{}{:g}", i ? ", " : "", v[i]);
  return s;
}

// Keys a restart may always change: the end, the output, the run's name and the thread count.
bool always_free(const std::string& key) {
  return key == "run.end_time" || key.rfind("output.", 0) == 0 || key == "name" ||
         key == "description" || key == "numerics.threads";
}

const std::vector<double>& need(const core::Case& c, const RestartPoint& r,
                                const std::string& name) {
  const auto it = r.record.history.find(name);
  if (it == r.record.history.end() || it->second.empty())
    refuse_restart(c, r.file, fmt::format("its history has no '{}'", name));
  return it->second;
}

}  // namespace

void refuse_restart(const core::Case& c, const std::string& file, const std::string& why) {
  c.fail("output.restart_from", fmt::format("{}: {}", file, why));
}

std::optional<RestartPoint> check_restart(const core::Case& c,
                                          std::initializer_list<std::string_view> free_keys) {
  if (!c.has("output.restart_from")) return std::nullopt;
  RestartPoint r;
  r.file = c.string("output.restart_from");
  if (r.file.empty()) return std::nullopt;
  try {
    r.record = read_checkpoint_record(r.file, r.clock);
  } catch (const CheckpointError& e) {
    refuse_restart(c, r.file, e.what());
  }
  if (r.record.case_yaml.empty())
    refuse_restart(c, r.file,
                   "the checkpoint holds no record of the case that wrote it (an older granflow); "
                   "run the case again with output.checkpoint: true");
  YAML::Node then;
  try {
    then = YAML::Load(r.record.case_yaml);
  } catch (const YAML::Exception&) {
    refuse_restart(c, r.file, "its record of the case is not valid YAML");
  }
  Leaves before, now;
  flatten(then, "", before);
  flatten(YAML::Load(c.resolved_yaml()), "", now);
  std::map<std::string, YAML::Node> by_key(before.begin(), before.end());
  auto is_free = [&](const std::string& key) {
    return always_free(key) ||
           std::find(free_keys.begin(), free_keys.end(), key) != free_keys.end();
  };
  std::string allowed = "run.end_time, output.*, name, description, numerics.threads";
  for (const auto k : free_keys) allowed += fmt::format(", {}", k);
  auto differs = [&](const std::string& key, const std::string& here, const std::string& there) {
    refuse_restart(c, r.file,
                   fmt::format("written by another case: {} is {} here, {} in the checkpoint (a "
                               "restart continues the same case; it may change only {})",
                               key, here, there, allowed));
  };
  for (const auto& [key, value] : now) {
    const auto it = by_key.find(key);
    if (!is_free(key)) {
      if (it == by_key.end())
        differs(key, text(value), "not given");
      else if (!same(value, it->second))
        differs(key, text(value), text(it->second));
    }
    if (it != by_key.end()) by_key.erase(it);
  }
  for (const auto& [key, value] : before)
    if (by_key.count(key) && !is_free(key)) differs(key, "not given", text(value));
  return r;
}

void check_restart_end(const core::Case& c, const RestartPoint& r, double end_time,
                       std::string_view end_key) {
  if (!(r.clock.time < end_time - 0.5 * r.clock.dt))
    refuse_restart(c, r.file,
                   fmt::format("the checkpoint is at t = {:.6g} s (step {}), at or past the end of "
                               "this run, t = {:.6g} s from {}: nothing would run; expected an end "
                               "after {:.6g} s",
                               r.clock.time, r.clock.step, end_time, end_key, r.clock.time));
}

void check_terzaghi_restart(const core::Case& c, const RestartPoint& r) {
  const std::vector<double>& done = need(c, r, "terzaghi.isochrones");
  const double time_per_Tv = need(c, r, "terzaghi.time_per_Tv").front();
  auto now = c.number_list("run.isochrones");
  std::sort(now.begin(), now.end());
  if (now.size() < done.size() || !std::equal(done.begin(), done.end(), now.begin()))
    refuse_restart(c, r.file,
                   fmt::format("run.isochrones is [{}]; a restart keeps the isochrones checked "
                               "before the checkpoint, [{}], first (their errors are its history) "
                               "and may add later ones",
                               join(now), join(done)));
  check_restart_end(c, r, now.back() * time_per_Tv, "the last of run.isochrones");
}

void check_couette_restart(const core::Case& c, const RestartPoint& r) {
  check_restart_end(c, r, c.number("run.end_time"), "run.end_time");
  const double from_then = need(c, r, "couette.average_from").front();
  const double from_now = c.number("run.average_from");
  // The checkpoint's sums hold the samples at t >= from_then up to the checkpoint: they are the
  // new window's samples there when the window is the same; a window that starts after the
  // checkpoint has none there (its sums restart from zero).
  if (!(r.clock.time < from_now) && from_now != from_then)
    refuse_restart(
        c, r.file,
        fmt::format("run.average_from = {:g} s starts the averaging window before the checkpoint "
                    "(t = {:.6g} s), whose sums are over the window from {:g} s; expected "
                    "run.average_from: {:g} or a time after {:.6g} s",
                    from_now, r.clock.time, from_then, from_then, r.clock.time));
}

const std::vector<double>& RunHistory::restored(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end() || it->second.empty())
    refuse_restart(*case_, file_, fmt::format("its history has no '{}'", name));
  return it->second;
}

const TimeStepLimits& RunHistory::limits(const Solver& solver) const {
  return restarted_ && solver.steps() < limits_until_ ? limits_ : solver.limits();
}

double RunHistory::get(const std::string& name, double fresh) const {
  return restarted_ ? restored(name).front() : fresh;
}

void RunHistory::get(const std::string& name, std::vector<double>& v) const {
  if (!restarted_) return;
  const auto it = values_.find(name);
  if (it == values_.end())
    refuse_restart(*case_, file_, fmt::format("its history has no '{}'", name));
  v = it->second;
}

RunHistory restore_run(core::RunContext& ctx, Solver& solver) {
  RunHistory h;
  h.case_ = &ctx.run_case;
  const core::Case& c = ctx.run_case;
  if (!c.has("output.restart_from")) return h;
  h.file_ = c.string("output.restart_from");
  if (h.file_.empty()) return h;
  try {
    h.values_ = read_checkpoint(h.file_, solver).history;
  } catch (const CheckpointError& e) {
    refuse_restart(c, h.file_, e.what());
  }
  h.restarted_ = true;
  const auto limits = h.values_.find("solver.limits");
  const long interval = solver.options().dt_update_interval;
  if (limits != h.values_.end() && limits->second.size() == 4) {
    h.limits_ = {limits->second[0], limits->second[1], limits->second[2], limits->second[3]};
    h.limits_until_ = interval > 0 ? (solver.steps() / interval + 1) * interval
                                   : std::numeric_limits<long>::max();
  }
  ctx.log->info("restarted from {} at t = {:.6g} s (step {})", h.file_, solver.time(),
                solver.steps());
  const auto threads = h.values_.find("solver.threads");
  if (threads != h.values_.end() && !threads->second.empty() &&
      threads->second.front() != solver.threads())
    ctx.log->warn(
        "the checkpoint was written on {} thread(s), this run has {}: the nodal sums add up in "
        "another order, so the continuation equals the uninterrupted run to round-off, not bit "
        "for bit",
        threads->second.front(), solver.threads());
  return h;
}

void write_run_checkpoint(core::RunContext& ctx, const Solver& solver, const RunHistory& history) {
  if (!ctx.run_case.boolean("output.checkpoint")) return;
  CheckpointRecord record{ctx.run_case.resolved_yaml(), history.values()};
  record.history["solver.threads"] = {static_cast<double>(solver.threads())};
  const TimeStepLimits& L = history.limits(solver);
  record.history["solver.limits"] = {L.wave, L.viscous, L.drag, L.conduction};
  write_checkpoint(ctx.directory / "checkpoint.h5", solver, record);
  ctx.log->info("checkpoint written: {}", (ctx.directory / "checkpoint.h5").string());
}

void check_error_measures(const core::RunContext& ctx, long step,
                          std::initializer_list<std::string_view> keys) {
  for (const auto key : keys) {
    const std::string name(key);
    const double value = ctx.summary.contains(name) ? ctx.summary.get(name) : std::nan("");
    if (!std::isfinite(value))
      throw core::NumericalFailure(step, "summary", name, value,
                                   "not finite: the run has no value for this error measure");
  }
}

}  // namespace granflow::mpm
