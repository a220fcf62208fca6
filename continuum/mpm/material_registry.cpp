#include "continuum/mpm/material_registry.hpp"

#include <stdexcept>

#include "continuum/mpm/linear_elastic.hpp"
#include "core/case.hpp"
#include "core/schema.hpp"

namespace granflow::mpm {

// One line per material (built on each call: no global state).
MaterialRegistry material_registry() {
  MaterialRegistry r;
  r.add(linear_elastic_material());
  return r;
}

void MaterialRegistry::add(MaterialEntry entry) {
  if (entry.name.empty() || !entry.declare || !entry.create)
    throw std::logic_error("a solid material needs a name, declare and create");
  for (const auto& e : entries_)
    if (e.name == entry.name) throw std::logic_error("solid material '" + e.name + "' twice");
  entries_.push_back(std::move(entry));
}

std::vector<std::string> MaterialRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& e : entries_) out.push_back(e.name);
  return out;
}

const MaterialEntry& MaterialRegistry::at(const std::string& name) const {
  for (const auto& e : entries_)
    if (e.name == name) return e;
  std::string valid;
  for (const auto& n : names()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown solid material '" + name + "' (one of: " + valid + ")");
}

void MaterialRegistry::declare(core::Field& solid, const SolidDefaults& defaults) const {
  if (entries_.empty()) throw std::logic_error("no solid material registered");
  solid.choice("material", names(), "constitutive model of the solid points")
      .default_value(entries_.front().name);
  for (const auto& e : entries_) e.declare(solid, defaults);
  for (const auto& [key, text] : defaults)
    if (!solid.child(key))
      throw std::logic_error("a default for solid." + key + ", which no solid material declares");
}

std::unique_ptr<SolidMaterial> MaterialRegistry::create(const core::Case& c) const {
  return at(c.string("solid.material")).create(c);
}

std::string solid_default(const SolidDefaults& defaults, const std::string& key,
                          const std::string& fallback) {
  const auto it = defaults.find(key);
  return it == defaults.end() ? fallback : it->second;
}

}  // namespace granflow::mpm
