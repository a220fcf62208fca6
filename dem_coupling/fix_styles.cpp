#include "dem_coupling/fix_styles.hpp"

#include <array>

#include "dem_coupling/fixes/fix_drainage.hpp"
#include "dem_coupling/fixes/fix_fluid_le.hpp"

namespace granflow::dem {

namespace {
// Add {"style/name", &create_style} entries here (see fix_styles.hpp).
constexpr std::array<FixStyle, 2> fix_style_table{
    {{"fluid/le", &create_fix_fluid_le}, {"drainage", &create_fix_drainage}}};
}  // namespace

std::span<const FixStyle> custom_fix_styles() { return fix_style_table; }

void register_custom_fix_styles(LAMMPS_NS::LAMMPS& lmp) {
  for (const FixStyle& style : custom_fix_styles())
    register_fix_style(lmp, style.name, style.create);
}

}  // namespace granflow::dem
