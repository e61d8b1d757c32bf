// The motor model and the section 7 current limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <random>

#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "sinkwatch/ground/reference.hpp"
#include "quantity_support.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;
namespace ref = sinkwatch::ground::reference;

using sinkwatch::test::d;
using sinkwatch::test::q;

MotorParams motor() {
  // N = 400, eta = 0.6, Kt = 0.025 N m/A: gain 6 N m/A; I0 = 0.1 A; sensor 10 A.
  return default_parameter_table().motor;
}

TEST(Motor, ForwardSubtractsTheNoLoadCurrent) {
  const TorqueResult t = torque_from_current(motor(), q<CurrentA>(2.1), DriveDirection::forward);
  ASSERT_EQ(t.status, EstimateStatus::ok);
  EXPECT_NEAR(d(t.torque_nm), 6.0 * 2.0, 1e-4);
}

TEST(Motor, ReverseAddsTheNoLoadCurrentSoTheTorqueIsMirrored) {
  const TorqueResult t = torque_from_current(motor(), q<CurrentA>(-2.1), DriveDirection::reverse);
  ASSERT_EQ(t.status, EstimateStatus::ok);
  EXPECT_NEAR(d(t.torque_nm), -12.0, 1e-4);
  const TorqueResult f = torque_from_current(motor(), q<CurrentA>(2.1), DriveDirection::forward);
  EXPECT_EQ(t.torque_nm.raw(), -f.torque_nm.raw());  // exact mirror: rounding is symmetric
}

TEST(Motor, BelowTheNoLoadCurrentTheTorqueOpposesTheMotion) {
  const TorqueResult t = torque_from_current(motor(), q<CurrentA>(0.05), DriveDirection::forward);
  ASSERT_EQ(t.status, EstimateStatus::ok);
  EXPECT_NEAR(d(t.torque_nm), 6.0 * -0.05, 1e-5);
}

TEST(Motor, CurrentAtTheSensorLimitIsValidBeyondItIsNot) {
  EXPECT_EQ(torque_from_current(motor(), q<CurrentA>(10.0), DriveDirection::forward).status, EstimateStatus::ok);
  EXPECT_EQ(torque_from_current(motor(), q<CurrentA>(-10.0), DriveDirection::reverse).status, EstimateStatus::ok);
  const TorqueResult t = torque_from_current(motor(), CurrentA::from_raw(q<CurrentA>(10.0).raw() + 1),
                                             DriveDirection::forward);
  EXPECT_EQ(t.status, EstimateStatus::invalid_current);
  EXPECT_EQ(t.torque_nm, TorqueNm::zero());
  EXPECT_EQ(torque_from_current(motor(), q<CurrentA>(-10.5), DriveDirection::forward).status,
            EstimateStatus::invalid_current);
  EXPECT_EQ(torque_from_current(motor(), CurrentA::from_raw(INT32_MIN), DriveDirection::forward).status,
            EstimateStatus::invalid_current);
}

TEST(Motor, InvalidMotorAndDirectionHaveTheirStatus) {
  MotorParams m = motor();
  m.efficiency = Efficiency::zero();
  EXPECT_EQ(make_motor_divisors(m).inverse_gain.mantissa, 0U);  // no reciprocal of a zero gain
  EXPECT_EQ(torque_from_current(m, q<CurrentA>(1.0), DriveDirection::forward).status, EstimateStatus::invalid_motor);
  EXPECT_EQ(test::current_of(m, q<TorqueNm>(1.0), DriveDirection::forward).status, EstimateStatus::invalid_motor);
  m = motor();
  m.gear_ratio = q<GearRatio>(-1.0);
  EXPECT_EQ(check_motor(m), EstimateStatus::invalid_motor);
  m = motor();
  m.kt_nm_per_a = TorqueConstantNmPerA::zero();
  EXPECT_EQ(check_motor(m), EstimateStatus::invalid_motor);
  m = motor();
  m.efficiency = q<Efficiency>(1.5);
  EXPECT_EQ(check_motor(m), EstimateStatus::invalid_motor);
  m = motor();
  m.no_load_current_a = q<CurrentA>(-0.1);
  EXPECT_EQ(check_motor(m), EstimateStatus::invalid_motor);
  m = motor();
  m.current_abs_max_a = m.no_load_current_a;
  EXPECT_EQ(check_motor(m), EstimateStatus::invalid_motor);
  const auto bad = static_cast<DriveDirection>(7);
  EXPECT_EQ(torque_from_current(motor(), q<CurrentA>(1.0), bad).status, EstimateStatus::invalid_direction);
  EXPECT_EQ(test::current_of(motor(), q<TorqueNm>(1.0), bad).status, EstimateStatus::invalid_direction);
}

