// Constant-normal-stress servo (NormalStressServo with default_servo_gain) on model plants: the
// linear-spring dry plant below (run_elastic_loop) and, here, the immersed steady rheology in the
// loop granflow-dem runs: every servo interval (0.05 strain, 5 samples) the height moves linearly
// (fix deform y final) to servo.next_height(L_y, mean σ_yy), either over the whole interval (dry
// decks) or over its first 2 samples and then held, the mean taken over the 3 held samples
// (immersed decks: ShearDeck::servo_move_every). σ_yy relaxes towards its steady value over a
// strain γ_r = 0.1 (the microstructure's response) and responds at once to the dilation rate:
// σ_measured = σ (1 - β ε̇/γ̇) (lubrication and drag resist the dilation; the DEM point below shows β
// = 2-4: σ_yy 12 vs 75 Pa while dilating vs compacting at ε̇ = ±0.2 γ̇ about 43 Pa).
//
// Plant: φ = φ_m / (1 + b √K), K = J + α I², J = η0 γ̇/σ, I² = ρ_p d² γ̇²/σ (Boyer et al. 2011 with
// J -> K, Trulsson et al. 2012), i.e. σ_ss(φ) = (η0 γ̇ + α ρ_p d² γ̇²) / ((φ_m/φ - 1)/b)². The
// parameters are the DEM's own wet-sweep fit (φ_m = 0.5961, b = 1.543, α = 0.081, docs/
// dem_dataset.md), not the servo's design values (b = 1, α = 0.6): the loop must tolerate that.
// The wet sweep's 25 Pa / St 0.1 point (η0 = 0.25 Pa s, γ̇ = 10 1/s, start φ = 0.57) ended at
// σ_yy = 46.6 Pa with gain 0.01 (the dry rule), at most 0.002 height strain per 0.05 strain and
// the height moving over the whole interval.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dem_coupling/deck/shear_deck.hpp"
#include "dem_coupling/extraction/normal_stress_servo.hpp"

