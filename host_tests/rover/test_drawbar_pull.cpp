// Drawbar pulls from the force balance (docs/rover-loads.md, section 6): the
// balance, the split by load, the DP_max cap, high slip and invalid inputs,
// flight code and double twin.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "prepared_support.hpp"
#include "rover_test_support.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace sinkwatch {
namespace {

using flight::DrawbarStatus;
using rover_test::d;
using rover_test::q;

struct Scene {
  flight::RoverParams params;
  flight::WheelLoadResult loads;
  double mg;
};

Scene scene(double pitch, double roll) {
  Scene s{flight::yutu_like_rover_params(flight::kGravityMoon), {}, 0.0};
  s.loads = flight::wheel_loads(test::prepared_rover(s.params), rover_test::attitude(pitch, roll), rover_test::joints(0.1, -0.1, 0.2, -0.05), flight::kNoDriveTorques);
  s.mg = d(s.params.mass_kg) * d(s.params.gravity_mps2);
  return s;
}

flight::DrawbarInput input(double accel, double pitch, double ratio) {
  flight::DrawbarInput in{};
  in.accel_mps2 = q<flight::AccelMps2>(accel);
  in.pitch_rad = q<flight::AngleRad>(pitch);
  in.slip_known = false;
  in.slip = flight::Ratio::zero();
  for (flight::Ratio& r : in.dp_max_ratio) r = q<flight::Ratio>(ratio);
  return in;
}

double load_sum(const flight::WheelLoadResult& loads) {
  double sum = 0.0;
  for (const flight::WheelLoadN w : loads.load_n) sum += d(w);
  return sum;
}

TEST(RoverDrawbarPull, SharesBalanceTheSlopeAndSplitByLoad) {
  const Scene s = scene(0.2, 0.05);
  ASSERT_EQ(s.loads.status, flight::WheelLoadStatus::ok);
  const flight::DrawbarInput in = input(0.02, 0.2, 0.5);
  const flight::DrawbarResult r = flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, in);
  ASSERT_EQ(r.status, DrawbarStatus::ok);
  const double m = d(s.params.mass_kg);
  const double g = d(s.params.gravity_mps2);
  const double total = m * (d(in.accel_mps2) + g * std::sin(d(in.pitch_rad)));
  const double bound = rover_test::drawbar_bound_n(s.mg, total);
  EXPECT_NEAR(d(r.total_n), total, bound);
  double sum = 0.0;
  for (std::size_t i = 0; i < 6; ++i) {
    sum += d(r.dp_n[i]);
    // Equal DP/W on every wheel: the share is the load's fraction.
    EXPECT_NEAR(d(r.dp_n[i]), total * d(s.loads.load_n[i]) / load_sum(s.loads), bound) << i;
  }
  EXPECT_NEAR(sum, total, 6.0 * bound);
  EXPECT_EQ(r.capped_mask, 0U);
  // The rear wheels carry more on an uphill pitch, so they pull more.
  EXPECT_GT(d(r.dp_n[2]), d(r.dp_n[0]));
}

// The pulls take sin(pitch) from the loads when they were computed at the
// drawbar's pitch (the step's case): the same bits as the sine computed
// afresh, at pitches over the attitude range, uphill and downhill.
TEST(RoverDrawbarPull, SineFromTheLoadsGivesTheSameBitsAsComputedAfresh) {
  for (int k = -20; k <= 20; ++k) {
    const double pitch = 0.0137 * k;
    const Scene s = scene(pitch, 0.03);
    ASSERT_EQ(s.loads.status, flight::WheelLoadStatus::ok) << pitch;
    const flight::DrawbarInput in = input(0.01, pitch, 0.6);
    ASSERT_EQ(s.loads.pitch_rad, in.pitch_rad);
    flight::WheelLoadResult without_sine = s.loads;
    without_sine.pitch_rad = flight::AngleRad::zero();
    without_sine.sin_pitch = sinkwatch::fx::Q1_30::zero();
    const flight::DrawbarResult reused = flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, in);
    const flight::DrawbarResult fresh = flight::drawbar_pulls(test::prepared_rover(s.params), without_sine, in);
    ASSERT_EQ(reused.status, fresh.status) << pitch;
    EXPECT_EQ(reused.total_n, fresh.total_n) << pitch;
    for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(reused.dp_n[i], fresh.dp_n[i]) << pitch << " wheel " << i;
  }
}

/// The pull of wheel i in Q31.32 as fx::div and fx::mul give it: total (W_i / sum W).
flight::WheelLoadN share_by_division(const flight::RoverParams& p, const flight::WheelLoadResult& loads,
                                     const flight::DrawbarInput& in, std::size_t i) {
  using W = flight::WideQ;
  fx::Status st;
  const W sin_pitch = fx::rescale<W>(fx::sin(in.pitch_rad.q(), st), st);
  const W accel = fx::add(fx::rescale<W>(in.accel_mps2.q(), st), fx::mul<W>(p.gravity_mps2.q(), sin_pitch, st), st);
  const W total = fx::mul<W>(p.mass_kg.q(), accel, st);
  std::int64_t sum_raw = 0;
  for (const flight::WheelLoadN w : loads.load_n) sum_raw += w.raw();
  // The raw Q15.16 sum widened to Q31.32 (exact: below 2^34 * 2^16).
  const W sum = W::from_raw(sum_raw * 65536);
  const W fraction = fx::div<W>(fx::rescale<W>(loads.load_n[i].q(), st), sum, st);
  const flight::WheelLoadN share{fx::rescale<flight::LoadQ>(fx::mul(total, fraction, st), st)};
  EXPECT_TRUE(st.ok());
  return share;
}