TEST(Motor, OverflowIsAStatus) {
  MotorParams m = motor();
  m.gear_ratio = q<GearRatio>(10000.0);
  m.kt_nm_per_a = q<TorqueConstantNmPerA>(4.0);
  m.efficiency = q<Efficiency>(1.0);
  m.current_abs_max_a = q<CurrentA>(1000.0);
  // 10000 * 4 * 1000 N m: beyond Q15.16.
  EXPECT_EQ(torque_from_current(m, q<CurrentA>(1000.0), DriveDirection::forward).status, EstimateStatus::overflow);
  MotorParams weak = motor();
  weak.gear_ratio = q<GearRatio>(1.0);
  weak.kt_nm_per_a = q<TorqueConstantNmPerA>(0.0001);
  weak.efficiency = q<Efficiency>(0.01);
  // 30000 N m / 1e-6 N m/A: beyond Q11.20.
  EXPECT_EQ(test::current_of(weak, q<TorqueNm>(30000.0), DriveDirection::forward).status,
            EstimateStatus::overflow);
}

/// torque_from_current as the checked fx::mul chain it was until session 18:
/// Kt I into Q31.32, eta x into Q31.32, N x into Q15.16, each rounded ties
/// away from zero, overflow from any step.
TorqueResult torque_by_checked_chain(const MotorParams& m, CurrentA current_a, DriveDirection direction) {
  const EstimateStatus motor_status = check_motor(m);
  if (motor_status != EstimateStatus::ok) {
    return TorqueResult{TorqueNm::zero(), motor_status};
  }
  if ((direction != DriveDirection::forward) && (direction != DriveDirection::reverse)) {
    return TorqueResult{TorqueNm::zero(), EstimateStatus::invalid_direction};
  }
  fx::Status st;
  const CurrentQ magnitude = fx::abs(current_a.q(), st);
  if ((!st.ok()) || (magnitude > m.current_abs_max_a.q())) {
    return TorqueResult{TorqueNm::zero(), EstimateStatus::invalid_current};
  }
  const CurrentQ effective = (direction == DriveDirection::forward)
                                 ? fx::sub(current_a.q(), m.no_load_current_a.q(), st)
                                 : fx::add(current_a.q(), m.no_load_current_a.q(), st);
  const WideQ motor_torque = fx::mul<WideQ>(m.kt_nm_per_a.q(), effective, st);
  const WideQ after_gear_loss = fx::mul<WideQ>(m.efficiency.q(), motor_torque, st);
  const LoadQ wheel_torque = fx::mul<LoadQ>(m.gear_ratio.q(), after_gear_loss, st);
  if (!st.ok()) {
    return TorqueResult{TorqueNm::zero(), EstimateStatus::overflow};
  }
  return TorqueResult{TorqueNm(wheel_torque), EstimateStatus::ok};
}

/// A raw value of `bits` significant bits (1 to 31), at least 1.
std::int32_t random_raw(std::mt19937_64& rng, std::uint32_t bits) {
  return static_cast<std::int32_t>((rng() >> (64U - bits)) | (std::uint64_t{1U} << (bits - 1U)));
}

// A motor check_motor() accepts, of every magnitude: gear, Kt and the
// sensor range of 1 to 31 bits, eta in (0, 1] (1 for every seventh k), I0
// below the range (0 for every fifth k). The draws in a fixed order, so a
// seed gives the same motors.
MotorParams random_valid_motor(std::mt19937_64& rng, int k) {
  MotorParams m{};
  m.gear_ratio = GearRatio::from_raw(random_raw(rng, 1U + static_cast<std::uint32_t>(rng() % 31U)));
  m.efficiency = Efficiency::from_raw(
      ((k % 7) == 0) ? 0x40000000 : std::max(1, static_cast<std::int32_t>(rng() % 0x40000000U)));
  m.kt_nm_per_a = TorqueConstantNmPerA::from_raw(random_raw(rng, 1U + static_cast<std::uint32_t>(rng() % 31U)));
  m.current_abs_max_a = CurrentA::from_raw(std::max(1, random_raw(rng, 1U + static_cast<std::uint32_t>(rng() % 31U))));
  const std::int32_t range = m.current_abs_max_a.raw();
  m.no_load_current_a =
      CurrentA::from_raw(((k % 5) == 0) ? 0 : static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(range)));
  return m;
}