namespace {

using granflow::dem::default_servo_gain;
using granflow::dem::NormalStressServo;
using granflow::dem::ShearDeckParams;

struct SteadyRheology {
  double solid_fraction_max, b, alpha;  // φ = φ_m / (1 + b √K), K = J + α I²
};
constexpr SteadyRheology dem_fit{0.5961, 1.543, 0.081};
constexpr SteadyRheology boyer{0.585, 1.0, 0.6};

struct Condition {
  double viscosity, normal_stress;  // η0 (Pa s), target σ_yy (Pa)
  double shear_rate = 10.0, diameter = 1e-3, particle_density = 2500.0;
};

double steady_stress(const SteadyRheology& r, const Condition& c, double phi) {
  const double numerator = c.viscosity * c.shear_rate + r.alpha * c.particle_density * c.diameter *
                                                            c.diameter * c.shear_rate *
                                                            c.shear_rate;
  const double root_k = std::max(r.solid_fraction_max / phi - 1.0, 1e-9) / r.b;
  return numerator / (root_k * root_k);
}

ShearDeckParams immersed(const Condition& c) {
  ShearDeckParams p;
  p.material.diameter = c.diameter;
  p.material.particle_density = c.particle_density;
  p.constant_pressure = true;
  p.normal_stress = c.normal_stress;
  p.shear_rate = c.shear_rate;
  p.wet.enabled = true;
  p.wet.viscosity = c.viscosity;
  p.wet.trulsson_alpha = 0.6;
  return p;
}

// Interval means of σ_yy / p0 as the servo sees them, one per update, over `total` strain.
// move_samples: 0 = the height moves over the whole interval and all 5 samples count; k > 0 =
// it moves over the first k samples and the servo averages the others.
std::vector<double> run_loop(const SteadyRheology& r, const Condition& c, double gain,
                             double max_strain, int move_samples, double rate_response,
                             double total = 8.0, double start_phi = 0.57) {
  const double servo_strain = 0.05, sample_strain = 0.01, response_strain = 0.1;
  constexpr int samples = 5, substeps = 10;
  NormalStressServo servo(c.normal_stress, gain, max_strain);
  double height = 1.0, sigma = steady_stress(r, c, start_phi), mean = 0.0;
  std::vector<double> means;
  const int updates = int(std::lround(total / servo_strain));
  for (int k = 0; k < updates; ++k) {
    const double start = height, end = k == 0 ? height : servo.next_height(height, mean);
    const int moving = k == 0 ? 0 : move_samples;  // the first interval keeps the deck's height
    const double move_strain = (moving > 0 ? moving : samples) * sample_strain;
    const double dilation_per_strain = std::log(end / start) / move_strain;  // ε̇ / γ̇
    double sum = 0.0;
    int counted = 0;
    for (int s = 0; s < samples; ++s) {
      const bool moves = moving == 0 || s < moving;
      for (int q = 1; q <= substeps; ++q) {
        const double f =
            std::min(1.0, double(s * substeps + q) / ((moving > 0 ? moving : samples) * substeps));
        const double phi = start_phi / (start + (end - start) * f);  // N, L_x, L_z fixed
        sigma += (steady_stress(r, c, phi) - sigma) *
                 (1.0 - std::exp(-sample_strain / substeps / response_strain));
      }
      const double measured = sigma * (1.0 - rate_response * (moves ? dilation_per_strain : 0.0));
      if (moving == 0 || !moves) {
        sum += measured;
        ++counted;
      }
    }
    mean = sum / counted;
    height = end;
    means.push_back(mean / c.normal_stress);
  }
  return means;
}

// Largest |σ/p0 - 1| over the updates at strain >= from.
double worst_after(const std::vector<double>& means, double from) {
  double worst = 0.0;
  for (std::size_t k = std::size_t(std::lround(from / 0.05)); k < means.size(); ++k)
    worst = std::max(worst, std::abs(means[k] - 1.0));
  return worst;
}

TEST(DemServo, DefaultGainIsTheDryRuleWithoutLiquid) {
  // Dry: 0.1 I_target within [1e-4, 0.02], I = γ̇ d / sqrt(p0/ρ_p) = 10e-3 / sqrt(100/2500) = 0.05.
  ShearDeckParams p = immersed({0.0, 100.0});
  p.wet.enabled = false;
  EXPECT_NEAR(default_servo_gain(p), 0.005, 1e-15);  // round-off of the sqrt
  p.normal_stress = 1e-4;                            // I = 50: clamped
  EXPECT_EQ(default_servo_gain(p), 0.02);
}

TEST(DemServo, LinearSpringGainIsLimitedByTheElasticResponse) {
  // k_n = 1000 N/m, σ_yy = 100 Pa, d = 1 mm: elastic d ln σ/d ln φ ≈ k_n/(σ d) = 1e4, so the gain
  // is 2 σ d/k_n = 2e-4 instead of the dry rule's 0.1 I = 0.005 (I = 0.05).
  ShearDeckParams p = immersed({0.0, 100.0});
  p.wet.enabled = false;
  p.material.contact_law = granflow::dem::ContactLaw::hooke;
  p.material.normal_stiffness = 1000.0;
  EXPECT_NEAR(default_servo_gain(p), 2e-4, 1e-15);
  p.material.normal_stiffness = 1.0;  // very soft springs: the dry rule is the smaller one
  EXPECT_NEAR(default_servo_gain(p), 0.005, 1e-15);
}

// Dry plant with an elastic response (linear-spring contacts): steady φ = φ_c − a I, i.e.
// σ_ss(φ) = ρ_p (a γ̇ d / (φ_c − φ))², approached over a strain γ_r = 0.1 as above; and every
// height change answered at once elastically, dσ = k_el p0 d ln φ (k_el ≈ k_n/(σ_yy d), the
// affine compression of contacts carrying ~0.6 σ_yy d² each; shear_deck.hpp), σ >= 0. The height
// moves linearly over each servo interval and the servo sees the interval mean. Returns the
// interval means of σ/p0.
std::vector<double> run_elastic_loop(double gain, double servo_strain, double elastic_sensitivity,
                                     double shear_rate, double total = 8.0) {
  const double p0 = 100.0, rho = 2500.0, d = 1e-3, phi_c = 0.588, a = 0.16;
  const double max_strain = 0.004, sample_strain = 0.01, response_strain = 0.1;
  const auto steady = [&](double phi) {
    const double gap = std::max(phi_c - phi, 1e-4);
    return rho * std::pow(a * shear_rate * d / gap, 2);
  };
  NormalStressServo servo(p0, gain, max_strain);
  const int samples = int(std::lround(servo_strain / sample_strain)), substeps = 10;
  const double start_phi = 0.57;
  double height = 1.0, sigma = steady(start_phi), mean = 0.0;
  std::vector<double> means;
  for (int k = 0; k < int(std::lround(total / servo_strain)); ++k) {
    const double start = height, end = k == 0 ? height : servo.next_height(height, mean);
    double sum = 0.0, previous_phi = start_phi / start;
    for (int s = 0; s < samples; ++s) {
      for (int q = 1; q <= substeps; ++q) {
        const double phi =
            start_phi / (start + (end - start) * double(s * substeps + q) / (samples * substeps));
        // elastic increment about the target stress; dilated contacts open, so σ stays >= 0
        sigma = std::max(0.0, sigma + p0 * elastic_sensitivity * std::log(phi / previous_phi));
        previous_phi = phi;
        sigma +=
            (steady(phi) - sigma) * (1.0 - std::exp(-sample_strain / substeps / response_strain));
      }
      sum += sigma;
    }
    mean = sum / samples;
    height = end;
    means.push_back(mean / p0);
  }
  return means;
}

// Root mean square of σ/p0 − 1 over the updates from strain `from` (updates every `every`).
double rms_after(const std::vector<double>& means, double from, double every) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = std::size_t(std::lround(from / every)); k < means.size(); ++k, ++n)
    sum += (means[k] - 1.0) * (means[k] - 1.0);
  return std::sqrt(sum / n);
}

