// Safety of what granflow starts and deletes (reliability probe, docs: README "Run directories"):
// no shell anywhere (core/process.hpp), the one quoting function for printed command lines,
// --force only on granflow's own run directories and never on ., .., /, $HOME, the working
// directory, the source tree or their ancestors, a plain `name:`, and a calibrated.yaml whose
// comments cannot add YAML.
#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/process.hpp"
#include "core/run.hpp"
#ifdef GRANFLOW_TEST_CALIBRATE
#include "tests/calibration/synthetic_data.hpp"
#endif

namespace fs = std::filesystem;
using granflow::core::ProcessOptions;
using granflow::core::run_process;
using granflow::core::shell_quote;

namespace {

const std::string granflow = std::string(GRANFLOW_BINARY_DIR) + "/app/granflow";
const fs::path source = GRANFLOW_SOURCE_DIR;
const fs::path rev_case = source / "cases/rev/simple_shear_dry.yaml";

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh scratch directory of this test process.
fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("granflow_safety_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct Output {
  int code;
  std::string text;
};

// granflow ARGS, started without a shell, in `cwd` (default: this one), stdout+stderr captured.
Output granflow_run(const std::vector<std::string>& args, const fs::path& cwd = {},
                    const std::vector<std::string>& env = {}) {
  static int count = 0;
  const fs::path out =
      fs::temp_directory_path() /
      ("granflow_safety_out_" + std::to_string(::getpid()) + "_" + std::to_string(++count));
  std::vector<std::string> argv = {granflow};
  argv.insert(argv.end(), args.begin(), args.end());
  ProcessOptions options;
  options.output = out;
  options.directory = cwd;
  options.set_environment = env;
  const auto r = run_process(argv, options);
  Output o{r.status, r.error + read(out)};
  fs::remove(out);
  return o;
}

int lines(const std::string& text) {
  int n = 0;
  for (char ch : text) n += ch == '\n';
  return n;
}

}  // namespace

// ---- core/process: no shell, clear errors, the one quoting function

TEST(Process, ShellQuoteRoundTripsThroughPrintfInSh) {
  const fs::path dir = scratch("quote");
  const std::string pwned = (dir / "PWNED").string();
  const std::vector<std::string> words = {"plain",
                                          "",
                                          " ",
                                          "a b",
                                          "it's",
                                          "''",
                                          "'",
                                          "\"dq\"",
                                          "$(touch " + pwned + ")",
                                          "`touch " + pwned + "`",
                                          "a\nb\n",
                                          "\\",
                                          "\\'",
                                          "*",
                                          "~",
                                          "#x",
                                          "a=b",
                                          "-n",
                                          "%s%%",
                                          "; touch " + pwned,
                                          "&& touch " + pwned,
                                          "| cat",
                                          "\t",
                                          "ünïcødé 🙂",
                                          "$HOME",
                                          "!x",
                                          "x'$(touch " + pwned + ")'y"};
  for (const auto& word : words) {
    // The one place a shell is used on purpose: to check that the quoting is what sh reads.
    ProcessOptions options;
    options.output = dir / "printed";
    const auto r = run_process({"/bin/sh", "-c", "printf %s " + shell_quote(word)}, options);
    ASSERT_TRUE(r.ok()) << r.error << " status " << r.status << " for [" << word << "]";
    EXPECT_EQ(read(dir / "printed"), word) << shell_quote(word);
  }
  EXPECT_FALSE(fs::exists(dir / "PWNED"));
  // Plain words stay readable; the command line of a rerun is the words quoted and joined.
  EXPECT_EQ(shell_quote("-np"), "-np");
  EXPECT_EQ(shell_quote("/usr/bin/mpirun"), "/usr/bin/mpirun");
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
  EXPECT_EQ(granflow::core::shell_line({"mpirun", "-np", "2", "a b"}), "mpirun -np 2 'a b'");
  fs::remove_all(dir);
}