// The magnitude chain of torque_from_current (motor.cpp, session 18) against
// the checked chain it replaced, bit for bit and status for status: random
// motors of every magnitude (gear, Kt and the sensor range of 1 to 31 bits,
// eta in (0, 1], I0 below the range, including 0), currents across the
// whole range and at its ends, both directions; the driving current's
// product above 2^32 raw and the torque beyond Q15.16 included.
TEST(Motor, MagnitudeChainGivesTheCheckedChainsBits) {
  std::mt19937_64 rng(20261127U);  // NOLINT(cert-msc32-c,cert-msc51-cpp): reproducible samples
  std::uint32_t overflows = 0U;
  std::uint32_t torques = 0U;
  for (int k = 0; k < 20000; ++k) {
    const MotorParams m = random_valid_motor(rng, k);
    const std::int32_t range = m.current_abs_max_a.raw();
    ASSERT_EQ(check_motor(m), EstimateStatus::ok);
    const std::int32_t ends[] = {range, -range, 0, 1, -1, range - 1, -(range - 1)};
    for (int j = 0; j < 27; ++j) {
      // A draw in [0, 2 range] less the range, on 64 bits (2 range exceeds int32_t).
      const std::int64_t offset = static_cast<std::int64_t>(rng() % ((2U * static_cast<std::uint64_t>(range)) + 1U));
      const std::int32_t raw = (j < 7) ? ends[j] : static_cast<std::int32_t>(offset - range);
      for (const DriveDirection dir : {DriveDirection::forward, DriveDirection::reverse}) {
        const CurrentA i = CurrentA::from_raw(raw);
        const TorqueResult expected = torque_by_checked_chain(m, i, dir);
        const TorqueResult got = torque_from_current(m, i, dir);
        ASSERT_EQ(got.status, expected.status) << raw;
        ASSERT_EQ(got.torque_nm.raw(), expected.torque_nm.raw()) << raw;
        overflows += (expected.status == EstimateStatus::overflow) ? 1U : 0U;
        torques += (expected.status == EstimateStatus::ok) ? 1U : 0U;
      }
    }
  }
  EXPECT_GT(overflows, 10000U);  // both outcomes well represented
  EXPECT_GT(torques, 100000U);
}

// The six wheels' torques in one call (detail::torques_of_valid_motor, the
// per-cycle step's form, round 14): each wheel's result is the checked
// chain's for its own current and direction, whatever the other wheels'
// are (an invalid direction, a current beyond the range, an overflow among
// them), and every field of every result is written.
TEST(Motor, SixWheelsInOneCallAreEachWheelsCheckedChain) {
  std::mt19937_64 rng(20261128U);  // NOLINT(cert-msc32-c,cert-msc51-cpp): reproducible samples
  std::uint32_t outcomes[8] = {};
  for (int k = 0; k < 20000; ++k) {
    const MotorParams m = random_valid_motor(rng, k);
    const std::int32_t range = m.current_abs_max_a.raw();
    CurrentA currents[limits::kWheelCount]{};
    DriveDirection directions[limits::kWheelCount]{};
    TorqueResult torques[limits::kWheelCount]{};
    for (std::uint32_t w = 0U; w < limits::kWheelCount; ++w) {
      // A draw in [0, 2 range + 2] less the range + 1: one raw ampere beyond either end included.
      const std::int64_t offset = static_cast<std::int64_t>(rng() % ((2U * static_cast<std::uint64_t>(range)) + 3U));
      currents[w] = CurrentA::from_raw(static_cast<std::int32_t>(std::max<std::int64_t>(offset - range - 1, INT32_MIN)));
      const std::uint64_t d = rng() % 16U;
      directions[w] = (d == 0U) ? static_cast<DriveDirection>(2U) : ((d < 8U) ? DriveDirection::forward : DriveDirection::reverse);
      // A stale result in the output: every field must be overwritten.
      torques[w] = TorqueResult{TorqueNm::from_raw(0x5A5A5A5A), EstimateStatus::invalid_motor};
    }
    detail::torques_of_valid_motor(m, currents, directions, torques);
    for (std::uint32_t w = 0U; w < limits::kWheelCount; ++w) {
      const TorqueResult expected = torque_by_checked_chain(m, currents[w], directions[w]);
      ASSERT_EQ(torques[w].status, expected.status) << k << " " << w;
      ASSERT_EQ(torques[w].torque_nm.raw(), expected.torque_nm.raw()) << k << " " << w;
      ++outcomes[static_cast<std::uint32_t>(expected.status) % 8U];
    }
  }
  EXPECT_GT(outcomes[static_cast<std::uint32_t>(EstimateStatus::ok)], 10000U);
  EXPECT_GT(outcomes[static_cast<std::uint32_t>(EstimateStatus::overflow) % 8U], 1000U);
  EXPECT_GT(outcomes[static_cast<std::uint32_t>(EstimateStatus::invalid_direction) % 8U], 1000U);
  EXPECT_GT(outcomes[static_cast<std::uint32_t>(EstimateStatus::invalid_current) % 8U], 100U);
}