// The split by load divides through one reciprocal of the load sum with an
// exact remainder correction: bit for bit the rounded quotient of fx::div,
// for loads up to the format's top (sums beyond 2^32 raw, where the
// reciprocal's divisor drops low bits), small and zero loads.
TEST(RoverDrawbarPull, SplitByLoadIsTheDivisionsRoundedFractionBitForBit) {
  // The heaviest rover at the largest gravity and acceleration: a total of
  // about 18 kN, so that one unit of the fraction (2^-32) moves a pull by a
  // tenth of its LSB or more and a wrong fraction shows in the pulls' bits.
  flight::RoverParams p = flight::yutu_like_rover_params(flight::kGravityMoon);
  p.mass_kg = q<flight::MassKg>(1000.0);
  p.gravity_mps2 = q<flight::AccelMps2>(10.0);
  p.attitude_limit_rad = q<flight::AngleRad>(1.0);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  std::mt19937 rng(15U);
  int compared = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    flight::WheelLoadResult loads{};
    loads.status = flight::WheelLoadStatus::ok;
    const std::uint32_t top = 1U << (1U + (static_cast<std::uint32_t>(trial) % 31U));
    for (flight::WheelLoadN& w : loads.load_n) {
      const std::uint32_t raw = ((rng() % 8U) == 0U) ? 0U : (rng() % top);
      w = flight::WheelLoadN{flight::LoadQ::from_raw(static_cast<std::int32_t>(raw & 0x7FFFFFFFU))};
    }
    // One wheel carrying nearly all the weight: fractions next to 1 (2^32
    // raw), where the reciprocal's estimate is farthest from the quotient.
    if ((trial % 3) != 0) {
      const std::uint32_t dominant = 0x40000000U + (rng() % 0x40000000U);
      if ((trial % 3) == 2) {
        for (flight::WheelLoadN& w : loads.load_n) w = flight::WheelLoadN{flight::LoadQ::from_raw(static_cast<std::int32_t>(rng() % 16U))};
      }
      loads.load_n[trial % 6] = flight::WheelLoadN{flight::LoadQ::from_raw(static_cast<std::int32_t>(dominant))};
    }
    const flight::DrawbarInput in = input(10.0 - (0.01 * static_cast<double>(trial % 5)), 0.9, 2.0);
    const flight::DrawbarResult r = flight::drawbar_pulls(test::prepared_rover(p), loads, in);
    if (r.status == DrawbarStatus::invalid_loads) continue;  // every load zero
    // Loads of a few LSB pull more than DP_max allows: those are capped.
    ASSERT_TRUE((r.status == DrawbarStatus::ok) || (r.status == DrawbarStatus::capped)) << trial;
    for (std::size_t i = 0; i < 6; ++i) {
      if ((r.capped_mask & (1U << i)) == 0U) {
        ++compared;
        ASSERT_EQ(r.dp_n[i].raw(), share_by_division(p, loads, in, i).raw()) << trial << " wheel " << i;
      }
    }
  }
  EXPECT_GT(compared, 60000);
}

TEST(RoverDrawbarPull, DecelerationDownhillGivesNegativePull) {
  const Scene s = scene(-0.15, 0.0);
  const flight::DrawbarResult r = flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, input(-0.01, -0.15, 0.5));
  ASSERT_EQ(r.status, DrawbarStatus::ok);
  for (const flight::DrawbarPullN dp : r.dp_n) EXPECT_LT(dp.raw(), 0);
}

TEST(RoverDrawbarPull, ShareBeyondDpMaxIsCapped) {
  const Scene s = scene(0.0, 0.0);
  // a = 1 m/s^2 on the Moon: m a = 140 N, 0.61 of the weight, above DP_max/W = 0.3.
  flight::DrawbarInput in = input(1.0, 0.0, 0.3);
  in.dp_max_ratio[4] = q<flight::Ratio>(0.9);  // this wheel's soil can take its share
  const flight::DrawbarResult r = flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, in);
  ASSERT_EQ(r.status, DrawbarStatus::capped);
  EXPECT_EQ(r.capped_mask, 0x2FU);  // all but wheel 4
  const double total = d(s.params.mass_kg) * 1.0;
  EXPECT_NEAR(d(r.total_n), total, rover_test::drawbar_bound_n(s.mg, total));
  for (std::size_t i = 0; i < 6; ++i) {
    const double w = d(s.loads.load_n[i]);
    const double expected = (i == 4) ? total * w / load_sum(s.loads) : 0.3 * w;
    EXPECT_NEAR(d(r.dp_n[i]), expected, rover_test::drawbar_bound_n(s.mg, total)) << i;
  }
  // Negative side: braking hard is capped at -DP_max.
  const flight::DrawbarResult neg = flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, input(-1.0, 0.0, 0.3));
  ASSERT_EQ(neg.status, DrawbarStatus::capped);
  EXPECT_NEAR(d(neg.dp_n[0]), -0.3 * d(s.loads.load_n[0]), rover_test::drawbar_bound_n(s.mg, total));
}