TEST(DemServo, LinearSpringDefaultsHoldAnElasticPlantTheDryRuleDoesNot) {
  // k_n/(σ_yy d) = 1e4: k_el = 1e4. At I = 0.02 and 0.1 the linear-spring defaults (gain
  // 2 σ_yy d/k_n = 2e-4, update every 0.01 strain) hold the interval means to an rms of 4.6 % and
  // 0.7 % of p0 from strain 4 (start φ = 0.57); bound 10 %, the DEM's standard error of σ_yy at
  // I = 0.02 (the DEM: 94-101 Pa, docs/dem_dataset.md). The dry rule (0.1 I, every 0.05 strain)
  // runs into the clamp: rms 5.2 and 11 p0 here, the DEM swung 5-800 Pa; bound 1.
  ShearDeckParams p;
  p.constant_pressure = true;
  p.normal_stress = 100.0;
  p.material.contact_law = granflow::dem::ContactLaw::hooke;
  p.material.normal_stiffness = 1000.0;
  for (double shear_rate : {4.0, 20.0}) {  // I = 0.02, 0.1
    p.shear_rate = shear_rate;
    const double gain = default_servo_gain(p);
    ASSERT_NEAR(gain, 2e-4, 1e-15);
    EXPECT_LT(rms_after(run_elastic_loop(gain, 0.01, 1e4, shear_rate), 4.0, 0.01), 0.1)
        << shear_rate;
    const double dry_rule = 0.1 * shear_rate * 5e-3;
    EXPECT_GT(rms_after(run_elastic_loop(dry_rule, 0.05, 1e4, shear_rate), 4.0, 0.05), 1.0)
        << shear_rate;
  }
}

TEST(DemServo, ImmersedGainFollowsTheMixedNumberAtTheTarget) {
  // η0 = 0.25 Pa s, p0 = 25 Pa: J = 0.1, I = 0.1, K = 0.1 + 0.6 × 0.01 = 0.106,
  // gain = 0.125 / (2 (1 + √K)/√K) = 0.0625 √K/(1 + √K).
  const double root_k = std::sqrt(0.106);
  EXPECT_NEAR(default_servo_gain(immersed({0.25, 25.0})), 0.0625 * root_k / (1.0 + root_k), 1e-15);
  // Inertial limit (η0 -> 0): 0.0625 √α I/(1 + √α I), within 10 % of half the dry rule 0.1 I.
  const double gain = default_servo_gain(immersed({1e-9, 100.0}));
  EXPECT_NEAR(gain, 0.0025, 0.1 * 0.0025);
}

