// Case validation: every class of bad input gives one error naming file:line, the key path and
// what was expected, and overrides/sweeps follow the same rules.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/case.hpp"
#include "core/kind_registry.hpp"

using granflow::core::Case;
using granflow::core::CaseError;
using granflow::core::Schema;

namespace {

Schema test_schema() {
  Schema s = granflow::core::kind_header("rev", "simple_shear", "test schema");
  auto& m = s.section("material", "grains");
  m.number("diameter", "m", "grain diameter").required().greater_than(0);
  m.number("restitution", "", "restitution").required().greater_than(0).at_most(1);
  m.number("viscosity", "Pa s", "viscosity").default_value("1e-3").at_least(0);
  auto& l = s.section("loading", "loading");
  l.number("void_ratio", "", "void ratio e").greater_than(0).sweepable();
  l.number("shear_rate", "1/s", "shear rate").required().greater_than(0).sweepable();
  l.number("solid_fraction", "", "ν").greater_than(0).less_than(1);
  l.choice("control", {"constant_volume", "constant_pressure"}, "control")
      .default_value("constant_volume");
  l.integer("steps", "steps").default_value("10").greater_than(0).sweepable();
  l.boolean("verbose", "flag").default_value("false");
  return s;
}

const char* good =
    "kind: rev\n"
    "test: simple_shear\n"
    "material:\n"
    "  diameter: 1.0e-3\n"
    "  restitution: 0.7\n"
    "loading:\n"
    "  void_ratio: 0.8\n"
    "  shear_rate: 10\n";

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  static const Schema schema = test_schema();
  try {
    Case::parse(text, "case.yaml", sets, schema);
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

}  // namespace

TEST(Case, ValidCaseFillsDefaults) {
  const Schema schema = test_schema();
  const Case c = Case::parse(good, "case.yaml", {}, schema);
  EXPECT_DOUBLE_EQ(c.number("material.diameter"), 1e-3);
  EXPECT_DOUBLE_EQ(c.number("material.viscosity"), 1e-3);  // default
  EXPECT_EQ(c.string("loading.control"), "constant_volume");
  EXPECT_EQ(c.integer("loading.steps"), 10);
  EXPECT_FALSE(c.boolean("loading.verbose"));
  EXPECT_FALSE(c.has("loading.solid_fraction"));
  EXPECT_THROW(c.number("loading.nonexistent"), std::logic_error);  // programming error
}

TEST(Case, UnknownKeyIsAnErrorWithLineAndSuggestion) {
  const auto e = error_of(replace(good, "  diameter:", "  diametr:"));
  EXPECT_NE(e.find("case.yaml:4: material.diametr: unknown key"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'diameter'"), std::string::npos) << e;
}

TEST(Case, WrongTypeIsAnError) {
  const auto e = error_of(replace(good, "shear_rate: 10", "shear_rate: fast"));
  EXPECT_NE(e.find("case.yaml:8: loading.shear_rate: not a number"), std::string::npos) << e;
  EXPECT_NE(e.find("> 0"), std::string::npos) << e;
  const auto s = error_of(
      replace(good, "material:\n  diameter: 1.0e-3\n  restitution: 0.7\n", "material: 3\n"));
  EXPECT_NE(s.find("material: expected a section"), std::string::npos) << s;
}

TEST(Case, MissingRequiredKeyIsAnError) {
  const auto e = error_of(replace(good, "  restitution: 0.7\n", ""));
  EXPECT_NE(e.find("material.restitution: missing required key"), std::string::npos) << e;
  EXPECT_NE(e.find("case.yaml:4"), std::string::npos) << e;  // located at the section
}

TEST(Case, PhysicallyImpossibleValuesAreErrors) {
  // e <= 0, restitution outside (0, 1], negative diameter / viscosity, ν >= 1
  EXPECT_NE(
      error_of(replace(good, "void_ratio: 0.8", "void_ratio: 0"))
          .find("loading.void_ratio: value 0 is outside the physical range; expected number > 0"),
      std::string::npos);
  EXPECT_NE(
      error_of(replace(good, "restitution: 0.7", "restitution: 1.2")).find("material.restitution"),
      std::string::npos);
  EXPECT_NE(error_of(replace(good, "restitution: 0.7", "restitution: 0")).find("in (0, 1]"),
            std::string::npos);
  EXPECT_NE(error_of(replace(good, "diameter: 1.0e-3", "diameter: -1.0e-3"))
                .find("case.yaml:4: material.diameter"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(good) + "  solid_fraction: 1.0\n").find("loading.solid_fraction"),
            std::string::npos);
  EXPECT_NE(error_of(replace(good, "restitution: 0.7", "restitution: 0.7\n  viscosity: -1"))
                .find("material.viscosity"),
            std::string::npos);
  EXPECT_NE(
      error_of(replace(good, "void_ratio: 0.8", "void_ratio: .nan")).find("loading.void_ratio"),
      std::string::npos);
}

TEST(Case, UnknownChoiceListsTheValidNames) {
  const auto e = error_of(std::string(good) + "  control: constant_strain\n");
  EXPECT_NE(e.find("loading.control: unknown name 'constant_strain'; expected one of: "
                   "constant_volume, constant_pressure"),
            std::string::npos)
      << e;
}

TEST(Case, KindAndTestAreChecked) {
  EXPECT_NE(error_of(replace(good, "kind: rev", "kind: dem"))
                .find("case.yaml:1: kind: unknown name 'dem'"),
            std::string::npos);
  EXPECT_NE(error_of(replace(good, "test: simple_shear\n", "")).find("test: missing required key"),
            std::string::npos);
}

TEST(Case, YamlSyntaxErrorNamesTheLine) {
  const auto e = error_of(replace(good, "  shear_rate: 10", "  shear_rate: [10"));
  EXPECT_NE(e.find("YAML syntax error"), std::string::npos) << e;
}

TEST(Case, SetOverridesAreValidatedLikeTheFile) {
  const Schema schema = test_schema();
  const Case c =
      Case::parse(good, "case.yaml", {"loading.shear_rate=50", "material.viscosity=0.01"}, schema);
  EXPECT_DOUBLE_EQ(c.number("loading.shear_rate"), 50);
  EXPECT_DOUBLE_EQ(c.number("material.viscosity"), 0.01);
  const auto bad = error_of(good, {"loading.shear_rate=-5"});
  EXPECT_NE(bad.find("--set loading.shear_rate=-5: loading.shear_rate: value -5 is outside"),
            std::string::npos)
      << bad;
  const auto unknown = error_of(good, {"loading.shear_rat=5"});
  EXPECT_NE(unknown.find("--set loading.shear_rat=5: loading.shear_rat: unknown key"),
            std::string::npos)
      << unknown;
  EXPECT_NE(error_of(good, {"loading.shear_rate"}).find("expected key.path=value"),
            std::string::npos);
}

TEST(Case, SweepExpandsAsCartesianProductFirstKeySlowest) {
  const Schema schema = test_schema();
  const Case c =
      Case::parse(std::string(good) +
                      "sweep:\n  loading.shear_rate: [1, 2, 3]\n  loading.void_ratio: [0.6, 0.9]\n",
                  "case.yaml", {}, schema);
  ASSERT_TRUE(c.is_sweep());
  const auto conditions = c.expand_sweep();
  ASSERT_EQ(conditions.size(), 6u);
  EXPECT_DOUBLE_EQ(conditions[0].number("loading.shear_rate"), 1);
  EXPECT_DOUBLE_EQ(conditions[0].number("loading.void_ratio"), 0.6);
  EXPECT_DOUBLE_EQ(conditions[1].number("loading.void_ratio"), 0.9);
  EXPECT_DOUBLE_EQ(conditions[5].number("loading.shear_rate"), 3);
  EXPECT_DOUBLE_EQ(conditions[5].number("loading.void_ratio"), 0.9);
  EXPECT_FALSE(conditions[2].is_sweep());
  EXPECT_NE(conditions[3].location("loading.shear_rate").find("sweep loading.shear_rate=2"),
            std::string::npos);
}

TEST(Case, SweepValuesAndKeysAreValidated) {
  const auto not_sweepable =
      error_of(std::string(good) + "sweep:\n  material.diameter: [1e-3, 2e-3]\n");
  EXPECT_NE(
      not_sweepable.find("case.yaml:10: sweep.material.diameter: not a sweepable key; "
                         "expected one of: loading.void_ratio, loading.shear_rate, loading.steps"),
      std::string::npos)
      << not_sweepable;
  const auto bad_value = error_of(std::string(good) + "sweep:\n  loading.shear_rate: [1, -2]\n");
  EXPECT_NE(bad_value.find("sweep.loading.shear_rate[1]: expected number > 0"), std::string::npos)
      << bad_value;
}

TEST(Case, IntegerKeysSweepOverWholeNumbers) {
  // e.g. dem.seed: one condition per integer value, read back as an integer.
  const Schema schema = test_schema();
  const Case c =
      Case::parse(std::string(good) + "sweep:\n  loading.steps: [5, 7]\n", "case.yaml", {}, schema);
  const auto conditions = c.expand_sweep();
  ASSERT_EQ(conditions.size(), 2u);
  EXPECT_EQ(conditions[0].integer("loading.steps"), 5);
  EXPECT_EQ(conditions[1].integer("loading.steps"), 7);
  const auto fractional = error_of(std::string(good) + "sweep:\n  loading.steps: [5, 7.5]\n");
  EXPECT_NE(fractional.find("sweep.loading.steps[1]: expected integer > 0"), std::string::npos)
      << fractional;
}

TEST(Case, SetOverridesOrAddsADottedSweepKey) {
  // --set sweep.loading.shear_rate=[4, 5] replaces the file's list for that key (not a nested
  // sweep.loading map); a new key adds a dimension.
  const Schema schema = test_schema();
  const Case c =
      Case::parse(std::string(good) + "sweep:\n  loading.shear_rate: [1, 2, 3]\n", "case.yaml",
                  {"sweep.loading.shear_rate=[4, 5]", "sweep.loading.steps=[5, 7]"}, schema);
  const auto conditions = c.expand_sweep();
  ASSERT_EQ(conditions.size(), 4u);
  EXPECT_DOUBLE_EQ(conditions[0].number("loading.shear_rate"), 4);
  EXPECT_DOUBLE_EQ(conditions[3].number("loading.shear_rate"), 5);
  EXPECT_EQ(conditions[3].integer("loading.steps"), 7);
}

TEST(Case, CrossFieldFailureIsLocated) {
  const Schema schema = test_schema();
  const Case c = Case::parse(good, "case.yaml", {}, schema);
  try {
    c.fail("loading.void_ratio", "expected something else");
    FAIL();
  } catch (const CaseError& e) {
    EXPECT_STREQ(e.what(), "case.yaml:7: loading.void_ratio: expected something else");
  }
}

TEST(Case, ResolvedYamlRoundTripsThroughTheValidator) {
  const Schema schema = test_schema();
  const Case c = Case::parse(good, "case.yaml", {"loading.shear_rate=7"}, schema);
  const Case again = Case::parse(c.resolved_yaml(), "resolved.yaml", {}, schema);
  EXPECT_DOUBLE_EQ(again.number("loading.shear_rate"), 7);
  EXPECT_DOUBLE_EQ(again.number("material.viscosity"), 1e-3);
}

namespace {
std::filesystem::path write_files(const std::string& name,
                                  const std::vector<std::pair<std::string, std::string>>& files) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("granflow_include_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const auto& [file, text] : files) std::ofstream(dir / file) << text;
  return dir;
}
}  // namespace

TEST(Case, IncludeMergesParameterSectionsAndLocatesTheirErrors) {
  const Schema schema = test_schema();
  const std::string main_text =
      replace(good, "  restitution: 0.7\n", "") + "include: calibrated.yaml\n";
  auto dir = write_files(
      "ok", {{"case.yaml", main_text}, {"calibrated.yaml", "material:\n  restitution: 0.85\n"}});
  const Case c = Case::load(dir / "case.yaml", {}, schema);
  EXPECT_DOUBLE_EQ(c.number("material.restitution"), 0.85);
  EXPECT_DOUBLE_EQ(c.number("material.diameter"), 1e-3);  // from the including file
  EXPECT_EQ(c.location("material.restitution"), (dir / "calibrated.yaml").string() + ":2");
  // --set still overrides an included key
  EXPECT_DOUBLE_EQ(Case::load(dir / "case.yaml", {"material.restitution=0.5"}, schema)
                       .number("material.restitution"),
                   0.5);
  // an impossible value in the included file is reported at its own line
  dir = write_files(
      "bad", {{"case.yaml", main_text}, {"calibrated.yaml", "material:\n  restitution: 1.5\n"}});
  try {
    Case::load(dir / "case.yaml", {}, schema);
    FAIL();
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("calibrated.yaml:2: material.restitution: value 1.5"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(Case, IncludeRefusesAKeyGivenTwiceAndMissingFiles) {
  const Schema schema = test_schema();
  auto dir = write_files("twice", {{"case.yaml", std::string(good) + "include: calibrated.yaml\n"},
                                   {"calibrated.yaml", "material:\n  restitution: 0.85\n"}});
  try {
    Case::load(dir / "case.yaml", {}, schema);
    FAIL();
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("material.restitution: given both here and in"),
              std::string::npos)
        << e.what();
  }
  dir = write_files("missing", {{"case.yaml", std::string(good) + "include: nowhere.yaml\n"}});
  EXPECT_THROW(Case::load(dir / "case.yaml", {}, schema), CaseError);
  std::filesystem::remove_all(dir);
}