TEST(Process, RunsAnArgumentVectorWithoutAShell) {
  const fs::path dir = scratch("argv");
  ProcessOptions options;
  options.output = dir / "out.txt";
  // Shell syntax in an argument is just text.
  const std::string payload = "$(touch " + (dir / "PWNED").string() + ")";
  auto r = run_process({"printf", "%s|", payload, "a b"}, options);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(read(dir / "out.txt"), payload + "|a b|");
  EXPECT_FALSE(fs::exists(dir / "PWNED"));
  // Appending, the working directory, and the exit status.
  options.append = true;
  options.directory = dir;
  r = run_process({"pwd"}, options);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(read(dir / "out.txt"), payload + "|a b|" + fs::canonical(dir).string() + "\n");
  EXPECT_EQ(run_process({"false"}).status, 1);
  // The environment set for the child.
  options.append = false;
  options.set_environment = {"GRANFLOW_SAFETY_TEST=it's set"};
  r = run_process({"printenv", "GRANFLOW_SAFETY_TEST"}, options);
  EXPECT_EQ(read(dir / "out.txt"), "it's set\n");
  fs::remove_all(dir);
}

TEST(Process, AProgramThatCannotStartIsAClearErrorNamingIt) {
  auto r = run_process({"/no/such/dir/program", "x"});
  EXPECT_FALSE(r.started());
  EXPECT_EQ(r.status, 127);
  EXPECT_NE(r.error.find("/no/such/dir/program"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("No such file or directory"), std::string::npos) << r.error;
  ProcessOptions options;
  options.directory = "/no/such/dir";
  r = run_process({"true"}, options);
  EXPECT_FALSE(r.started());
  EXPECT_NE(r.error.find("/no/such/dir"), std::string::npos) << r.error;
  EXPECT_FALSE(run_process({}).started());
}

// ---- the probe's injections: nothing is executed

TEST(Safety, OutWithAQuoteAndCommandSubstitutionExecutesNothing) {
  const fs::path dir = scratch("inject_out");
  const fs::path pwned = dir / "PWNED_out";
  const fs::path out = dir / ("x'$(touch " + pwned.string() + ")'y");
  const auto r = granflow_run({"run", rev_case.string(), "--out", out.string(), "--quiet"});
  EXPECT_EQ(r.code, 0) << r.text;
  EXPECT_TRUE(fs::exists(out / "summary.json")) << r.text;  // the directory by its literal name
  EXPECT_FALSE(fs::exists(pwned)) << "a shell ran the --out text";
  // `granflow report` of that directory (plots through core::run_process too)
  const auto report = granflow_run({"report", out.string()});
  EXPECT_EQ(report.code, 0) << report.text;
  EXPECT_FALSE(fs::exists(pwned));
  fs::remove_all(dir);
}

TEST(Safety, CaseNameWithCommandSubstitutionIsRefusedAtTheKey) {
  const fs::path dir = scratch("inject_name");
  const fs::path pwned = dir / "PWNED_name";
  std::string text = read(rev_case);
  const auto at = text.find("\ntest: simple_shear\n");
  ASSERT_NE(at, std::string::npos);
  text.insert(at + 20, "name: \"n'$(touch " + pwned.string() + ")'\"\n");
  std::ofstream(dir / "case.yaml") << text;
  const int line = lines(text.substr(0, at + 20)) + 1;
  const auto r = granflow_run({"run", (dir / "case.yaml").string(), "--quiet"}, dir);
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find((dir / "case.yaml").string() + ":" + std::to_string(line) +
                        ": name: expected a plain file name"),
            std::string::npos)
      << r.text;
  EXPECT_FALSE(fs::exists(pwned));
  EXPECT_FALSE(fs::exists(dir / "runs"));
  // The same through --set, and the names that are no file name.
  for (const std::string bad : {"../victim", "/tmp/victim", ".", "..", "a b", "x\ny"}) {
    const auto s = granflow_run({"check", rev_case.string(), "--set", "name=" + bad});
    EXPECT_EQ(s.code, 2) << bad << ": " << s.text;
    EXPECT_NE(s.text.find("name: expected a plain file name"), std::string::npos) << s.text;
  }
  EXPECT_EQ(granflow_run({"check", rev_case.string(), "--set", "name=ok_name-1.2"}).code, 0);
  fs::remove_all(dir);
}

