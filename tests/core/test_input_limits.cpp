// Input limits (core/schema.hpp limits_section) and the messages of bad input: a sweep, a sphere
// count, an MPI rank count or a run length beyond the case's `limits:` is refused before anything
// is expanded or allocated, and a user raises the bound on purpose; numbers that underflow are
// refused; errors caused by --set are located at the --set; a tab or too deep nesting is named;
// a command line that does not parse exits 2. The DEM part runs the granflow binary (its kind
// registry) with `check`.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/case.hpp"
#include "core/kind_registry.hpp"
#include "core/process.hpp"

using granflow::core::Case;
using granflow::core::CaseError;
using granflow::core::Schema;
namespace fs = std::filesystem;

namespace {

Schema limits_schema() {
  Schema s = granflow::core::kind_header("rev", "simple_shear", "test schema");
  auto& m = s.section("material", "grains");
  m.number("diameter", "m", "grain diameter").required().greater_than(0);
  m.number("particle_density", "kg/m^3", "grain density").default_value("2500").greater_than(0);
  auto& l = s.section("loading", "loading");
  l.number("shear_rate", "1/s", "shear rate").required().greater_than(0).sweepable();
  l.number("void_ratio", "", "void ratio").default_value("0.8").greater_than(0).sweepable();
  l.integer("seed", "seed").default_value("1").at_least(1).sweepable();
  auto& d = s.section("dem", "dem");
  d.integer("particles", "spheres")
      .default_value("1000")
      .greater_than(0)
      .limited_by("max_particles");
  return s;
}

const Schema& schema() {
  static const Schema s = limits_schema();
  return s;
}

const std::string good =
    "kind: rev\n"           // 1
    "test: simple_shear\n"  // 2
    "material:\n"           // 3
    "  diameter: 1.0e-3\n"  // 4
    "loading:\n"            // 5
    "  shear_rate: 10\n";   // 6

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    Case::parse(text, "case.yaml", sets, schema());
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

// "[1, 2, ..., n]" times `scale`
std::string list(int n, double scale = 1.0) {
  std::string text = "[";
  for (int i = 1; i <= n; ++i) text += (i > 1 ? ", " : "") + std::to_string(i * scale);
  return text + "]";
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

// --- sweep size ---------------------------------------------------------------------------------

TEST(InputLimits, AMillionConditionSweepIsRefusedBeforeExpanding) {
  const auto start = std::chrono::steady_clock::now();
  const std::string e = error_of(good, {"sweep.loading.shear_rate=" + list(1000),
                                        "sweep.loading.void_ratio=" + list(1000, 1e-3)});
  EXPECT_LT(seconds_since(start), 2.0) << "refused before the million conditions are built";
  EXPECT_EQ(e.rfind("--set sweep.loading.shear_rate=[1.000000, ", 0), 0) << e;
  EXPECT_NE(e.find(": sweep: 1000 values of loading.shear_rate x 1000 values of "
                   "loading.void_ratio = 1000000 conditions; expected at most "
                   "limits.max_conditions = 10000"),
            std::string::npos)
      << e;
}

TEST(InputLimits, TheConditionLimitIsTheProductAndCanBeRaised) {
  // 100 x 100 = 10 000 is the default bound itself; 101 x 100 is beyond it
  EXPECT_EQ(error_of(good, {"sweep.loading.shear_rate=" + list(100),
                            "sweep.loading.void_ratio=" + list(100, 1e-2)}),
            "");
  EXPECT_NE(error_of(good, {"sweep.loading.shear_rate=" + list(101),
                            "sweep.loading.void_ratio=" + list(100, 1e-2)})
                .find("= 10100 conditions; expected at most limits.max_conditions = 10000"),
            std::string::npos);
  // raised on purpose: on the command line or in the file (located there when refused)
  EXPECT_EQ(error_of(good, {"sweep.loading.shear_rate=" + list(101),
                            "sweep.loading.void_ratio=" + list(100, 1e-2),
                            "limits.max_conditions=20000"}),
            "");
  const std::string in_file = good +
                              "limits:\n"                           // 7
                              "  max_conditions: 2\n"               // 8
                              "sweep:\n"                            // 9
                              "  loading.shear_rate: [1, 2, 3]\n";  // 10
  EXPECT_EQ(error_of(in_file),
            "case.yaml:10: sweep: 3 values of loading.shear_rate = 3 conditions; expected at most "
            "limits.max_conditions = 2 (raise limits.max_conditions in the case, or with --set "
            "limits.max_conditions=N, to run them on purpose)");
  EXPECT_EQ(error_of(in_file, {"limits.max_conditions=3"}), "");
}

TEST(InputLimits, TheLimitsSectionIsValidatedLikeAnyOther) {
  EXPECT_EQ(error_of(good + "limits:\n  max_conditions: 0\n"),
            "case.yaml:8: limits.max_conditions: value 0 is out of range; expected integer >= 1 "
            "(at most 2147483647)");
  EXPECT_NE(error_of(good, {"limits.max_condition=5"})
                .find("--set limits.max_condition=5: limits.max_condition: unknown key; expected "
                      "one of: max_conditions, max_particles, max_ranks, max_steps (did you mean "
                      "'max_conditions'?)"),
            std::string::npos);
  EXPECT_EQ(error_of(good + "limits: 5\n"),
            "case.yaml:7: limits: expected a section (a map of keys)");
}

TEST(InputLimits, LimitsAppearInTheResolvedCaseOnlyWhenGiven) {
  const Case plain = Case::parse(good, "case.yaml", {}, schema());
  EXPECT_EQ(plain.resolved_yaml().find("limits"), std::string::npos);
  EXPECT_EQ(plain.limit("max_conditions"), 10000);
  EXPECT_EQ(plain.limit("max_particles"), 1e6);
  EXPECT_EQ(plain.limit("max_steps"), 1e10);
  EXPECT_EQ(plain.limit("max_ranks"), double(granflow::core::default_max_ranks()));
  EXPECT_GE(plain.limit("max_ranks"), 4);
  const Case raised = Case::parse(good, "case.yaml", {"limits.max_particles=2000000"}, schema());
  EXPECT_EQ(raised.limit("max_particles"), 2e6);
  const Case again = Case::parse(raised.resolved_yaml(), "resolved.yaml", {}, schema());
  EXPECT_EQ(again.limit("max_particles"), 2e6);
  EXPECT_THROW((void)plain.limit("max_nothing"), std::logic_error);
}

TEST(InputLimits, RepeatedSweepValuesAreRefusedNamingTheKey) {
  EXPECT_EQ(error_of(good, {"sweep.loading.shear_rate=[5, 5, 5]"}),
            "--set sweep.loading.shear_rate=[5, 5, 5]: sweep.loading.shear_rate[1]: value 5 is "
            "listed twice (also [0]); expected distinct values (a repeated condition runs the "
            "same point again)");
  EXPECT_EQ(error_of(good + "sweep:\n  loading.seed: [1, 2,\n    1]\n"),
            "case.yaml:9: sweep.loading.seed[2]: value 1 is listed twice (also [0]); expected "
            "distinct values (a repeated condition runs the same point again)");
  EXPECT_EQ(error_of(good, {"sweep.loading.shear_rate=[5, 5.0000001]"}), "");
}

TEST(InputLimits, ConditionsOfALargeSweepShareTheCaseTree) {
  // 10 000 conditions: each holds its swept values only (the case tree is shared), so expanding
  // takes well under a second instead of cloning the tree 10 000 times
  const Case c = Case::parse(
      good, "case.yaml",
      {"sweep.loading.shear_rate=" + list(100), "sweep.loading.void_ratio=" + list(100, 1e-2)},
      schema());
  const auto start = std::chrono::steady_clock::now();
  const auto conditions = c.expand_sweep();
  EXPECT_LT(seconds_since(start), 1.0);
  ASSERT_EQ(conditions.size(), 10000u);
  EXPECT_EQ(conditions[0].number("loading.shear_rate"), 1.0);
  EXPECT_EQ(conditions[9999].number("loading.shear_rate"), 100.0);
  EXPECT_DOUBLE_EQ(conditions[9999].number("loading.void_ratio"), 1.0);
  EXPECT_EQ(conditions[5].number("material.diameter"), 1e-3);
  EXPECT_NE(conditions[101].resolved_yaml().find("shear_rate: 2\n"), std::string::npos)
      << conditions[101].resolved_yaml();
  EXPECT_NE(conditions[101].resolved_yaml().find("void_ratio: 0.02"), std::string::npos);
  EXPECT_NE(c.resolved_yaml().find("shear_rate: 10\n"), std::string::npos)
      << "the shared tree keeps the case's own values";
}

// --- limited keys, underflow
// ----------------------------------------------------------------------

TEST(InputLimits, ALimitedKeyBeyondItsLimitNamesTheLimit) {
  for (const std::string v : {"3e9", "1e19", "1000001"})
    EXPECT_EQ(error_of(good, {"dem.particles=" + v}),
              "--set dem.particles=" + v + ": dem.particles: value " + v +
                  " is above limits.max_particles = 1e+06; expected integer > 0 and <= "
                  "limits.max_particles (raise limits.max_particles in the case, or with --set "
                  "limits.max_particles=N, to run it on purpose)");
  EXPECT_EQ(error_of(good, {"dem.particles=1000000"}), "");
  EXPECT_EQ(error_of(good, {"dem.particles=3000000", "limits.max_particles=3e6"}), "");
  // the limit does not hide the other bounds
  EXPECT_NE(error_of(good, {"dem.particles=0"}).find("value 0 is out of range"), std::string::npos);
}

TEST(InputLimits, SubnormalNumbersAreRefused) {
  EXPECT_EQ(error_of(good + "  void_ratio: 1e-320\n"),
            "case.yaml:7: loading.void_ratio: value 1e-320 is below 2.2e-308, the smallest "
            "normal double, and underflows in arithmetic; expected number > 0");
  EXPECT_NE(error_of(good, {"material.particle_density=-4e-310"})
                .find("material.particle_density: value -4e-310 is below 2.2e-308"),
            std::string::npos);
  EXPECT_NE(error_of(good, {"sweep.loading.void_ratio=[0.5, 1e-320]"})
                .find("sweep.loading.void_ratio[1]: value 1e-320 is below 2.2e-308"),
            std::string::npos);
  EXPECT_EQ(error_of(good + "  void_ratio: 2.3e-308\n"), "");  // the smallest normal is fine
}

// --- errors caused by --set are located at the --set -------------------------------------------

TEST(InputLimits, SetErrorsAreLocatedAtTheSet) {
  EXPECT_EQ(error_of(good, {"loading..shear_rate=5"}),
            "--set loading..shear_rate=5: loading..shear_rate: an empty key (two dots, or a dot "
            "at an end); expected key.path=value");
  EXPECT_EQ(error_of(good, {".=5"}),
            "--set .=5: .: an empty key (two dots, or a dot at an end); expected key.path=value");
  EXPECT_EQ(error_of(good, {"loading.=5"}).rfind("--set loading.=5: loading.: an empty key", 0), 0);
  EXPECT_EQ(error_of(good, {"loading.shear_rate.x=5"}),
            "--set loading.shear_rate.x=5: loading.shear_rate.x: unknown key; loading.shear_rate "
            "is a number, not a section of keys");
  EXPECT_EQ(error_of(good, {"sweep=5"}),
            "--set sweep=5: sweep: expected a map of key.path: [values]");
  EXPECT_EQ(error_of(good, {"sweep.loading.shear_rate=[1, abc]"}),
            "--set sweep.loading.shear_rate=[1, abc]: sweep.loading.shear_rate[1]: expected "
            "number > 0 [1/s]");
  EXPECT_EQ(error_of(good, {"sweep=5", "sweep.loading.shear_rate=[1]"}),
            "--set sweep=5: sweep: expected a map of key.path: [values]");
  // a scalar sweep in the file is blamed on the file's line
  EXPECT_EQ(error_of(good + "sweep: 5\n", {"sweep.loading.shear_rate=[1]"}),
            "case.yaml:7: sweep: expected a map of key.path: [values]");
}

// --- syntax errors named by their cause --------------------------------------------------------

TEST(InputLimits, ATabInTheIndentationIsNamed) {
  const std::string tabbed = good + "loading2:\n\tshear_rate: 5\n  other: 1\n";
  const std::string e = error_of(tabbed);
  EXPECT_EQ(e.rfind("case.yaml:8: YAML syntax error: a tab in the indentation; expected spaces", 0),
            0)
      << e;
  // also before a comment (yaml-cpp refuses it there too); inside a value a tab is fine
  EXPECT_EQ(error_of(good + "\t# comment\n").rfind("case.yaml:7: YAML syntax error: a tab", 0), 0);
  EXPECT_EQ(error_of(good + "description: \"a\tb\"  # a\ttab\n"), "");
}

TEST(InputLimits, DeepNestingIsNamed) {
  const std::string deep = good + "description: " + std::string(100000, '[') + "\n";
  const std::string e = error_of(deep);
  EXPECT_EQ(e.rfind("case.yaml:", 0), 0) << e;
  EXPECT_NE(e.find(": YAML syntax error: nested too deeply"), std::string::npos) << e;
  std::string maps = good;
  std::string indent;
  for (int i = 0; i < 2000; ++i) maps += indent + "k" + std::to_string(i) + ":\n", indent += "  ";
  EXPECT_NE(error_of(maps).find("YAML syntax error: nested too deeply"), std::string::npos);
}

// --- the granflow command: DEM limits, CLI exit codes ------------------------------------------

namespace {

const std::string granflow = std::string(GRANFLOW_BINARY_DIR) + "/app/granflow";
const fs::path source = GRANFLOW_SOURCE_DIR;

struct Output {
  int code;
  std::string text;
  double seconds;
};

Output run_granflow(const std::vector<std::string>& args) {
  static int count = 0;
  const fs::path out =
      fs::temp_directory_path() /
      ("granflow_limits_out_" + std::to_string(::getpid()) + "_" + std::to_string(++count));
  std::vector<std::string> argv = {granflow};
  argv.insert(argv.end(), args.begin(), args.end());
  granflow::core::ProcessOptions options;
  options.output = out;
  const auto start = std::chrono::steady_clock::now();
  const auto r = granflow::core::run_process(argv, options);
  const double seconds = seconds_since(start);
  std::ifstream in(out);
  std::stringstream text;
  text << in.rdbuf();
  fs::remove(out);
  return {r.status, r.error + text.str(), seconds};
}

int lines(const std::string& text) {
  int n = 0;
  for (char ch : text) n += ch == '\n';
  return n;
}

}  // namespace

TEST(InputLimits, CommandLineParseErrorsExitTwo) {
  const auto none = run_granflow({});
  EXPECT_EQ(none.code, 2) << none.text;
  EXPECT_NE(none.text.find("A subcommand is required"), std::string::npos) << none.text;
  const auto bogus =
      run_granflow({"check", (source / "cases/rev/simple_shear_dry.yaml").string(), "--bogus"});
  EXPECT_EQ(bogus.code, 2) << bogus.text;
  EXPECT_NE(bogus.text.find("--bogus"), std::string::npos) << bogus.text;
  EXPECT_EQ(run_granflow({"--help"}).code, 0);
  EXPECT_EQ(run_granflow({"check", "--help"}).code, 0);
}

#if GRANFLOW_HAVE_DEM
namespace {

const std::string dem_case = (source / "cases/dem/dry_point.yaml").string();

// `granflow check` of the shipped DEM point with --set overrides: exit 2 with one line that
// begins "error: " and holds each of `expected`.
void expect_refused(const std::vector<std::string>& sets,
                    const std::vector<std::string>& expected) {
  std::vector<std::string> args = {"check", dem_case};
  for (const auto& s : sets) args.insert(args.end(), {"--set", s});
  const auto r = run_granflow(args);
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_EQ(lines(r.text), 1) << r.text;
  EXPECT_EQ(r.text.rfind("error: ", 0), 0) << r.text;
  for (const auto& part : expected) EXPECT_NE(r.text.find(part), std::string::npos) << r.text;
}

void expect_valid(const std::vector<std::string>& sets) {
  std::vector<std::string> args = {"check", dem_case};
  for (const auto& s : sets) args.insert(args.end(), {"--set", s});
  const auto r = run_granflow(args);
  EXPECT_EQ(r.code, 0) << r.text;
}

}  // namespace

TEST(InputLimitsDem, ThreeBillionSpheresAreRefusedAtOnce) {
  const auto r = run_granflow({"check", dem_case, "--set", "dem.particles=3e9"});
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_EQ(r.text,
            "error: --set dem.particles=3e9: dem.particles: value 3e9 is above "
            "limits.max_particles = 1e+06; expected integer > 0 and <= limits.max_particles "
            "(raise limits.max_particles in the case, or with --set limits.max_particles=N, to "
            "run it on purpose)\n");
  EXPECT_LT(r.seconds, 2.0) << "check builds no deck";
  // at the limit the check places no particles either: as fast as the shipped 1000
  const auto at_limit = run_granflow({"check", dem_case, "--set", "dem.particles=1000000"});
  EXPECT_EQ(at_limit.code, 0) << at_limit.text;
  EXPECT_LT(at_limit.seconds, 2.0);
  expect_valid({"dem.particles=2000000", "limits.max_particles=2e6"});
}

TEST(InputLimitsDem, RanksAreBoundedByTheMachine) {
  expect_refused({"dem.ranks=100000"}, {"dem.ranks: value 100000 is above limits.max_ranks = ",
                                        "--set limits.max_ranks=N"});
  expect_refused({"dem.ranks=1e19"}, {"dem.ranks: value 1e19 is above limits.max_ranks"});
  expect_valid({"dem.ranks=" + std::to_string(granflow::core::default_max_ranks())});
  expect_valid({"dem.ranks=5000", "limits.max_ranks=5000"});
}

TEST(InputLimitsDem, SeedsArePositiveInts) {
  expect_refused({"dem.seed=0"}, {"dem.seed: value 0 is out of range; expected integer >= 1"});
  expect_refused({"dem.seed=1e30"}, {"dem.seed: value 1e30 is out of range"});
  expect_refused({"dem.seed=2147483648"}, {"(at most 2147483647)"});
  expect_valid({"dem.seed=2147483647"});
}

TEST(InputLimitsDem, RunLengthIsBoundedNamingTheKeyThatMakesItLong) {
  // γ̇ = 1e-9: ~1e15 steps at any strain: the shear rate is named
  expect_refused({"shear_rate=1e-9"},
                 {"--set shear_rate=1e-9: shear_rate: the run would take 3.", "e+15 time steps",
                  "expected at most limits.max_steps = 1e+10", "a larger shear_rate"});
  expect_refused({"shear_rate=1e-300"}, {"shear_rate: the run would take"});
  // strain.total = 1e12 at γ̇ = 20: the strain is named
  expect_refused(
      {"strain.total=1e12"},
      {"--set strain.total=1e12: strain.total: the run would take", "a smaller strain.total"});
  expect_valid({"strain.total=1e5"});  // 2.6e9 steps
  expect_valid({"strain.total=1e6", "limits.max_steps=1e11"});
}

TEST(InputLimitsDem, HighShearRateSampleCountNamesTheStepSize) {
  // γ̇ = 1e6: a time step is more strain than strain.sample, so the samples are fewer than 100
  // although strain.sample = strain.total / 100: the cause is the step, named at shear_rate
  expect_refused({"shear_rate=1e6", "strain.total=0.3", "strain.sample=0.003"},
                 {"shear_rate: a time step is γ̇ Δt = ", "strain.sample = 0.003 takes 1 steps",
                  "expected >= 100 samples"});
  // too large a strain.sample is still named as such
  expect_refused({"strain.sample=0.5", "control.servo_strain=1"},
                 {"strain.sample: at most strain.total/100 = 0.12"});
}

TEST(InputLimitsDem, LiggghtsBoundsAreCheckedBeforeLaunch) {
  expect_refused({"material.restitution=0.01"},
                 {"material.restitution: > 0.05 with contact_law hertz"});
  expect_refused({"material.restitution=0.05"}, {"material.restitution: > 0.05"});
  expect_valid({"material.restitution=0.06"});
  // linear springs take any e in (0, 1]: granflow passes a damping rate, not the restitution
  expect_valid({"material.restitution=0.01", "material.contact_law=hooke",
                "material.normal_stiffness=1000"});
  // LIGGGHTS' bounds on E and ν for its hertz model (measured: exit 4 after launch before)
  expect_refused({"material.youngs_modulus=1e6"},
                 {"material.youngs_modulus: in [5e6, 1e9] Pa with contact_law hertz"});
  expect_refused({"material.youngs_modulus=2e9"}, {"material.youngs_modulus: in [5e6, 1e9]"});
  expect_refused({"material.poisson_ratio=-0.2"},
                 {"material.poisson_ratio: >= 0 with contact_law hertz"});
  expect_valid({"material.youngs_modulus=5e6", "material.poisson_ratio=0"});
  expect_refused({"material.particle_density=0.5"},
                 {"material.particle_density: value 0.5 is outside the physical range; expected "
                  "number >= 1 [kg/m^3]"});
  expect_refused({"material.particle_density=1e-320"}, {"smallest normal double"});
}
#endif