TEST(RoverDrawbarPull, HighSlipTakesEveryWheelAtDpMax) {
  const Scene s = scene(0.1, 0.0);
  flight::DrawbarInput in = input(0.0, 0.1, 0.35);
  in.slip_known = true;
  in.slip = s.params.high_slip;  // at the level: saturated
  const flight::DrawbarResult r = flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, in);
  ASSERT_EQ(r.status, DrawbarStatus::saturated);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(d(r.dp_n[i]), 0.35 * d(s.loads.load_n[i]), rover_test::drawbar_bound_n(s.mg, 0.0)) << i;
  }
  in.slip = q<flight::Ratio>(0.59);  // just below: the balance
  EXPECT_EQ(flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, in).status, DrawbarStatus::ok);
  in.slip_known = false;
  in.slip = q<flight::Ratio>(0.95);  // a value that is not a measurement is ignored
  EXPECT_EQ(flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, in).status, DrawbarStatus::ok);
}

TEST(RoverDrawbarPull, InvalidInputsReturnStatusNotNumber) {
  const Scene s = scene(0.0, 0.0);
  const auto expect_invalid = [&](const flight::WheelLoadResult& loads, const flight::DrawbarInput& in,
                                  DrawbarStatus expected) {
    const flight::DrawbarResult r = flight::drawbar_pulls(test::prepared_rover(s.params), loads, in);
    EXPECT_EQ(r.status, expected);
    EXPECT_FALSE(flight::usable(r.status));
    for (const flight::DrawbarPullN dp : r.dp_n) EXPECT_EQ(dp.raw(), 0);
  };
  const flight::WheelLoadResult tipped =
      flight::wheel_loads(test::prepared_rover(s.params), rover_test::attitude(0.0, 0.8), rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
  ASSERT_EQ(tipped.status, flight::WheelLoadStatus::tip_over);
  expect_invalid(tipped, input(0.0, 0.0, 0.3), DrawbarStatus::invalid_loads);
  expect_invalid(s.loads, input(10.5, 0.0, 0.3), DrawbarStatus::invalid_input);
  expect_invalid(s.loads, input(-10.5, 0.0, 0.3), DrawbarStatus::invalid_input);
  expect_invalid(s.loads, input(0.0, 1.1, 0.3), DrawbarStatus::invalid_input);
  flight::DrawbarInput zero_ratio = input(0.0, 0.0, 0.3);
  zero_ratio.dp_max_ratio[3] = flight::Ratio::zero();
  expect_invalid(s.loads, zero_ratio, DrawbarStatus::invalid_input);
  flight::DrawbarInput big_ratio = input(0.0, 0.0, 2.5);
  expect_invalid(s.loads, big_ratio, DrawbarStatus::invalid_input);
  flight::DrawbarInput bad_slip = input(0.0, 0.0, 0.3);
  bad_slip.slip_known = true;
  bad_slip.slip = q<flight::Ratio>(1.2);
  expect_invalid(s.loads, bad_slip, DrawbarStatus::invalid_input);
  flight::RoverParams bad_params = s.params;
  bad_params.mass_kg = flight::MassKg::zero();
  EXPECT_EQ(flight::drawbar_pulls(test::prepared_rover(bad_params), s.loads, input(0.0, 0.0, 0.3)).status, DrawbarStatus::invalid_input);
}

TEST(RoverDrawbarPull, ReferenceTwinAgreesOnTheSameCases) {
  const Scene s = scene(0.25, -0.1);
  ground::WheelLoads loads;
  loads.status = ground::LoadStatus::ok;
  for (std::size_t i = 0; i < 6; ++i) loads.load_n[i] = d(s.loads.load_n[i]);
  const ground::RoverGeometry g = rover_test::to_ground(s.params);
  ground::DrawbarParams p;
  p.dp_max_over_w.fill(0.4);
  p.high_slip = d(s.params.high_slip);
  for (const double accel : {-0.5, 0.0, 0.03, 0.5}) {
    const flight::DrawbarInput in = input(accel, 0.25, 0.4);
    const flight::DrawbarResult r = flight::drawbar_pulls(test::prepared_rover(s.params), s.loads, in);
    const ground::DrawbarPulls ref =
        ground::drawbar_pulls(g, loads, ground::DrawbarInput{d(in.accel_mps2), d(in.pitch_rad), false, 0.0}, p);
    ASSERT_TRUE(flight::usable(r.status));
    EXPECT_EQ(r.status == DrawbarStatus::capped, ref.status == ground::DrawbarStatus::capped) << accel;
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_NEAR(d(r.dp_n[i]), ref.dp_n[i], rover_test::drawbar_bound_n(s.mg, ref.total_n)) << accel << " " << i;
    }
  }
}