// I -+ I0 at the ends of Q11.20 (round 14; the random motors above reach
// them only by chance): driving forward I = INT32_MIN + I0 is the lowest
// current whose I - I0 fits, in reverse I = INT32_MAX - I0 the highest whose
// I + I0 does; one raw ampere further is overflow, as in the checked chain.
// A gain of a few raw units keeps the torque itself far inside Q15.16.
TEST(Motor, EffectiveCurrentAtTheFormatsEndsOverflowsAsTheCheckedChain) {
  MotorParams m{};
  m.gear_ratio = GearRatio::from_raw(1);
  m.efficiency = Efficiency::from_raw(1 << 30);
  m.kt_nm_per_a = TorqueConstantNmPerA::from_raw(1 << 12);
  m.current_abs_max_a = CurrentA::from_raw(INT32_MAX);
  std::uint32_t overflows = 0U;
  for (const std::int32_t i0 : {0, 1, 2, 1000, 1 << 30, INT32_MAX - 1}) {
    m.no_load_current_a = CurrentA::from_raw(i0);
    ASSERT_EQ(check_motor(m), EstimateStatus::ok);
    const std::int64_t low = std::int64_t{INT32_MIN} + i0;
    const std::int64_t high = std::int64_t{INT32_MAX} - i0;
    for (const std::int64_t raw : {low - 1, low, low + 1, high - 1, high, high + 1}) {
      if ((raw < -std::int64_t{INT32_MAX}) || (raw > INT32_MAX)) {
        continue;  // beyond the sensor's range: invalid_current, tested above
      }
      const CurrentA i = CurrentA::from_raw(static_cast<std::int32_t>(raw));
      for (const DriveDirection dir : {DriveDirection::forward, DriveDirection::reverse}) {
        const TorqueResult expected = torque_by_checked_chain(m, i, dir);
        const TorqueResult got = torque_from_current(m, i, dir);
        ASSERT_EQ(got.status, expected.status) << raw << " " << i0;
        ASSERT_EQ(got.torque_nm.raw(), expected.torque_nm.raw()) << raw << " " << i0;
        overflows += (expected.status == EstimateStatus::overflow) ? 1U : 0U;
      }
    }
  }
  EXPECT_GE(overflows, 8U);  // the step beyond each bound, for the non-zero I0
}