// ---- --force: only granflow's own run directories, never the protected ones

TEST(Safety, ForceRefusesDotDotDotTheSourceTreeHomeAndUnmarkedDirectories) {
  const fs::path top = scratch("force");
  const fs::path cwd = top / "work";
  fs::create_directories(cwd);
  std::ofstream(top / "keep_parent.txt") << "parent";
  std::ofstream(cwd / "thesis.tex") << "thesis";
  // Markers do not make the protected directories replaceable.
  std::ofstream(cwd / granflow::core::run_marker) << "";
  std::ofstream(top / granflow::core::run_marker) << "";
  const fs::path home = top / "home";
  fs::create_directories(home);
  std::ofstream(home / "notes.txt") << "notes";
  std::ofstream(home / granflow::core::run_marker) << "";
  const fs::path unmarked = top / "victim";
  fs::create_directories(unmarked / "sub");
  std::ofstream(unmarked / "important.txt") << "important";
  std::ofstream(top / "afile.txt") << "a file";

  struct Attempt {
    std::string out, why;
  };
  const std::vector<Attempt> attempts = {
      {".", "is . or .."},
      {"..", "is . or .."},
      {cwd.string(), "working directory"},
      {top.string(), "never replaces it"},  // an ancestor of both the cwd and $HOME
      {source.string(), "source tree"},
      {(source / "cases" / "..").string(), "is . or .."},
      {home.string(), "home directory"},
      {"/", "root directory"},
      {unmarked.string(), "no .granflow-run marker"},
      {(top / "afile.txt").string(), "not a directory"},
  };
  for (const auto& a : attempts) {
    const auto r = granflow_run({"run", rev_case.string(), "--out", a.out, "--force", "--quiet"},
                                cwd, {"HOME=" + home.string()});
    EXPECT_EQ(r.code, 2) << a.out << ": " << r.text;
    EXPECT_EQ(lines(r.text), 1) << r.text;
    EXPECT_NE(r.text.find("error: " + a.out + ": "), std::string::npos) << r.text;
    EXPECT_NE(r.text.find(a.why), std::string::npos) << a.out << ": " << r.text;
  }
  // Nothing was deleted.
  EXPECT_EQ(read(cwd / "thesis.tex"), "thesis");
  EXPECT_EQ(read(top / "keep_parent.txt"), "parent");
  EXPECT_EQ(read(home / "notes.txt"), "notes");
  EXPECT_EQ(read(unmarked / "important.txt"), "important");
  EXPECT_TRUE(fs::is_directory(unmarked / "sub"));
  EXPECT_EQ(read(top / "afile.txt"), "a file");
  EXPECT_TRUE(fs::exists(source / "CMakeLists.txt"));
  EXPECT_TRUE(fs::exists(source / "core" / "run.cpp"));
  fs::remove_all(top);
}

TEST(Safety, StudyConvergenceForceReplacesOnlyAStudyDirectoryGranflowMade) {
  // `granflow study convergence --out DIR --force` removed any existing DIR that was not
  // protected; it now needs granflow's marker there, like a run directory.
  const fs::path dir = scratch("study_force");
  fs::create_directories(dir / "mydata");
  std::ofstream(dir / "mydata" / "thesis.tex") << "keep\n";
  const auto o =
      granflow_run({"study", "convergence", (source / "cases/mpm/rheometer_ci.yaml").string(),
                    "--out", (dir / "mydata").string(), "--force"});
  EXPECT_EQ(o.code, granflow::core::exit_bad_input) << o.text;
  EXPECT_NE(o.text.find("marker"), std::string::npos) << o.text;
  EXPECT_TRUE(fs::exists(dir / "mydata" / "thesis.tex"));
  fs::remove_all(dir);
}

