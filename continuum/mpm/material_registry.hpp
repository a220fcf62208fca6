// Solid materials by name, as a case file selects them with `solid.material` (docs/extending.md,
// "An MPM solid material"). Each material's own file declares its keys in the `solid` section and
// reads them into its typed parameters; material_registry.cpp lists the materials, one line each.
// The choices of `solid.material` are the registered names, so a name is spelled only in its
// material's file.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "continuum/mpm/solid_material.hpp"

namespace granflow::core {
class Case;
class Field;
}  // namespace granflow::core

namespace granflow::mpm {

// The defaults a problem gives the keys of its `solid` section, as YAML text by key (e.g. the
// benchmark's numbers); a key without one keeps its material's own default.
using SolidDefaults = std::map<std::string, std::string>;

struct MaterialEntry {
  std::string name;  // the value of `solid.material`
  // Adds the material's keys to the `solid` section, with the problem's defaults where given.
  std::function<void(core::Field& solid, const SolidDefaults& defaults)> declare;
  // Reads the keys of a validated case (`solid.<key>`) into the material's parameters and
  // creates it.
  std::function<std::unique_ptr<SolidMaterial>(const core::Case& c)> create;
};

class MaterialRegistry {
 public:
  void add(MaterialEntry entry);
  std::vector<std::string> names() const;  // in registration order; the first is the default
  // Throws std::invalid_argument naming the valid materials.
  const MaterialEntry& at(const std::string& name) const;
  // `solid.material` (a choice of names()) and the keys of every material. Throws
  // std::logic_error for a default of a key no material declares (a problem's typo).
  void declare(core::Field& solid, const SolidDefaults& defaults) const;
  // The material `solid.material` names, from the case's keys.
  std::unique_ptr<SolidMaterial> create(const core::Case& c) const;

 private:
  std::vector<MaterialEntry> entries_;
};

// Every solid material a case can select.
MaterialRegistry material_registry();

// The default a problem gives `key`, or `fallback` (YAML text) when it gives none.
std::string solid_default(const SolidDefaults& defaults, const std::string& key,
                          const std::string& fallback);

}  // namespace granflow::mpm