// The torque's own limits: with N = 32, eta = 1 and Kt = 1 N m/A the torque
// is twice the current's raw value, so 2^30 raw amperes give +2^31 raw
// newton-metres (beyond Q15.16: overflow) and -2^30 give the format's
// minimum, -2^31 (no overflow); one raw ampere less is the largest torque.
TEST(Motor, TorqueAtTheFormatsEndsSaturatesOnlyBeyondIt) {
  MotorParams m{};
  m.gear_ratio = GearRatio::from_raw(1 << 21);
  m.efficiency = Efficiency::from_raw(1 << 30);
  m.kt_nm_per_a = TorqueConstantNmPerA::from_raw(1 << 28);
  m.no_load_current_a = CurrentA::zero();
  m.current_abs_max_a = CurrentA::from_raw(INT32_MAX);
  const TorqueResult beyond = torque_from_current(m, CurrentA::from_raw(1 << 30), DriveDirection::forward);
  EXPECT_EQ(beyond.status, EstimateStatus::overflow);
  EXPECT_EQ(beyond.torque_nm, TorqueNm::zero());
  const TorqueResult lowest = torque_from_current(m, CurrentA::from_raw(-(1 << 30)), DriveDirection::forward);
  ASSERT_EQ(lowest.status, EstimateStatus::ok);
  EXPECT_EQ(lowest.torque_nm.raw(), INT32_MIN);
  const TorqueResult highest = torque_from_current(m, CurrentA::from_raw((1 << 30) - 1), DriveDirection::forward);
  ASSERT_EQ(highest.status, EstimateStatus::ok);
  EXPECT_EQ(highest.torque_nm.raw(), INT32_MAX - 1);
  for (const std::int32_t raw : {1 << 30, -(1 << 30), (1 << 30) - 1}) {
    const TorqueResult expected = torque_by_checked_chain(m, CurrentA::from_raw(raw), DriveDirection::forward);
    const TorqueResult got = torque_from_current(m, CurrentA::from_raw(raw), DriveDirection::forward);
    EXPECT_EQ(got.status, expected.status);
    EXPECT_EQ(got.torque_nm, expected.torque_nm);
  }
}

// A table validate() accepts whose motor is drawn across validate_motor's
// ranges (gear 1..10000, eta 0.01..1, Kt 0.0001..4, I0 0..100 A, the sensor
// range up to 1000 A); every third one with the range set so that the
// torque at -(range) is within a few raw units of Q15.16's end, where
// validate_envelope()'s test decides. False when validate() refuses it.
bool random_validated_table(std::mt19937_64& rng, int k, ParameterTable& t) {
  t = default_parameter_table();
  MotorParams& m = t.motor;
  m.gear_ratio = GearRatio::from_raw(random_raw(rng, 17U + static_cast<std::uint32_t>(rng() % 14U)));
  m.efficiency = Efficiency::from_raw(((k % 7) == 0) ? 0x40000000
                                                     : (10737419 + static_cast<std::int32_t>(rng() % 1063004405U)));
  m.kt_nm_per_a = TorqueConstantNmPerA::from_raw(random_raw(rng, 15U + static_cast<std::uint32_t>(rng() % 17U)));
  m.no_load_current_a = CurrentA::from_raw(((k % 5) == 0) ? 0 : static_cast<std::int32_t>(rng() % (100U << 20U)));
  std::int64_t range = random_raw(rng, 1U + static_cast<std::uint32_t>(rng() % 30U));
  if ((k % 3) == 0) {
    const double gain = d(m.gear_ratio) * d(m.efficiency) * d(m.kt_nm_per_a);
    range = static_cast<std::int64_t>((32768.0 / gain) * 1048576.0) - m.no_load_current_a.raw() +
            static_cast<std::int64_t>(rng() % 9U) - 4;
  }
  m.current_abs_max_a = CurrentA::from_raw(static_cast<std::int32_t>(std::clamp<std::int64_t>(range, 1, INT32_MAX)));
  return validate(t) == RejectReason::ok;
}