TEST(Safety, ForceReplacesARunDirectoryGranflowCreated) {
  const fs::path dir = scratch("replace");
  const fs::path out = dir / "runs" / "new" / "run";  // parents created
  auto r = granflow_run({"run", rev_case.string(), "--out", out.string(), "--quiet"});
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_TRUE(fs::exists(out / granflow::core::run_marker));
  std::ofstream(out / "stale.txt") << "from the first run";
  r = granflow_run({"run", rev_case.string(), "--out", out.string(), "--quiet"});
  EXPECT_EQ(r.code, 2) << r.text;  // without --force: refused
  EXPECT_TRUE(fs::exists(out / "stale.txt"));
  r = granflow_run({"run", rev_case.string(), "--out", out.string(), "--force", "--quiet"});
  EXPECT_EQ(r.code, 0) << r.text;
  EXPECT_FALSE(fs::exists(out / "stale.txt"));
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_TRUE(fs::exists(out / granflow::core::run_marker));
  fs::remove_all(dir);
}

TEST(Safety, RunDirectoryIsCreatedAtomicallyAndRefusedCleanly) {
  const fs::path dir = scratch("atomic");
  {
    granflow::core::RunDirectory first(dir / "a" / "b", false);
    EXPECT_TRUE(fs::exists(dir / "a" / "b" / granflow::core::run_marker));
  }
  EXPECT_THROW(granflow::core::RunDirectory(dir / "a" / "b", false), granflow::core::CaseError);
  // a parent that is a file: a CaseError naming the path, not an abort
  std::ofstream(dir / "file") << "x";
  try {
    granflow::core::RunDirectory under_file(dir / "file" / "sub", false);
    FAIL() << "created under a file";
  } catch (const granflow::core::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "file" / "sub").string()), std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

// ---- calibrated.yaml: free text in comments cannot add a section

#ifdef GRANFLOW_TEST_CALIBRATE
TEST(Safety, CraftedCalibrateNameCannotAddASectionToCalibratedYaml) {
  namespace synthetic = granflow::calibration::testing;
  const fs::path dir = scratch("calibrated");
  const auto data = synthetic::write_dem_dataset(
      synthetic::synthetic_points(synthetic::dry_model(0.8, 0.60), 42, 16), dir / "dem.h5");
  // `name:` is refused as no plain file name ...
  const std::string crafted = "pwn').\ncollisional:\n  jamming_fraction: 0.70\n#";
  const std::string body =
      "material: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7, "
      "particle_friction: 0.5}\n"
      "collisional: {jamming_fraction: 0.6}\nforce_chains: {enabled: false}\n"
      "data: {files: '" +
      data.string() +
      "', observables: 'friction solid_fraction'}\n"
      "fit: {parameters: 'restitution'}\n";
  YAML::Emitter named;
  named << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "calibrate" << YAML::Key
        << "name" << YAML::Value << crafted << YAML::EndMap;
  std::ofstream(dir / "named.yaml") << named.c_str() << "\n" << body;
  auto r = granflow_run(
      {"run", (dir / "named.yaml").string(), "--out", (dir / "named").string(), "--quiet"});
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find("name: expected a plain file name"), std::string::npos) << r.text;
  // ... but the default name, the case file's stem, may hold a newline: it reaches the comment.
  const fs::path file = dir / (crafted + ".yaml");
  std::ofstream(file) << "kind: calibrate\n" << body;
  const fs::path out = dir / "run";
  r = granflow_run({"run", file.string(), "--out", out.string(), "--quiet"});
  ASSERT_EQ(r.code, 0) << r.text;
  const std::string text = read(out / "calibrated.yaml");
  const YAML::Node y = YAML::Load(text);
  EXPECT_FALSE(y["collisional"].IsDefined()) << text;
  EXPECT_TRUE(y["material"]["restitution"].IsDefined()) << text;
  EXPECT_EQ(y.size(), 1u) << text;
  EXPECT_NE(text.find("# Calibrated parameters (granflow kind: calibrate, run 'pwn'). "
                      "collisional:   jamming_fraction: 0.70 #')."),
            std::string::npos)
      << text;
  fs::remove_all(dir);
}
#endif
