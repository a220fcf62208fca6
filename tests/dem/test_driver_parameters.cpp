// The deck header granflow-dem reads: DriverParameters from NAME=VALUE words (granflow-dem
// --header, used by hand-written decks) give the same lines as the deck writer's struct.
#include <gtest/gtest.h>

#include <stdexcept>

#include "dem_coupling/deck/driver_parameters.hpp"

namespace granflow::dem {
namespace {

TEST(DriverParameters, WordsGiveTheSameHeaderAsTheStruct) {
  DriverParameters p;
  p.shear_rate = 50;
  p.total_steps = 1000;
  p.sample_every = 100;
  p.servo_every = 100;  // the words' default: servo_every = sample_every
  p.profile_bins = 10;
  p.particle_density = 2500;
  EXPECT_EQ(driver_parameter_lines(driver_parameters_from_words(
                {"shear_rate=50", "total_steps=1000", "sample_every=100", "profile_bins=10",
                 "particle_density=2500"})),
            driver_parameter_lines(p));
  p.constant_pressure = true, p.normal_stress = 100, p.servo_every = 300, p.servo_move_every = 100;
  EXPECT_EQ(driver_parameter_lines(driver_parameters_from_words(
                {"shear_rate=50", "total_steps=1000", "sample_every=100", "profile_bins=10",
                 "particle_density=2500", "constant_pressure=1", "normal_stress=100",
                 "servo_every=300", "servo_move_every=100"})),
            driver_parameter_lines(p));
}

TEST(DriverParameters, AWordThatIsNoParameterIsNamed) {
  for (const char* bad : {"shear=5", "shear_rate", "shear_rate=fast", "total_steps=1e3x"}) try {
      driver_parameters_from_words({bad});
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace granflow::dem
