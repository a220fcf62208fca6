#include "core/kind_registry.hpp"

#include <fmt/format.h>

namespace granflow::core {

void KindRegistry::add(KindEntry entry) {
  for (const auto& e : entries_)
    if (e.kind == entry.kind && e.test == entry.test)
      throw std::logic_error(fmt::format("kind {} {} registered twice", entry.kind, entry.test));
  entries_.push_back(std::move(entry));
}

const KindEntry& KindRegistry::find(const std::string& kind, const std::string& test,
                                    const std::string& origin) const {
  std::string kinds, tests;
  bool kind_known = false;
  for (const auto& e : entries_) {
    if (kinds.find(e.kind) == std::string::npos) kinds += (kinds.empty() ? "" : ", ") + e.kind;
    if (e.kind != kind) continue;
    kind_known = true;
    if (!e.test.empty()) tests += (tests.empty() ? "" : ", ") + e.test;
    if (e.test == test) return e;
  }
  if (!kind_known)
    throw CaseError(
        fmt::format("{}: kind: unknown kind '{}'; expected one of: {}", origin, kind, kinds));
  throw CaseError(fmt::format("{}: test: {} '{}' for kind {}; expected one of: {}", origin,
                              test.empty() ? "missing test" : "unknown test", test, kind, tests));
}

const KindEntry* KindRegistry::lookup(const std::string& kind, const std::string& test) const {
  for (const auto& e : entries_)
    if (e.kind == kind && e.test == test) return &e;
  return nullptr;
}

Schema kind_header(const std::string& kind, const std::string& test, const std::string& doc) {
  Schema schema = make_root_schema(doc);
  schema.choice("kind", {kind}, "case kind").required();
  if (!test.empty()) schema.choice("test", {test}, "test run at the material point").required();
  schema.string("name", "run name; default: the case file name without .yaml (runs/<name>/)");
  schema.string("description", "free text describing the case");
  return schema;
}

}  // namespace granflow::core
