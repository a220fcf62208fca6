// End-to-end checks of the `granflow` command: exit codes, error messages, run directory files,
// and that docs/cases.md is the validator's own schema.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/process.hpp"
#include "core/run.hpp"

namespace fs = std::filesystem;

namespace {

const std::string granflow = std::string(GRANFLOW_BINARY_DIR) + "/app/granflow";
const fs::path source = GRANFLOW_SOURCE_DIR;

struct Output {
  int code;
  std::string text;
};

Output run(const std::string& arguments) {
  const std::string command = granflow + " " + arguments + " 2>&1";
  Output out{0, ""};
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  while (fgets(buffer, sizeof buffer, pipe)) out.text += buffer;
  const int status = pclose(pipe);
  out.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("granflow_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(Cli, DefaultCaseRunsAndReproducesTheClosedForm) {
  const fs::path out = scratch("dry");
  const auto r = run("run " + (source / "cases/rev/simple_shear_dry.yaml").string() + " --out " +
                     out.string());
  ASSERT_EQ(r.code, 0) << r.text;
  for (const char* file : {"case.yaml", "result.h5", "summary.json", "log.txt"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  const auto summary = granflow::core::Summary::read(out / "summary.json");
  EXPECT_LT(summary.get("closed_form.T_rel_err"), 1e-6);
  for (const char* key :
       {"steady.mu", "steady.e", "steady.phi", "steady.T", "steady.p", "steady.tau", "steady.I",
        "cost.wall_s", "cost.steps", "cost.updates_per_s"})
    EXPECT_TRUE(summary.contains(key)) << key;
  // never overwrite a previous run silently
  const auto again = run("run " + (source / "cases/rev/simple_shear_dry.yaml").string() +
                         " --out " + out.string());
  EXPECT_EQ(again.code, 2);
  EXPECT_NE(again.text.find("exists"), std::string::npos) << again.text;
  EXPECT_EQ(run("run " + (source / "cases/rev/simple_shear_dry.yaml").string() +
                " --force --quiet --out " + out.string())
                .code,
            0);
  fs::remove_all(out);
}

TEST(Cli, MisspelledKeyExitsTwoNamingIt) {
  const fs::path dir = scratch("typo");
  fs::create_directories(dir);
  std::string text = read(source / "cases/rev/simple_shear_dry.yaml");
  text.replace(text.find("shear_rate:"), 11, "shear_rat:");
  std::ofstream(dir / "typo.yaml") << text;
  const auto r = run("run " + (dir / "typo.yaml").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.text.find("loading.shear_rat: unknown key"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("typo.yaml:"), std::string::npos) << r.text;
  EXPECT_FALSE(fs::exists(dir / "out")) << "nothing may run on bad input";
  const auto set = run("check " + (source / "cases/rev/simple_shear_dry.yaml").string() +
                       " --set material.restitution=1.5");
  EXPECT_EQ(set.code, 2);
  EXPECT_NE(set.text.find("material.restitution"), std::string::npos) << set.text;
  fs::remove_all(dir);
}

TEST(Cli, NumericalFailureExitsThreeAndKeepsTheData) {
  const fs::path out = scratch("fail");
  // No temperature at t = 0 under constant pressure: nothing can carry p.
  const auto r = run("run " + (source / "cases/rev/simple_shear_pressure.yaml").string() +
                     " --set initial.granular_temperature=0 --out " + out.string());
  EXPECT_EQ(r.code, 3) << r.text;
  EXPECT_NE(r.text.find("step 0, REV point: solid_fraction"), std::string::npos) << r.text;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_TRUE(fs::exists(out / "result.h5"));
  fs::remove_all(out);
}

TEST(Cli, EveryShippedCaseValidates) {
  for (const auto& entry : fs::recursive_directory_iterator(source / "cases")) {
    if (entry.path().extension() != ".yaml" || entry.path().parent_path().filename() == "materials")
      continue;
    // A closure study (`granflow study closures`) is a calibrate case plus `closures:`; its own
    // tests run the shipped one (tests/calibration/test_closure_study.cpp).
    if (read(entry.path()).find("\nclosures:") != std::string::npos) continue;
    const auto r = run("check " + entry.path().string());
    EXPECT_EQ(r.code, 0) << entry.path() << ": " << r.text;
  }
}

TEST(Cli, CaseReferenceIsGeneratedFromTheSchema) {
  const auto r = run("schema --markdown");
  ASSERT_EQ(r.code, 0);
  EXPECT_EQ(read(source / "docs/cases.md"), r.text)
      << "docs/cases.md is stale: regenerate with `build/app/granflow schema --markdown > "
         "docs/cases.md`";
}

// A plot script that fails leaves the data and only warns a user (exit 0), but fails a run the
// tests start: every test program sets GRANFLOW_STRICT_PLOTS=1 (tests/strict_plots.cpp), and a
// strict run whose plot fails exits 4. The failing interpreter stands for a broken plot script.
TEST(Cli, StrictPlotsTurnAFailedPlotIntoExitFour) {
  const auto case_file = (source / "cases/rev/simple_shear_dry.yaml").string();
  for (const bool strict : {true, false}) {
    const fs::path out = scratch(strict ? "plot_strict" : "plot_lenient");
    granflow::core::ProcessOptions options;
    options.output = out.string() + ".log";
    options.set_environment = {"GRANFLOW_PYTHON=/bin/false",
                               std::string("GRANFLOW_STRICT_PLOTS=") + (strict ? "1" : "0")};
    const auto r = granflow::core::run_process(
        {std::string(GRANFLOW_BINARY_DIR) + "/app/granflow", "run", case_file, "--out", out.string(),
         "--quiet"},
        options);
    const std::string text = read(out.string() + ".log") + read(out / "log.txt");
    EXPECT_EQ(r.status, strict ? 4 : 0) << text;
    EXPECT_NE(text.find("plotting with plot_rev.py failed"), std::string::npos) << text;
    EXPECT_TRUE(fs::exists(out / "summary.json"));
    fs::remove_all(out);
    fs::remove(out.string() + ".log");
  }
}
