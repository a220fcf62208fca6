// Bad DEM tables through the command line (`granflow run`, no shell: tests/cli/granflow_child.hpp):
// each is one line naming the table's file and line (where there is one), the case key and what
// was expected, exit 2, and no run directory.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/cli/granflow_child.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path work = fs::path(GRANFLOW_BINARY_DIR) / "test_calibration_table_errors";

const std::string good_rows =
    "shear_rate,normal_stress,friction,friction_err,solid_fraction,solid_fraction_err\n"
    "2,100,0.38,0.004,0.586,0.0003\n"
    "10,100,0.42,0.004,0.575,0.0003\n"
    "40,100,0.49,0.004,0.553,0.0003\n";

struct Bad {
  std::string name;
  std::string table;         // the table's text
  std::string data;          // keys of the data section besides `table`
  std::string material;      // the material section
  std::vector<std::string> expected;  // texts the one line must hold
};

std::string si_material() {
  return "{diameter: 1.0e-3, particle_density: 2500, restitution: 0.7, particle_friction: 0.5}";
}

TEST(DemTableErrors, EveryBadTableIsOneLineAndExitTwo) {
  const std::string cp = "protocol: constant_pressure";
  const std::vector<Bad> cases = {
      {"missing_column", "shear_rate,friction,friction_err\n2,0.4,0.004\n", cp, si_material(),
       {"missing_column.csv:1: data.columns:", "missing column", "normal stress"}},
      {"unknown_column", good_rows, cp + ", columns: {friction: mu}", si_material(),
       {"unknown_column.csv:1: data.columns.friction:", "column 'mu' is not in the header"}},
      {"unknown_quantity", good_rows, cp + ", columns: {temperature: T}", si_material(),
       {"data.columns.temperature: unknown key", "granular_temperature"}},
      {"non_numeric",
       "# a comment\nshear_rate,normal_stress,friction,friction_err\n2,100,0.38,0.004\n"
       "4,1O0,0.40,0.004\n",
       cp, si_material(), {"non_numeric.csv:4: data.table:", "column 'normal_stress'",
                           "expected a finite number, got '1O0'"}},
      {"non_finite", "shear_rate,normal_stress,friction,friction_err\n2,100,nan,0.004\n", cp,
       si_material(), {"non_finite.csv:2: data.table:", "column 'friction'", "got 'nan'"}},
      {"infinite", "shear_rate,normal_stress,friction,friction_err\n2,inf,0.4,0.004\n", cp,
       si_material(), {"infinite.csv:2: data.table:", "got 'inf'"}},
      {"negative_phi",
       "shear_rate,normal_stress,solid_fraction,friction,friction_err\n2,100,-0.5,0.4,0.004\n",
       cp, si_material(), {"negative_phi.csv:2:", "φ in (0, 0.74], got -0.5"}},
      {"phi_above_074",
       "shear_rate,normal_stress,solid_fraction,friction,friction_err\n2,100,0.75,0.4,0.004\n",
       cp, si_material(), {"phi_above_074.csv:2:", "φ in (0, 0.74], got 0.75"}},
      {"negative_p", "shear_rate,normal_stress,friction,friction_err\n2,-100,0.4,0.004\n", cp,
       si_material(), {"negative_p.csv:2:", "column 'normal_stress'", "a value > 0, got -100"}},
      {"negative_T",
       "shear_rate,normal_stress,granular_temperature,friction,friction_err\n"
       "2,100,-1e-6,0.4,0.004\n",
       cp, si_material(), {"negative_T.csv:2:", "granular_temperature", "a value >= 0"}},
      {"no_protocol", good_rows, "", si_material(),
       {"data.protocol: not given and not inferable for no_protocol.csv",
        "constant_pressure or constant_volume"}},
      {"table_protocol_disagrees", "# protocol: constant_volume\n" + good_rows, cp, si_material(),
       {"table_protocol_disagrees.csv:1: data.protocol:", "the case says constant_pressure"}},
      {"dimensionless_with_si_material", "normal_stress,friction,friction_err\n100,0.4,0.004\n",
       cp + ", units: dimensionless", si_material(),
       {"material.diameter:", "1 with the dimensionless table", "got 0.001"}},
      {"field_count", "shear_rate,normal_stress,friction,friction_err\n2,100,0.4\n", cp,
       si_material(), {"field_count.csv:2: data.table:", "3 fields", "names 4 columns"}},
  };
  fs::remove_all(work);
  fs::create_directories(work);
  for (const auto& bad : cases) {
    const std::string& stem = bad.name;
    std::ofstream(work / (stem + ".csv")) << bad.table;
    const fs::path case_file = work / (bad.name + ".yaml");
    std::ofstream(case_file) << "kind: calibrate\nmaterial: " << bad.material
                             << "\ncollisional: {jamming_fraction: 0.587}\n"
                                "force_chains: {enabled: false}\n"
                                "fit: {parameters: jamming_fraction}\n"
                                "data: {table: " << stem << ".csv"
                             << (bad.data.empty() ? "" : ", ") << bad.data << "}\n";
    const fs::path out = work / (bad.name + "_out");
    granflow::test::GranflowChild child({"run", case_file.string(), "--out", out.string()},
                                        work / (bad.name + ".log"));
    const int code = child.wait();
    std::string text = child.output();
    EXPECT_EQ(code, 2) << bad.name << ": " << text;
    while (!text.empty() && text.back() == '\n') text.pop_back();
    EXPECT_EQ(text.find('\n'), std::string::npos) << bad.name << ": more than one line: " << text;
    for (const auto& e : bad.expected)
      EXPECT_NE(text.find(e), std::string::npos) << bad.name << ": no '" << e << "' in: " << text;
    EXPECT_FALSE(fs::exists(out)) << bad.name << ": a run directory was made on bad input";
    std::printf("%s\n", text.c_str());
  }
}

}  // namespace
