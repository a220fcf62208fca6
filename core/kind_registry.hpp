// Case kinds selected by name from the case file (`kind:` and, for kinds with several tests,
// `test:`), the way LAMMPS selects styles: each module registers its kinds explicitly with a
// schema, a cross-field check and a run function. No global state: the CLI builds the registry.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/case.hpp"
#include "core/run.hpp"

namespace granflow::core {

struct KindEntry {
  std::string kind;     // e.g. "rev"
  std::string test;     // e.g. "simple_shear"; empty when the kind has no `test:` key
  std::string summary;  // one line for --help and docs
  Schema schema;        // must contain `kind` (and `test`) as choice fields
  std::function<void(const Case&)> check;  // cross-field checks; throw via Case::fail
  std::function<int(RunContext&)> run;     // returns an ExitCode
  std::string example;                     // a case file under cases/ that uses this kind
  // Checks of the files the case reads (data sets), made by `run` before the run directory
  // exists (throw via Case::fail); `check` leaves them out, the files may not exist yet. Optional.
  std::function<void(const Case&)> check_inputs = nullptr;
  // The run function hands its conditions to core::run_conditions, so that the ranks of an
  // mpirun share them (docs/parallel-runs.md); otherwise a run under mpirun is rank 0's alone.
  bool distributes_conditions = false;
  // `granflow report RUN_DIR`: the kind's own Markdown section of report.md, placed after the
  // description. It may bring summary.json and result.h5 up to date (a DEM sweep re-derives its
  // fits) and redraw its plots. Called also when RUN_DIR has result.h5 but no summary.json yet
  // (an interrupted run). Optional.
  std::function<std::string(const std::filesystem::path& run_dir, Summary& summary)> report =
      nullptr;
  // `granflow study convergence CASE`: the kind's ladder script, a path under the source
  // directory (analysis/...), started with CASE, the study directory (holding the resolved case
  // as case.yaml) and the command's options; empty: the kind has no convergence study.
  std::string convergence_study{};
};

class KindRegistry {
 public:
  void add(KindEntry entry);
  // Throws CaseError naming `origin` when the kind/test is unknown.
  const KindEntry& find(const std::string& kind, const std::string& test,
                        const std::string& origin) const;
  // nullptr when this build has no such kind/test (e.g. a report of a DEM run by a build
  // without the DEM).
  const KindEntry* lookup(const std::string& kind, const std::string& test) const;
  const std::vector<KindEntry>& entries() const { return entries_; }

 private:
  std::vector<KindEntry> entries_;
};

// Common schema pieces shared by kinds, so DEM and continuum read one material description.
Schema kind_header(const std::string& kind, const std::string& test, const std::string& doc);

}  // namespace granflow::core
