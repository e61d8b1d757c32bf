// The motor model and the section 7 current limit.
#include <gtest/gtest.h>

#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
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
  // T_max beyond Q15.16.
  EXPECT_EQ(torque_limit(Coefficients{q<Ratio>(0.25), q<Ratio>(4.0), q<Ratio>(1.0)}, q<Ratio>(2.0), q<LengthM>(2.0),
                         q<WheelLoadN>(30000.0), q<SinkageM>(2.0))
                .status,
            EstimateStatus::overflow);
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