// The per-cycle step's six torques (detail::torques_of_validated_motor)
// against the checked six-wheel form (detail::torques_of_valid_motor, its
// oracle) over validate()'s whole envelope: random validated motors, the
// currents at and one raw unit beyond the range's ends, at +-I0 and the
// format's ends and random across the range, both directions and an
// invalid one: the same bits and statuses, every field written.
TEST(Motor, ValidatedSixWheelsGiveTheCheckedFormsBitsOverTheEnvelope) {
  std::mt19937_64 rng(20261129U);  // NOLINT(cert-msc32-c,cert-msc51-cpp): reproducible samples
  std::uint32_t tables = 0U;
  std::uint32_t edge_tables = 0U;
  std::uint32_t outcomes[8] = {};
  for (int k = 0; k < 100000; ++k) {
    ParameterTable t{};
    if (!random_validated_table(rng, k, t)) {
      continue;
    }
    ++tables;
    edge_tables += ((k % 3) == 0) ? 1U : 0U;
    const MotorParams& m = t.motor;
    const std::int32_t range = m.current_abs_max_a.raw();
    const std::int32_t i0 = m.no_load_current_a.raw();
    const std::int32_t ends[] = {range, -range, range + 1, -range - 1, 0, 1, -1, i0, -i0, i0 + 1, -i0 - 1,
                                 INT32_MIN, INT32_MAX, range - 1, -range + 1};
    for (int j = 0; j < 8; ++j) {
      CurrentA currents[limits::kWheelCount]{};
      DriveDirection directions[limits::kWheelCount]{};
      TorqueResult expected[limits::kWheelCount]{};
      TorqueResult got[limits::kWheelCount]{};
      for (std::uint32_t w = 0U; w < limits::kWheelCount; ++w) {
        const std::uint32_t n = (static_cast<std::uint32_t>(j) * limits::kWheelCount) + w;
        const std::int64_t offset = static_cast<std::int64_t>(rng() % ((2U * static_cast<std::uint64_t>(range)) + 3U));
        currents[w] = CurrentA::from_raw((n < 15U) ? ends[n] : static_cast<std::int32_t>(offset - range - 1));
        const std::uint32_t dir = static_cast<std::uint32_t>(rng() % 9U);
        directions[w] = (dir == 0U) ? static_cast<DriveDirection>(2U)
                                    : ((dir < 5U) ? DriveDirection::forward : DriveDirection::reverse);
        got[w] = TorqueResult{TorqueNm::from_raw(0x5A5A5A5A), EstimateStatus::invalid_motor};
      }
      bool current_usable[limits::kWheelCount]{};
      DriveTorques drive{};
      for (std::uint32_t w = 0U; w < limits::kWheelCount; ++w) {
        current_usable[w] = (rng() % 4U) != 0U;
        drive.torque_nm[w] = TorqueNm::from_raw(0x5A5A5A5A);
        drive.usable[w] = !current_usable[w];
      }
      detail::torques_of_valid_motor(m, currents, directions, expected);
      detail::torques_of_validated_motor(m, currents, directions, current_usable, got, drive);
      for (std::uint32_t w = 0U; w < limits::kWheelCount; ++w) {
        ASSERT_EQ(got[w].status, expected[w].status) << k << " " << j << " " << w;
        ASSERT_EQ(got[w].torque_nm.raw(), expected[w].torque_nm.raw()) << k << " " << j << " " << w;
        // The loads' torque: the torque where the current is usable and
        // the torque ok, else zero and not usable.
        const bool expect_usable = current_usable[w] && (expected[w].status == EstimateStatus::ok);
        ASSERT_EQ(drive.usable[w], expect_usable) << k << " " << j << " " << w;
        ASSERT_EQ(drive.torque_nm[w].raw(), expect_usable ? expected[w].torque_nm.raw() : 0) << k << " " << j << " " << w;
        ++outcomes[static_cast<std::uint32_t>(expected[w].status) % 8U];
      }
    }
  }
  EXPECT_GT(tables, 8000U);
  EXPECT_GT(edge_tables, 2000U);
  EXPECT_GT(outcomes[static_cast<std::uint32_t>(EstimateStatus::ok)], 200000U);
  EXPECT_GT(outcomes[static_cast<std::uint32_t>(EstimateStatus::invalid_direction) % 8U], 30000U);
  EXPECT_GT(outcomes[static_cast<std::uint32_t>(EstimateStatus::invalid_current) % 8U], 25000U);
}