// Loads the load model itself would not produce, as a caller with its own
// load source could: every load zero, one load negative, loads at the top
// of the load format whose DP_max (up to twice the load) does not fit it;
// and a downhill slope past the attitude limit. Each is refused with its
// status, never turned into pulls (folded in from test_cov_drawbar_pull.cpp).
flight::WheelLoadResult equal_loads(double each_n) {
  flight::WheelLoadResult r{};
  for (flight::WheelLoadN& l : r.load_n) {
    l = q<flight::WheelLoadN>(each_n);
  }
  r.weight_normal_n = q<flight::WheelLoadN>(6.0 * each_n > 30000.0 ? 30000.0 : 6.0 * each_n);
  r.status = flight::WheelLoadStatus::ok;
  return r;
}

flight::DrawbarInput level_input(double dp_max_ratio) {
  flight::DrawbarInput in{};
  for (flight::Ratio& r : in.dp_max_ratio) {
    r = q<flight::Ratio>(dp_max_ratio);
  }
  return in;
}

const flight::PreparedParameters& moon_rover() {
  static const flight::PreparedParameters prepared =
      test::prepared_rover(flight::yutu_like_rover_params(flight::kGravityMoon));
  return prepared;
}

TEST(DrawbarPullsGivenLoads, AllLoadsZeroIsInvalidLoads) {
  const flight::DrawbarResult r = flight::drawbar_pulls(moon_rover(), equal_loads(0.0), level_input(0.5));
  EXPECT_EQ(r.status, DrawbarStatus::invalid_loads);
  EXPECT_FALSE(flight::usable(r.status));
}

TEST(DrawbarPullsGivenLoads, NegativeLoadIsInvalidInput) {
  flight::WheelLoadResult loads = equal_loads(37.8);
  loads.load_n[4] = q<flight::WheelLoadN>(-1.0);
  EXPECT_EQ(flight::drawbar_pulls(moon_rover(), loads, level_input(0.5)).status, DrawbarStatus::invalid_input);
}

TEST(DrawbarPullsGivenLoads, DownhillBeyondTheAttitudeLimitIsInvalidInput) {
  flight::DrawbarInput in = level_input(0.5);
  in.pitch_rad = q<flight::AngleRad>(-1.01);  // the Yutu-like limit is 1.0 rad
  EXPECT_EQ(flight::drawbar_pulls(moon_rover(), equal_loads(37.8), in).status, DrawbarStatus::invalid_input);
  in.pitch_rad = q<flight::AngleRad>(-0.99);
  EXPECT_TRUE(flight::usable(flight::drawbar_pulls(moon_rover(), equal_loads(37.8), in).status));
}

TEST(DrawbarPullsGivenLoads, SaturatedPullBeyondTheLoadFormatIsOverflowNotANumber) {
  flight::DrawbarInput in = level_input(2.0);
  in.slip_known = true;
  in.slip = q<flight::Ratio>(0.9);  // above high_slip (0.6): every wheel at DP_max = 2 W
  // 20000 N per wheel: DP_max = 40000 N does not fit Q15.16 (max 32768 N).
  const flight::DrawbarResult big = flight::drawbar_pulls(moon_rover(), equal_loads(20000.0), in);
  EXPECT_EQ(big.status, DrawbarStatus::overflow);
  EXPECT_EQ(big.dp_n[0], flight::DrawbarPullN::zero());
  // The control: 10000 N per wheel gives 20000 N, which fits.
  const flight::DrawbarResult fits = flight::drawbar_pulls(moon_rover(), equal_loads(10000.0), in);
  ASSERT_EQ(fits.status, DrawbarStatus::saturated);
  EXPECT_NEAR(d(fits.dp_n[0]), 20000.0, 0.01);
}

