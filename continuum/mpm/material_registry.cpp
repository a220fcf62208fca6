#include <stdexcept>

#include "continuum/mpm/linear_elastic.hpp"
#include "continuum/mpm/solid_material.hpp"

namespace granflow::mpm {

void MaterialRegistry::add(std::string name, std::vector<std::string> parameter_names,
                           Factory factory) {
  entries_[std::move(name)] = Entry{std::move(parameter_names), std::move(factory)};
}

std::vector<std::string> MaterialRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, entry] : entries_) out.push_back(name);
  return out;
}

const std::vector<std::string>& MaterialRegistry::parameter_names(const std::string& name) const {
  auto it = entries_.find(name);
  if (it == entries_.end()) throw std::invalid_argument("unknown solid material '" + name + "'");
  return it->second.parameter_names;
}

std::unique_ptr<SolidMaterial> MaterialRegistry::create(const std::string& name,
                                                        const MaterialParameters& params) const {
  auto it = entries_.find(name);
  if (it == entries_.end()) {
    std::string valid;
    for (const auto& n : names()) valid += (valid.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown solid material '" + name + "' (one of: " + valid + ")");
  }
  for (const auto& key : it->second.parameter_names) {
    if (!params.count(key)) {
      throw std::invalid_argument("solid material '" + name + "' needs parameter '" + key + "'");
    }
  }
  return it->second.factory(params);
}

MaterialRegistry default_material_registry() {
  MaterialRegistry r;
  r.add("linear_elastic", {"young_modulus", "poisson_ratio", "density"},
        [](const MaterialParameters& p) {
          return std::make_unique<LinearElastic>(p.at("young_modulus"), p.at("poisson_ratio"),
                                                 p.at("density"));
        });
  return r;
}

}  // namespace granflow::mpm
