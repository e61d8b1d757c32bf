// The per-cycle functions on prepared parameters against the dividing oracle
// (host_tests/flight/dividing_oracle.hpp): the corrections through the
// prepared segment widths equal the oracle's bit for bit over the shipped
// tables' load range, and the motor model through its prepared reciprocal is
// within oracle::current_tolerance_a of the oracle's three divisions, for the
// shipped and for random motors. (Until session 13 this file also tested
// constant_divisor.hpp, retired when its last per-cycle user, the
// corrections' fraction, moved to a prepared mantissa.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "dividing_oracle.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace sinkwatch {
namespace {

template <typename S>
S random_raw(std::mt19937_64& rng) {
  // A random magnitude at a random bit length, either sign.
  constexpr std::uint32_t bits = (sizeof(S) * 8U) - 1U;
  const std::uint32_t len = static_cast<std::uint32_t>(rng() % (bits + 1U));
  const std::uint64_t mag = (len == 0U) ? 0U : (rng() >> (64U - len));
  const S v = static_cast<S>(mag);
  return ((rng() & 1U) != 0U) ? static_cast<S>(-v) : v;
}

/// The flight current against the oracle's within oracle::current_tolerance_a;
/// where one overflows Q11.20 the other must be within it of the limit.
void expect_current_near_oracle(const flight::CurrentResult& oracle_i, const flight::CurrentResult& flight_i,
                                const flight::MotorParams& m) {
  const double lsb = std::ldexp(1.0, -20);
  const double a = static_cast<double>(oracle_i.current_a.raw()) * lsb;
  const double b = static_cast<double>(flight_i.current_a.raw()) * lsb;
  const double allowed = oracle::current_tolerance_a(m, oracle_i.current_a);
  if (oracle_i.status == flight_i.status) {
    EXPECT_LE(std::fabs(a - b), allowed) << a << " " << b;
    return;
  }
  const double ok_value = (oracle_i.status == flight::EstimateStatus::ok) ? a : b;
  EXPECT_GE(std::fabs(ok_value), 2048.0 - allowed - lsb) << a << " " << b;
}

TEST(PreparedDivisors, CorrectionsEqualAndMotorIsWithinItsBoundOfTheDividingOracle) {
  for (const flight::ParameterTable& table : {flight::default_parameter_table(), flight::eq15_parameter_table()}) {
    const flight::CorrectionDivisors cd = flight::make_correction_divisors(table.correction);
    for (std::int32_t raw = -5; raw < (260 << 16); raw += 997) {
      const flight::WheelLoadN w = flight::WheelLoadN::from_raw(raw);
      const flight::CorrectionResult a = oracle::corrections_at(table.correction, w);
      const flight::CorrectionResult b = flight::corrections_at(table.correction, cd, w);
      ASSERT_EQ(a.status, b.status) << raw;
      ASSERT_EQ(a.clamp, b.clamp) << raw;
      ASSERT_EQ(a.coefficients.c1, b.coefficients.c1) << raw;
      ASSERT_EQ(a.coefficients.c2, b.coefficients.c2) << raw;
      ASSERT_EQ(a.coefficients.c3, b.coefficients.c3) << raw;
      ASSERT_EQ(a.dp_max_ratio, b.dp_max_ratio) << raw;
    }
    const flight::MotorDivisors md = flight::make_motor_divisors(table.motor);
    std::mt19937_64 rng(11U);
    for (int i = 0; i < 200000; ++i) {
      const flight::TorqueNm t = flight::TorqueNm::from_raw(random_raw<std::int32_t>(rng));
      const flight::DriveDirection dir = ((i & 1) != 0) ? flight::DriveDirection::reverse
                                                        : flight::DriveDirection::forward;
      const flight::CurrentResult a = oracle::current_from_torque(table.motor, t, dir);
      const flight::CurrentResult b = flight::current_from_torque(table.motor, md, t, dir);
      expect_current_near_oracle(a, b, table.motor);
    }
    const flight::CorrectionResult c = flight::corrections_at(table.correction, cd, flight::WheelLoadN::from_raw(90 << 16));
    const flight::CurrentLimitResult plain = oracle::current_limit(
        c, table.motor, table.wheel_radius_m, flight::WheelLoadN::from_raw(90 << 16), table.monitor.allowed_sinkage_m);
    const flight::CurrentLimitResult prepared =
        flight::current_limit(c, table.motor, md, table.wheel_radius_m, flight::WheelLoadN::from_raw(90 << 16),
                              table.monitor.allowed_sinkage_m);
    EXPECT_EQ(plain.status, flight::EstimateStatus::ok);
    EXPECT_EQ(prepared.status, flight::EstimateStatus::ok);
    EXPECT_EQ(plain.torque_limit_nm, prepared.torque_limit_nm);
    expect_current_near_oracle({plain.current_limit_a, plain.status}, {prepared.current_limit_a, prepared.status},
                               table.motor);
  }
}

TEST(PreparedDivisors, MotorReciprocalOfOtherMotorsIsWithinItsBoundOfTheDividingOracle) {
  // Random valid motors over the validated ranges (gear, eta, Kt).
  std::mt19937_64 rng(12U);
  flight::MotorParams m = flight::default_parameter_table().motor;
  for (int i = 0; i < 2000; ++i) {
    m.gear_ratio = flight::GearRatio::from_raw(static_cast<std::int32_t>((rng() % (10000U << 16U)) + 1U));
    m.efficiency = flight::Efficiency::from_raw(static_cast<std::int32_t>((rng() % 0x40000000U) + 1U));
    m.kt_nm_per_a = flight::TorqueConstantNmPerA::from_raw(static_cast<std::int32_t>((rng() % 0x7FFFFFFFU) + 1U));
    const flight::MotorDivisors md = flight::make_motor_divisors(m);
    for (int j = 0; j < 100; ++j) {
      const flight::TorqueNm t = flight::TorqueNm::from_raw(random_raw<std::int32_t>(rng));
      const flight::CurrentResult a = oracle::current_from_torque(m, t, flight::DriveDirection::forward);
      const flight::CurrentResult b = flight::current_from_torque(m, md, t, flight::DriveDirection::forward);
      expect_current_near_oracle(a, b, m);
    }
  }
}

}  // namespace
}  // namespace sinkwatch