// The arithmetic of drawbar_pulls() on raw integers (drawbar_pull.hpp,
// detail) against the chain of fx operations it replaced in session 18, bit
// for bit, at random and at the edges of its ranges.
namespace arithmetic {

using W = flight::WideQ;

/// m (a + g sin(pitch)) as fx::rescale, fx::mul and fx::add gave it.
std::int64_t along_force_by_fx(std::int32_t mass, std::int32_t gravity, std::int32_t sine, std::int32_t accel) {
  fx::Status st;
  const W sin_w = fx::rescale<W>(fx::Q1_30::from_raw(sine), st);
  const W g_along = fx::mul<W>(flight::AccelQ::from_raw(gravity), sin_w, st);
  const W sum = fx::add(fx::rescale<W>(flight::AccelQ::from_raw(accel), st), g_along, st);
  const W total = fx::mul<W>(flight::MassQ::from_raw(mass), sum, st);
  EXPECT_TRUE(st.ok());
  return total.raw();
}

/// One wheel's pull as fx::mul, fx::clamp and fx::rescale gave it.
flight::detail::WheelPull wheel_pull_by_fx(std::int64_t total, std::uint64_t fraction, std::uint32_t load,
                                           std::uint32_t ratio, bool saturated) {
  fx::Status st;
  const W load_w = fx::rescale<W>(flight::LoadQ::from_raw(static_cast<std::int32_t>(load)), st);
  const W cap = fx::mul<W>(flight::RatioQ::from_raw(static_cast<std::int32_t>(ratio)), load_w, st);
  W dp = cap;
  bool capped = false;
  if (!saturated) {
    const W share = fx::mul(W::from_raw(total), W::from_raw(static_cast<std::int64_t>(fraction)), st);
    dp = fx::clamp(share, fx::neg(cap, st), cap, st);
    capped = dp != share;
  }
  const flight::LoadQ dp_n = fx::rescale<flight::LoadQ>(dp, st);
  return flight::detail::WheelPull{dp_n.raw(), capped, st.ok() ? 0U : 1U};
}

/// A value of magnitude up to 2^bits, log-uniform, or an edge of [0, 2^bits].
std::uint64_t magnitude_up_to(std::mt19937_64& rng, std::uint32_t bits) {
  const std::uint64_t top = std::uint64_t{1U} << bits;
  switch (rng() % 8U) {
    case 0U: return 0U;
    case 1U: return 1U + (rng() % 3U);
    case 2U: return top - (rng() % 3U);
    case 3U: return (top >> 1U) + (rng() % 3U) - 1U;
    default: {
      const std::uint32_t b = 1U + static_cast<std::uint32_t>(rng() % bits);
      return (rng() & ((std::uint64_t{1U} << b) - 1U)) | (std::uint64_t{1U} << (b - 1U));
    }
  }
}

TEST(DrawbarArithmetic, AlongForceIsTheFixedPointChainBitForBit) {
  std::mt19937_64 rng(18U);
  const std::uint64_t max_mass = 1000U << 16U;
  const std::uint64_t max_gravity = 10U << 24U;
  const std::uint64_t max_accel = 10U << 24U;
  for (int trial = 0; trial < 1000000; ++trial) {
    const auto mass = static_cast<std::int32_t>(1U + (magnitude_up_to(rng, 26U) % max_mass));
    const auto gravity = static_cast<std::int32_t>(1U + (magnitude_up_to(rng, 28U) % max_gravity));
    const auto sine_mag = static_cast<std::int32_t>(magnitude_up_to(rng, 30U));
    const std::int32_t sine = ((rng() % 2U) == 0U) ? sine_mag : -sine_mag;
    const auto accel_mag = static_cast<std::int32_t>(magnitude_up_to(rng, 28U) % (max_accel + 1U));
    const std::int32_t accel = ((rng() % 2U) == 0U) ? accel_mag : -accel_mag;
    ASSERT_EQ(flight::detail::along_force_raw(static_cast<std::uint32_t>(mass), static_cast<std::uint32_t>(gravity),
                                              sine, accel),
              along_force_by_fx(mass, gravity, sine, accel))
        << mass << " " << gravity << " " << sine << " " << accel;
  }
}

TEST(DrawbarArithmetic, WheelPullIsTheFixedPointChainBitForBit) {
  std::mt19937_64 rng(18U);
  int capped = 0;
  int overflowed = 0;
  int negative = 0;
  for (int trial = 0; trial < 2000000; ++trial) {
    // Totals of the validated rover are below 2^47 (20 kN); a few up to 2^62
    // take share_magnitude's wide branch.
    const std::uint64_t total_mag = magnitude_up_to(rng, ((trial % 16) == 0) ? 62U : 47U);
    const std::int64_t total =
        ((rng() % 2U) == 0U) ? static_cast<std::int64_t>(total_mag) : -static_cast<std::int64_t>(total_mag);
    const std::uint64_t fraction = magnitude_up_to(rng, 32U);
    const auto load = static_cast<std::uint32_t>(magnitude_up_to(rng, 31U) & 0x7FFFFFFFU);
    const auto ratio = static_cast<std::uint32_t>(1U + (magnitude_up_to(rng, 25U) % (1U << 25U)));
    const bool saturated = (rng() % 4U) == 0U;
    // As drawbar_pulls() forms them: the share's magnitude, or the largest
    // one where saturated, and the total's sign where not.
    const std::uint64_t share =
        flight::detail::share_or_all(fx::detail::magnitude(total), saturated ? 0U : fraction, saturated);
    const flight::detail::WheelPull fast =
        flight::detail::wheel_pull(share, load, ratio, !saturated && (total < 0));
    const flight::detail::WheelPull chain = wheel_pull_by_fx(total, fraction, load, ratio, saturated);
    ASSERT_EQ(fast.overflow != 0U, chain.overflow != 0U) << total << " " << fraction << " " << load << " " << ratio;
    // Saturated, the chain reports no cap; an overflowing pull has no value.
    if (!saturated) {
      ASSERT_EQ(fast.capped, chain.capped) << total << " " << fraction << " " << load << " " << ratio;
    }
    if (fast.overflow == 0U) {
      ASSERT_EQ(fast.dp_raw, chain.dp_raw) << total << " " << fraction << " " << load << " " << ratio;
    }
    capped += (fast.capped && !saturated) ? 1 : 0;
    overflowed += (fast.overflow != 0U) ? 1 : 0;
    negative += ((fast.overflow == 0U) && (fast.dp_raw < 0)) ? 1 : 0;
  }
  // Each branch taken often.
  EXPECT_GT(capped, 100000);
  EXPECT_GT(overflowed, 10000);
  EXPECT_GT(negative, 100000);
}

// wheel_pull's overflow test (round 14: m + 2^31 - 1, or m + 2^31 for a
// positive pull, reaching 2^32, instead of a saturation) at its edges: every
// total whose rounded magnitude is within two of 2^31, at and around the
// rounding's ties, both signs, against the chain's rescale.
TEST(DrawbarArithmetic, WheelPullOverflowsWhereTheRescaleDoes) {
  const std::uint32_t load = 0x7FFFFFFFU;
  const std::uint32_t ratio = 1U << 25U;  // the cap, about 2^48, stays above every share
  int overflowed = 0;
  for (std::uint64_t v = (1ULL << 31U) - 2U; v <= (1ULL << 31U) + 2U; ++v) {
    for (const std::int64_t d : {-32769, -32768, -32767, -1, 0, 1, 32766, 32767, 32768}) {
      const std::uint64_t mag = (v << 16U) + static_cast<std::uint64_t>(d);
      for (const bool negative : {false, true}) {
        const std::int64_t total = negative ? -static_cast<std::int64_t>(mag) : static_cast<std::int64_t>(mag);
        const flight::detail::WheelPull fast = flight::detail::wheel_pull(
            flight::detail::share_or_all(mag, std::uint64_t{1U} << 32U, false), load, ratio, negative);
        const flight::detail::WheelPull chain = wheel_pull_by_fx(total, std::uint64_t{1U} << 32U, load, ratio, false);
        ASSERT_EQ(fast.overflow != 0U, chain.overflow != 0U) << total;
        ASSERT_FALSE(fast.capped) << total;
        if (fast.overflow == 0U) {
          ASSERT_EQ(fast.dp_raw, chain.dp_raw) << total;
        }
        overflowed += (fast.overflow != 0U) ? 1 : 0;
      }
    }
  }
  // Rounded magnitudes of 2^31 - 2 .. 2^31 + 2: the positive pulls overflow
  // from 2^31 on, the negative ones from 2^31 + 1 on.
  EXPECT_GT(overflowed, 40);
  EXPECT_LT(overflowed, 80);
}

// The total's rounding into Q15.16 (round 16: detail::rounded_pull, where
// fx::rescale and its status were): the same value wherever the rescale
// does not overflow and an overflow exactly where it does, on magnitudes of
// every length up to 2^63 - 1, both signs, and every rounded magnitude
// within two of 2^31 at and around the rounding's ties.
TEST(DrawbarArithmetic, RoundedPullIsTheRescale) {
  std::mt19937_64 rng(160U);
  int overflowed = 0;
  const auto check = [&overflowed](std::uint64_t mag, bool negative) {
    const std::int64_t total = negative ? -static_cast<std::int64_t>(mag) : static_cast<std::int64_t>(mag);
    fx::Status st;
    const flight::LoadQ expected = fx::rescale<flight::LoadQ>(W::from_raw(total), st);
    const flight::detail::WheelPull got = flight::detail::rounded_pull(mag, negative);
    ASSERT_EQ(got.overflow != 0U, !st.ok()) << total;
    ASSERT_FALSE(got.capped);
    if (st.ok()) {
      ASSERT_EQ(got.dp_raw, expected.raw()) << total;
    }
    overflowed += st.ok() ? 0 : 1;
  };
  for (int trial = 0; trial < 1000000; ++trial) {
    check(magnitude_up_to(rng, 1U + static_cast<std::uint32_t>(trial % 62)), (trial % 2) == 0);
  }
  for (std::uint64_t v = (1ULL << 31U) - 2U; v <= (1ULL << 31U) + 2U; ++v) {
    for (const std::int64_t d : {-32769, -32768, -32767, -1, 0, 1, 32766, 32767, 32768}) {
      check((v << 16U) + static_cast<std::uint64_t>(d), false);
      check((v << 16U) + static_cast<std::uint64_t>(d), true);
    }
  }
  check(0U, true);
  check((1ULL << 63U) - 1U, false);
  check((1ULL << 63U) - 1U, true);
  EXPECT_GT(overflowed, 50000);
}

TEST(DrawbarArithmetic, LoadFractionIsTheDivisionsRoundedQuotient) {
  std::mt19937_64 rng(18U);
  for (int trial = 0; trial < 1000000; ++trial) {
    // Sums of six loads below 2^31: up to 2^34, beyond 2^32 where the
    // reciprocal's divisor drops low bits.
    std::uint64_t sum = 1U + magnitude_up_to(rng, 1U + static_cast<std::uint32_t>(trial % 34));
    if ((trial % 7) == 3) {
      // Around the largest sum whose remainders fit one word (3 S <= 2^32)
      // and up to 2^32, where the words' form would be wrong.
      const std::uint64_t edge = flight::detail::kWordRemainderSum;
      sum = ((trial % 14) == 3) ? (edge - 3U + (rng() % 7U)) : (edge + (rng() % (0x100000000U - edge)));
    }
    const std::uint64_t load_bound = (sum < 0x80000000U) ? sum : 0x7FFFFFFFU;
    const std::uint64_t pick = magnitude_up_to(rng, 31U);
    const std::uint64_t load = ((trial % 5) == 0) ? load_bound : (pick % (load_bound + 1U));
    fx::Status st;
    const W by_division = fx::div<W>(W::from_raw(static_cast<std::int64_t>(load << 16U)),
                                     W::from_raw(static_cast<std::int64_t>(sum << 16U)), st);
    ASSERT_TRUE(st.ok());
    ASSERT_EQ(flight::detail::load_fraction(static_cast<std::uint32_t>(load), flight::detail::load_sum_of(sum)),
              static_cast<std::uint64_t>(by_division.raw()))
        << load << " / " << sum;
  }
}

// The one-word fraction of a load below the sum (round 17, the step's
// split by word) against load_fraction_by_word, which the test above holds
// to fx::div: sums up to kWordRemainderSum, loads from 0 to S - 1 with the
// ends and the halves, where the rounding and the two steps up decide.
TEST(DrawbarArithmetic, LoadFractionBelowTheSumIsTheWordsForm) {
  std::mt19937_64 rng(17U);
  std::uint64_t rounded_up = 0U;
  for (int trial = 0; trial < 1000000; ++trial) {
    std::uint64_t sum = 2U + (magnitude_up_to(rng, 1U + static_cast<std::uint32_t>(trial % 31)) %
                              (flight::detail::kWordRemainderSum - 1U));
    if ((trial % 9) == 4) {
      sum = flight::detail::kWordRemainderSum - (rng() % 5U);
    }
    const std::uint64_t picks[] = {0U, 1U, sum - 1U, sum - 2U, sum / 2U, (sum / 2U) + 1U, sum / 3U,
                                   rng() % sum, magnitude_up_to(rng, 31U) % sum};
    const flight::detail::LoadSum s = flight::detail::load_sum_of(sum);
    for (const std::uint64_t pick : picks) {
      const std::uint64_t load = pick % sum;  // below the sum
      const auto l = static_cast<std::uint32_t>(load);
      const std::uint64_t expected = flight::detail::load_fraction_by_word(l, s);
      ASSERT_LT(expected, std::uint64_t{1U} << 32U) << load << " / " << sum;
      ASSERT_EQ(flight::detail::load_fraction_below_sum(l, s), expected) << load << " / " << sum;
      // The rounding's up case occurs (a mutated rounding fails).
      rounded_up += ((((std::uint64_t{l} << 32U) % sum) * 2U) >= sum) ? 1U : 0U;
    }
  }
  EXPECT_GT(rounded_up, 1000000U);
}

TEST(DrawbarArithmetic, ProductByHalvesIsTheProduct) {
  std::mt19937_64 rng(18U);
  for (int trial = 0; trial < 1000000; ++trial) {
    const auto a = static_cast<std::uint32_t>(magnitude_up_to(rng, 16U) & 0xFFFFU);
    const auto b = static_cast<std::uint32_t>(magnitude_up_to(rng, 32U) & 0xFFFFFFFFU);
    ASSERT_EQ(flight::detail::mul_16x32_64_by_halves(a, b), std::uint64_t{a} * std::uint64_t{b}) << a << " " << b;
  }
}

TEST(DrawbarArithmetic, WordShiftIsTheShift) {
  std::mt19937_64 rng(18U);
  for (int trial = 0; trial < 100000; ++trial) {
    const std::uint64_t p = rng();
    for (std::uint32_t s = 0U; s < 64U; ++s) {
      ASSERT_EQ(flight::detail::shr_by_words(p, s), p >> s) << p << " >> " << s;
    }
  }
}

/// The pulls as drawbar_pulls() took them past its range checks before
/// round 15: the load sum in one 64-bit loop, each wheel's fraction in the
/// form load_fraction() picks for it, the overflow and the status as then.
flight::DrawbarResult pulls_wheel_by_wheel(const flight::RoverParams& p, const flight::WheelLoadResult& loads,
                                           const flight::DrawbarInput& in, fx::Q1_30 sine) {
  flight::DrawbarResult r{};
  std::uint64_t sum_raw = 0U;
  for (const flight::WheelLoadN w : loads.load_n) sum_raw += static_cast<std::uint32_t>(w.raw());
  if (sum_raw == 0U) {
    r.status = DrawbarStatus::invalid_loads;
    return r;
  }
  fx::Status st;
  const std::int64_t total = flight::detail::along_force_raw(static_cast<std::uint32_t>(p.mass_kg.raw()),
                                                             static_cast<std::uint32_t>(p.gravity_mps2.raw()),
                                                             sine.raw(), in.accel_mps2.raw());
  const flight::DrawbarPullN total_n{fx::rescale<flight::LoadQ>(W::from_raw(total), st)};
  const bool saturated = in.slip_known && (in.slip >= p.high_slip);
  const flight::detail::LoadSum sum = flight::detail::load_sum_of(sum_raw);
  std::uint32_t overflow = 0U;
  std::uint8_t mask = 0U;
  flight::DrawbarPullN dp[6];
  for (std::uint32_t i = 0U; i < 6U; ++i) {
    const auto load = static_cast<std::uint32_t>(loads.load_n[i].raw());
    const std::uint64_t share = flight::detail::share_or_all(
        fx::detail::magnitude(total), saturated ? 0U : flight::detail::load_fraction(load, sum), saturated);
    const flight::detail::WheelPull pull = flight::detail::wheel_pull(
        share, load, static_cast<std::uint32_t>(in.dp_max_ratio[i].raw()), saturated ? false : (total < 0));
    dp[i] = flight::DrawbarPullN::from_raw(pull.dp_raw);
    overflow |= pull.overflow;
    mask = static_cast<std::uint8_t>(mask | (((pull.capped && !saturated) ? 1U : 0U) << i));
  }
  if ((overflow != 0U) || !st.ok()) {
    r.status = DrawbarStatus::overflow;
    return r;
  }
  for (std::uint32_t i = 0U; i < 6U; ++i) r.dp_n[i] = dp[i];
  r.total_n = total_n;
  r.capped_mask = mask;
  r.status = saturated ? DrawbarStatus::saturated : ((mask != 0U) ? DrawbarStatus::capped : DrawbarStatus::ok);
  return r;
}

void expect_same_result(const flight::DrawbarResult& a, const flight::DrawbarResult& b, int trial) {
  ASSERT_EQ(a.status, b.status) << trial;
  for (std::size_t i = 0; i < 6; ++i) ASSERT_EQ(a.dp_n[i].raw(), b.dp_n[i].raw()) << trial << " wheel " << i;
  if (flight::usable(a.status)) {
    ASSERT_EQ(a.total_n.raw(), b.total_n.raw()) << trial;
    ASSERT_EQ(a.capped_mask, b.capped_mask) << trial;
  }
}

// The step's entry past the range checks (detail::pulls_in_range, round 15:
// the load sum in three pairs, the fraction's form picked once per cycle)
// and drawbar_pulls() against the wheel-by-wheel form above, on in-range
// inputs: loads of every size up to 2^31 raw, so that sums on both sides of
// kWordRemainderSum occur, zero loads, one dominant wheel, both signs of the
// total, saturated and not, ratios across (0, 2].
TEST(DrawbarArithmetic, PullsInRangeAreTheWheelByWheelForm) {
  flight::RoverParams p = flight::yutu_like_rover_params(flight::kGravityMoon);
  p.mass_kg = q<flight::MassKg>(1000.0);
  p.gravity_mps2 = q<flight::AccelMps2>(10.0);
  p.attitude_limit_rad = q<flight::AngleRad>(1.0);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  const flight::PreparedParameters& prepared = test::prepared_rover(p);
  std::mt19937_64 rng(151U);
  int wide_sums = 0;
  int word_sums = 0;
  int lone_wheels = 0;
  for (int trial = 0; trial < 30000; ++trial) {
    flight::WheelLoadResult loads{};
    loads.status = flight::WheelLoadStatus::ok;
    const std::uint32_t bits = 1U + static_cast<std::uint32_t>(rng() % 31U);
    for (flight::WheelLoadN& w : loads.load_n) {
      const std::uint64_t raw = ((rng() % 8U) == 0U) ? 0U : (magnitude_up_to(rng, bits) & 0x7FFFFFFFU);
      w = flight::WheelLoadN::from_raw(static_cast<std::int32_t>(raw));
    }
    if ((trial % 4) == 0) {
      loads.load_n[rng() % 6U] = flight::WheelLoadN::from_raw(static_cast<std::int32_t>(0x40000000U + (rng() % 0x40000000U)));
    }
    if ((trial % 10) == 7) {
      // One wheel carries the whole load (its fraction is one): the split
      // by word takes |total| for it (round 17).
      const std::uint64_t lone = rng() % 6U;
      for (std::uint64_t w = 0U; w < 6U; ++w) {
        if (w != lone) loads.load_n[w] = flight::WheelLoadN::zero();
      }
      if (loads.load_n[lone].raw() == 0) loads.load_n[lone] = flight::WheelLoadN::from_raw(1 + static_cast<std::int32_t>(rng() % 0x50000000U));
      lone_wheels += (static_cast<std::uint32_t>(loads.load_n[lone].raw()) <= flight::detail::kWordRemainderSum) ? 1 : 0;
    }
    flight::DrawbarInput in{};
    in.accel_mps2 = flight::AccelMps2::from_raw(static_cast<std::int32_t>(rng() % (2U * 167772160U + 1U)) - 167772160);
    in.pitch_rad = q<flight::AngleRad>((static_cast<double>(rng() % 2001U) / 1000.0) - 1.0);
    in.slip_known = (rng() % 2U) == 0U;
    in.slip = flight::Ratio::from_raw(static_cast<std::int32_t>(rng() % (2U * 16777216U + 1U)) - 16777216);
    for (flight::Ratio& r : in.dp_max_ratio) r = flight::Ratio::from_raw(static_cast<std::int32_t>(1U + (rng() % 0x2000000U)));
    std::uint64_t sum = 0U;
    for (const flight::WheelLoadN w : loads.load_n) sum += static_cast<std::uint32_t>(w.raw());
    (sum > flight::detail::kWordRemainderSum ? wide_sums : word_sums) += 1;
    fx::Status sine_status;
    const fx::Q1_30 sine = fx::sin(in.pitch_rad.q(), sine_status);
    ASSERT_TRUE(sine_status.ok());
    const flight::DrawbarResult expected = pulls_wheel_by_wheel(p, loads, in, sine);
    flight::DrawbarResult direct{};
    direct.status = flight::detail::pulls_in_range(p, loads, in, sine, direct.dp_n, direct.total_n,
                                                   direct.capped_mask);
    expect_same_result(direct, expected, trial);
    expect_same_result(flight::drawbar_pulls(prepared, loads, in), expected, trial);
  }
  EXPECT_GT(wide_sums, 5000);
  EXPECT_GT(word_sums, 5000);
  EXPECT_GT(lone_wheels, 1000);
}

}  // namespace arithmetic

}  // namespace
}  // namespace sinkwatch