// The one refusal of the validated form's range test that a validated
// motor can meet (motor.cpp): validate_envelope() tests the torque at
// -(range) driving forward, |I - I0| = range + I0, which may be -2^31 raw;
// in reverse at +(range) the same magnitude is +2^31, beyond Q15.16. Here
// N eta Kt = 64 N m/A and range + I0 = 512 A: exactly 32768 N m.
TEST(Motor, ValidatedFormStillRefusesThePositiveEndOfQ15_16) {
  ParameterTable t = default_parameter_table();
  t.motor.gear_ratio = q<GearRatio>(32.0);
  t.motor.efficiency = Efficiency::from_raw(0x40000000);
  t.motor.kt_nm_per_a = q<TorqueConstantNmPerA>(2.0);
  t.motor.no_load_current_a = q<CurrentA>(1.0);
  t.motor.current_abs_max_a = q<CurrentA>(511.0);
  ASSERT_EQ(validate(t), RejectReason::ok);
  const CurrentA currents[limits::kWheelCount] = {q<CurrentA>(511.0), q<CurrentA>(-511.0), q<CurrentA>(511.0),
                                                   q<CurrentA>(-511.0), q<CurrentA>(511.0), q<CurrentA>(0.0)};
  const DriveDirection directions[limits::kWheelCount] = {DriveDirection::reverse, DriveDirection::forward,
                                                          DriveDirection::forward, DriveDirection::reverse,
                                                          DriveDirection::reverse, DriveDirection::reverse};
  TorqueResult got[limits::kWheelCount]{};
  const bool current_usable[limits::kWheelCount] = {true, true, true, true, false, true};
  DriveTorques drive{};
  detail::torques_of_validated_motor(t.motor, currents, directions, current_usable, got, drive);
  // Usable: an ok torque of a usable current (wheel 4's current is not).
  const bool expect_usable[limits::kWheelCount] = {false, true, true, true, false, true};
  for (std::uint32_t w = 0U; w < limits::kWheelCount; ++w) {
    EXPECT_EQ(drive.usable[w], expect_usable[w]) << w;
    EXPECT_EQ(drive.torque_nm[w].raw(), expect_usable[w] ? got[w].torque_nm.raw() : 0) << w;
  }
  EXPECT_EQ(got[0].status, EstimateStatus::overflow);
  EXPECT_EQ(got[0].torque_nm, TorqueNm::zero());
  EXPECT_EQ(got[1].status, EstimateStatus::ok);
  EXPECT_EQ(got[1].torque_nm.raw(), INT32_MIN);
  EXPECT_EQ(got[2].status, EstimateStatus::ok);
  EXPECT_EQ(got[2].torque_nm, q<TorqueNm>(32640.0));
  EXPECT_EQ(got[3].status, EstimateStatus::ok);
  EXPECT_EQ(got[3].torque_nm, q<TorqueNm>(-32640.0));
  EXPECT_EQ(got[4].status, EstimateStatus::overflow);
  EXPECT_EQ(got[5].status, EstimateStatus::ok);
  EXPECT_EQ(got[5].torque_nm, q<TorqueNm>(64.0));
}

TEST(Motor, CurrentFromTorqueInvertsTorqueFromCurrent) {
  for (double i : {-9.0, -2.5, -0.3, 0.3, 2.5, 9.0}) {
    for (DriveDirection dir : {DriveDirection::forward, DriveDirection::reverse}) {
      const TorqueResult t = torque_from_current(motor(), q<CurrentA>(i), dir);
      ASSERT_EQ(t.status, EstimateStatus::ok);
      const CurrentResult back = test::current_of(motor(), t.torque_nm, dir);
      ASSERT_EQ(back.status, EstimateStatus::ok);
      // T is rounded to 2^-17 N m; divided by the 6 N m/A gain: < 2e-6 A.
      EXPECT_NEAR(d(back.current_a), i, 2e-6);
    }
  }
}

TEST(CurrentLimit, HandComputedAt10kg) {
  // W = 98.1 N (a Table 2 load: C = 1, 1, 0.13), DP_max/W = 0.5, r = 0.15 m,
  // z_max = 0.045 m: T_max = 98.1 (0.15 (0.5 + 0.13) + 0.045) = 13.68495 N m,
  // I_max = 13.68495 / 6 + 0.1 = 2.380825 A.
  const ParameterTable t = default_parameter_table();
  const CurrentLimitResult l =
      test::current_limit_of(t.correction, t.motor, t.wheel_radius_m, q<WheelLoadN>(98.1), q<SinkageM>(0.045));
  ASSERT_EQ(l.status, EstimateStatus::ok);
  EXPECT_EQ(l.clamp, LoadClamp::none);
  EXPECT_NEAR(d(l.torque_limit_nm), 13.68495, 2e-5);
  EXPECT_NEAR(d(l.current_limit_a), 2.380825, 5e-6);
}

TEST(CurrentLimit, RisesWithTheLoad) {
  const ParameterTable t = default_parameter_table();
  double previous = 0.0;
  for (double w = 20.0; w <= 300.0; w += 10.0) {
    const CurrentLimitResult l =
        test::current_limit_of(t.correction, t.motor, t.wheel_radius_m, q<WheelLoadN>(w), t.monitor.allowed_sinkage_m);
    ASSERT_EQ(l.status, EstimateStatus::ok);
    EXPECT_GT(d(l.current_limit_a), previous) << w;
    previous = d(l.current_limit_a);
  }
}

