// Case kinds selected by name from the case file (`kind:` and, for kinds with several tests,
// `test:`), the way LAMMPS selects styles: each module registers its kinds explicitly with a
// schema, a cross-field check and a run function. No global state: the CLI builds the registry.
#pragma once

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
};

class KindRegistry {
 public:
  void add(KindEntry entry);
  // Throws CaseError naming `origin` when the kind/test is unknown.
  const KindEntry& find(const std::string& kind, const std::string& test,
                        const std::string& origin) const;
  const std::vector<KindEntry>& entries() const { return entries_; }

 private:
  std::vector<KindEntry> entries_;
};

// Common schema pieces shared by kinds, so DEM and continuum read one material description.
Schema kind_header(const std::string& kind, const std::string& test, const std::string& doc);

}  // namespace granflow::core
