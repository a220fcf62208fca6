// Run directory, summary.json, result.h5 and the numerical-failure stop.
#include <gtest/gtest.h>

#include <limits>

#include <sstream>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/result_file.hpp"
#include "core/run.hpp"

namespace fs = std::filesystem;
using namespace granflow::core;

namespace {
fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("granflow_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}
}  // namespace

TEST(RunDirectory, ExistingDirectoryIsNeverOverwrittenWithoutForce) {
  const fs::path dir = fresh_dir("rundir");
  {
    RunDirectory first(dir, false);
    std::ofstream(dir / "result.h5") << "previous";
  }
  EXPECT_THROW(RunDirectory(dir, false), CaseError);
  EXPECT_TRUE(fs::exists(dir / "result.h5"));  // untouched
  RunDirectory forced(dir, true);
  EXPECT_FALSE(fs::exists(dir / "result.h5"));
  fs::remove_all(dir);
}

TEST(Summary, RoundTripsNumbersExactlyAndLeavesOutWhatIsNotFinite) {
  const fs::path dir = fresh_dir("summary");
  fs::create_directories(dir);
  Summary s;
  s.set("steady.mu", 0.1 + 0.2);  // not representable in short decimal: checks %.17g
  s.set("cost.wall_s", 1.5e-7);
  s.set("steady.J", std::nan(""));
  s.set("steady.I", std::numeric_limits<double>::infinity());
  EXPECT_EQ(s.non_finite(), (std::vector<std::string>{"steady.I", "steady.J"}));
  s.write(dir / "summary.json");
  const Summary r = Summary::read(dir / "summary.json");
  EXPECT_EQ(r.get("steady.mu"), 0.1 + 0.2);
  EXPECT_EQ(r.get("cost.wall_s"), 1.5e-7);
  // summary.json holds finite numbers only: no null, nan or inf in the file.
  EXPECT_FALSE(r.contains("steady.J"));
  EXPECT_FALSE(r.contains("steady.I"));
  std::stringstream text;
  text << std::ifstream(dir / "summary.json").rdbuf();
  EXPECT_EQ(text.str().find("null"), std::string::npos);
  EXPECT_EQ(text.str().find("inf"), std::string::npos);
  EXPECT_EQ(text.str().find("nan"), std::string::npos);
  // A file of an earlier granflow with null still reads (as NaN).
  std::ofstream(dir / "old.json") << "{\n  \"steady.J\": null\n}\n";
  EXPECT_TRUE(std::isnan(Summary::read(dir / "old.json").get("steady.J")));
  fs::remove_all(dir);
}

TEST(Summary, EmptyTruncatedOrForeignFilesAreRefusedNamingTheByte) {
  // `granflow report` on a corrupt summary.json must refuse it, not write an empty report.
  const fs::path dir = fresh_dir("summary_bad");
  fs::create_directories(dir);
  Summary s;
  s.set("steady.mu", 0.5);
  s.set("steady.T", 1e-4);
  s.write(dir / "summary.json");
  std::stringstream whole;
  whole << std::ifstream(dir / "summary.json").rdbuf();
  const std::string text = whole.str();
  const std::vector<std::string> bad = {"",
                                        "   \n",
                                        text.substr(0, text.size() / 2),  // truncated mid-way
                                        text.substr(0, text.size() - 3),  // no closing brace
                                        "[1, 2]",
                                        "{\"a\": 1 \"b\": 2}",
                                        "{\"a\": abc}",
                                        text + "trailing"};
  for (const auto& content : bad) {
    std::ofstream(dir / "bad.json") << content;
    try {
      Summary::read(dir / "bad.json");
      ADD_FAILURE() << "accepted: " << content;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("not a granflow summary.json"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(Summary::read(dir / "summary.json").get("steady.T"), 1e-4);  // the good one still reads
  fs::remove_all(dir);
}

TEST(ResultFile, DatasetsCarryUnitsAndSurviveReopen) {
  const fs::path dir = fresh_dir("h5");
  fs::create_directories(dir);
  {
    ResultFile f(dir / "result.h5");
    const std::vector<double> T{1e-4, 2e-4, 3e-4};
    f.write("series/granular_temperature", T, "m^2/s^2", "granular temperature");
    f.write_matrix("fields/stress", std::vector<double>{1, 2, 3, 4, 5, 6}, 2, 3, "Pa", "stress");
    f.attribute("/steady", "diameter", 1e-3);
    f.attribute("/", "kind", std::string("rev"));
  }
  EXPECT_EQ(read_dataset(dir / "result.h5", "series/granular_temperature"),
            (std::vector<double>{1e-4, 2e-4, 3e-4}));
  EXPECT_EQ(read_string_attribute(dir / "result.h5", "series/granular_temperature", "unit"),
            "m^2/s^2");
  EXPECT_EQ(read_number_attribute(dir / "result.h5", "/steady", "diameter"), 1e-3);
  EXPECT_EQ(read_string_attribute(dir / "result.h5", "/", "kind"), "rev");
  EXPECT_EQ(read_dataset(dir / "result.h5", "fields/stress").size(), 6u);
  fs::remove_all(dir);
}

TEST(NumericalFailure, NamesStepPointAndVariable) {
  try {
    check_finite(-1e-3, 42, "material point 7", "granular_temperature", true);
    FAIL();
  } catch (const NumericalFailure& e) {
    EXPECT_EQ(e.step, 42);
    EXPECT_NE(std::string(e.what()).find(
                  "step 42, material point 7: granular_temperature = -0.001 (negative)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(check_finite(std::nan(""), 1, "p", "v"), NumericalFailure);
  EXPECT_THROW(check_finite(INFINITY, 1, "p", "v"), NumericalFailure);
  EXPECT_NO_THROW(check_finite(0.0, 1, "p", "v", true));
}