TEST(CurrentLimit, ReportsTheClampAndInvalidInputs) {
  const ParameterTable t = default_parameter_table();
  EXPECT_EQ(test::current_limit_of(t.correction, t.motor, t.wheel_radius_m, q<WheelLoadN>(5.0), t.monitor.allowed_sinkage_m).clamp,
            LoadClamp::below_first);
  EXPECT_EQ(test::current_limit_of(t.correction, t.motor, t.wheel_radius_m, q<WheelLoadN>(500.0), t.monitor.allowed_sinkage_m).clamp,
            LoadClamp::above_last);
  EXPECT_EQ(test::current_limit_of(t.correction, t.motor, t.wheel_radius_m, WheelLoadN::zero(), t.monitor.allowed_sinkage_m).status,
            EstimateStatus::invalid_load);
  EXPECT_EQ(test::current_limit_of(t.correction, t.motor, LengthM::zero(), q<WheelLoadN>(50.0), t.monitor.allowed_sinkage_m).status,
            EstimateStatus::invalid_radius);
  MotorParams m = t.motor;
  m.kt_nm_per_a = TorqueConstantNmPerA::zero();
  EXPECT_EQ(test::current_limit_of(t.correction, m, t.wheel_radius_m, q<WheelLoadN>(50.0), t.monitor.allowed_sinkage_m).status,
            EstimateStatus::invalid_motor);
  // torque_limit() checks its own inputs (current_limit() checks them before it).
  EXPECT_EQ(torque_limit(Coefficients{q<Ratio>(1.0), q<Ratio>(1.0), q<Ratio>(0.13)}, q<Ratio>(0.5), LengthM::zero(),
                         q<WheelLoadN>(50.0), q<SinkageM>(0.02))
                .status,
            EstimateStatus::invalid_radius);
  // T_max beyond Q15.16.
  EXPECT_EQ(torque_limit(Coefficients{q<Ratio>(0.25), q<Ratio>(4.0), q<Ratio>(1.0)}, q<Ratio>(2.0), q<LengthM>(2.0),
                         q<WheelLoadN>(30000.0), q<SinkageM>(2.0))
                .status,
            EstimateStatus::overflow);
  // The limit reports that overflow before a refused motor (T_max is formed
  // first, as current_from_torque() would form the current), and a refused
  // motor before anything else once T_max fits.
  const CorrectionResult steep{Coefficients{q<Ratio>(0.25), q<Ratio>(4.0), q<Ratio>(1.0)}, q<Ratio>(2.0),
                               LoadClamp::above_last, EstimateStatus::ok};
  const MotorDivisors divisors = make_motor_divisors(t.motor);
  const CurrentLimitResult beyond = current_limit(steep, m, divisors, q<LengthM>(2.0), q<WheelLoadN>(30000.0), q<SinkageM>(2.0));
  EXPECT_EQ(beyond.status, EstimateStatus::overflow);
  EXPECT_EQ(beyond.clamp, LoadClamp::above_last);
  EXPECT_EQ(current_limit(steep, t.motor, divisors, q<LengthM>(2.0), q<WheelLoadN>(30000.0), q<SinkageM>(2.0)).status,
            EstimateStatus::overflow);
  EXPECT_EQ(current_limit(steep, m, divisors, q<LengthM>(0.15), q<WheelLoadN>(50.0), q<SinkageM>(0.02)).status,
            EstimateStatus::invalid_motor);
}

TEST(CurrentLimit, AgreesWithTheReferenceTwin) {
  const ParameterTable t = default_parameter_table();
  const ref::Parameters p = ref::from_flight(t);
  for (double w = 5.0; w <= 400.0; w += 7.3) {
    const CurrentLimitResult l =
        test::current_limit_of(t.correction, t.motor, t.wheel_radius_m, q<WheelLoadN>(w), t.monitor.allowed_sinkage_m);
    ASSERT_EQ(l.status, EstimateStatus::ok);
    const double expected = ref::current_limit_a(p.correction, p.motor, p.wheel_radius_m,
                                                 d(q<WheelLoadN>(w)), p.allowed_sinkage_m);
    EXPECT_NEAR(d(l.current_limit_a), expected, 4e-6) << w;
  }
}

}  // namespace