TEST(DemServo, ImmersedDecksMoveTheHeightOverTwoFifthsOfTheIntervalThenHold) {
  ShearDeckParams p = immersed({0.25, 25.0});
  p.particles = 200;
  p.servo_strain = 0.05;
  p.sample_strain = 0.01;
  p.servo_max_strain = 0.01;
  p.servo_gain = default_servo_gain(p);
  const auto wet = granflow::dem::make_shear_deck(p, "particles.data");
  EXPECT_EQ(wet.servo_every, 5 * wet.sample_every);
  EXPECT_EQ(wet.servo_move_every, 2 * wet.sample_every);
  EXPECT_NE(
      wet.deck.find("variable gf_servo_move_every equal " + std::to_string(wet.servo_move_every)),
      std::string::npos);
  p.wet.enabled = false;  // dry decks keep moving over the whole interval
  EXPECT_EQ(granflow::dem::make_shear_deck(p, "particles.data").servo_move_every, 0);
}

TEST(DemServo, ViscousRegimeServoSettlesOnItsTarget) {
  // The failing point: 25 Pa, St = 0.1, rate response β = 3. With the immersed default gain
  // (0.015), the wet clamp of 0.01 per 0.05 strain and move-then-hold, the servo's interval mean
  // is within 2 % of p0 from strain 3 to 8 (2 %: a third of the DEM point's standard error of
  // σ_yy, 0.62/25; this plant leaves < 0.2 %), for the DEM's rheology and Boyer's.
  constexpr double beta = 3.0;
  const Condition viscous{0.25, 25.0};
  const double gain = default_servo_gain(immersed(viscous));
  EXPECT_LT(worst_after(run_loop(dem_fit, viscous, gain, 0.01, 2, beta), 3.0), 0.02);
  EXPECT_LT(worst_after(run_loop(boyer, viscous, gain, 0.01, 2, beta), 3.0), 0.02);
  // Without the rate response, moving over the whole interval would do as well...
  EXPECT_LT(worst_after(run_loop(dem_fit, viscous, gain, 0.01, 0, 0.0), 3.0), 0.02);
  // ...but with it the loop locks into a period-2 cycle at the clamp (the DEM, moving throughout
  // at twice this gain: interval means alternating 12 and 75 Pa, mean 40 Pa):
  EXPECT_GT(worst_after(run_loop(dem_fit, viscous, gain, 0.01, 0, beta), 3.0), 0.3);
  // The sweep's settings (dry-rule gain 0.01, clamp 0.002, moving throughout) are still > 10 %
  // high at strain 8 (1.86 p0 in the DEM), and the new gain alone does not cure them.
  EXPECT_GT(run_loop(dem_fit, viscous, 0.01, 0.002, 0, beta).back(), 1.1);
  EXPECT_GT(run_loop(dem_fit, viscous, gain, 0.002, 0, beta).back(), 1.1);
}

TEST(DemServo, ImmersedDefaultGainIsStableAtTheDenseInertialEnd) {
  // St = 1 to 100 at 25 and 100 Pa (d ln σ/d ln φ ~ 20-90): the same rule, clamp and
  // move-then-hold settle within 2 % by strain 3 and stay there (no growing oscillation), for
  // the DEM's rheology and Boyer's; a gain 20x the default oscillates (loop gain 2.5 > 2).
  // (This plant has no overshoot of the contact network after a fast move; in the DEM that is
  // what made twice the default gain cycle at St = 1-100, 25 Pa, docs/dem_fluid.md.)
  constexpr double beta = 3.0;
  for (const Condition c : {Condition{2.5e-4, 100.0}, Condition{2.5e-4, 25.0},
                            Condition{2.5e-3, 100.0}, Condition{0.025, 25.0}}) {
    const double gain = default_servo_gain(immersed(c));
    EXPECT_LT(worst_after(run_loop(dem_fit, c, gain, 0.01, 2, beta), 3.0), 0.02) << c.viscosity;
    EXPECT_LT(worst_after(run_loop(boyer, c, gain, 0.01, 2, beta), 3.0), 0.02) << c.viscosity;
  }
  const Condition dense{2.5e-4, 100.0};
  EXPECT_GT(
      worst_after(
          run_loop(dem_fit, dense, 20.0 * default_servo_gain(immersed(dense)), 0.01, 2, beta), 3.0),
      0.1);
}

}  // namespace
