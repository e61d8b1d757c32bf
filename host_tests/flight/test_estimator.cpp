// Eq. 11 (both ways), the correction table and the paper's published tables.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/fixedpoint/normalised_quotient.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/reference.hpp"
#include "of_valid.hpp"
#include "prepared_support.hpp"
#include "quantity_support.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;

using sinkwatch::test::d;
using sinkwatch::test::q;

Coefficients coeffs(double c1, double c2, double c3) { return Coefficients{q<Ratio>(c1), q<Ratio>(c2), q<Ratio>(c3)}; }

struct Table1Row {
  double slip, z_over_r, drive, traction, paper_fit;
};

std::vector<Table1Row> read_table1() {
  std::ifstream in(std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv");
  EXPECT_TRUE(in.good());
  std::vector<Table1Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("slip", 0) == 0) {
      continue;
    }
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    Table1Row r{};
    ss >> r.slip >> r.z_over_r >> r.drive >> r.traction >> r.paper_fit;
    rows.push_back(r);
  }
  return rows;
}

// Dimensional inputs for the dimensionless table: the soil-bin wheel at 3 kg.
// r = 0.15 m is an assumption (the Yutu wheel's radius is not given in the
// paper); the check is dimensionless, so r and W only set the quantisation.
constexpr double kR = 0.15;
constexpr double kW = 3.0 * 9.81;
// 0.001: the table's own rounding (its last column is T/(rW) - z/r of
// rounded columns, off by exactly 0.001 on rows 3, 4, 13, 16). 3e-6: the
// quantisation of T, z and DP in Q15.16 / Q7.24 at this r and W plus the
// function's rounding (docs/flight.md, "Table 1 check").
constexpr double kTable1Tolerance = 0.001 + 3e-6;

TEST(Table1, Eq10ReproducesTheLastColumnOnAll16Rows) {
  const auto rows = read_table1();
  ASSERT_EQ(rows.size(), 16U);
  const Coefficients eq10 = coeffs(1.0, 1.0, 0.0);
  for (const auto& r : rows) {
    const DrawbarPullResult dp = pull_from_sinkage(eq10, q<LengthM>(kR), q<WheelLoadN>(kW),
                                                   q<TorqueNm>(r.drive * kR * kW), q<SinkageM>(r.z_over_r * kR));
    ASSERT_EQ(dp.status, EstimateStatus::ok);
    EXPECT_NEAR(d(dp.drawbar_pull_n) / kW, r.paper_fit, kTable1Tolerance) << "slip " << r.slip;
  }
}

TEST(Table1, Eq10InvertedGivesTheSinkageColumnBack) {
  const auto rows = read_table1();
  const Coefficients eq10 = coeffs(1.0, 1.0, 0.0);
  for (const auto& r : rows) {
    const SinkageResult z = sinkage_from_pull(eq10, q<LengthM>(kR), q<WheelLoadN>(kW), q<TorqueNm>(r.drive * kR * kW),
                                              q<DrawbarPullN>(r.paper_fit * kW));
    ASSERT_EQ(z.status, EstimateStatus::ok);
    EXPECT_NEAR(d(z.sinkage_m) / kR, r.z_over_r, kTable1Tolerance) << "slip " << r.slip;
  }
}

TEST(Table1, Eq14AndEq15AreTheEq10ValuesShiftedByTheirC3) {
  const auto rows = read_table1();
  for (double c3 : {0.2, 0.13}) {
    const Coefficients c = coeffs(1.0, 1.0, c3);
    for (const auto& r : rows) {
      const DrawbarPullResult dp = pull_from_sinkage(c, q<LengthM>(kR), q<WheelLoadN>(kW),
                                                     q<TorqueNm>(r.drive * kR * kW), q<SinkageM>(r.z_over_r * kR));
      ASSERT_EQ(dp.status, EstimateStatus::ok);
      EXPECT_NEAR(d(dp.drawbar_pull_n) / kW, r.paper_fit - c3, kTable1Tolerance) << "C3 " << c3 << " slip " << r.slip;
    }
  }
}

// Finding F-2 (docs/derivation.md): least squares on Table 1 (Eq. 12-13) does not
// give Eq. 14's C = (1, 1, 0.2). This test records the numbers, so a change
// in the data file or the arithmetic shows up.
TEST(Table1, LeastSquaresDoesNotGiveEq14Finding) {
  const auto rows = read_table1();
  double ata[3][3] = {};
  double atb[3] = {};
  for (const auto& r : rows) {
    const double a[3] = {r.drive, -r.z_over_r, -1.0};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) ata[i][j] += a[i] * a[j];
      atb[i] += a[i] * r.traction;
    }
  }
  // Cramer's rule on the 3x3 normal equations.
  auto det3 = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double det = det3(ata);
  double c[3];
  for (int k = 0; k < 3; ++k) {
    double m[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = (j == k) ? atb[i] : ata[i][j];
    c[k] = det3(m) / det;
  }
  EXPECT_NEAR(c[0], 0.844, 0.001);
  EXPECT_NEAR(c[1], -0.079, 0.001);
  EXPECT_NEAR(c[2], 0.204, 0.001);
  // With C1 = C2 = 1 held, the best C3 is the mean residual: 0.174, not 0.2.
  double sum = 0.0;
  for (const auto& r : rows) sum += r.drive - r.z_over_r - r.traction;
  EXPECT_NEAR(sum / static_cast<double>(rows.size()), 0.174, 0.001);
}

TEST(Table2, DefaultTableGivesThePublishedC3AtEachLoad) {
  std::ifstream in(std::string(SINKWATCH_DATA_DIR) + "/paper/table2_corrections.csv");
  ASSERT_TRUE(in.good());
  const ParameterTable table = default_parameter_table();
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("load", 0) == 0) continue;
    double kg = 0.0, c3 = 0.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf", &kg, &c3), 2);
    const CorrectionResult c = test::corrections_of(table.correction, q<WheelLoadN>(kg * 9.81));
    ASSERT_EQ(c.status, EstimateStatus::ok);
    EXPECT_EQ(c.clamp, LoadClamp::none);
    EXPECT_NEAR(d(c.coefficients.c1), 1.0, 1e-7);
    EXPECT_NEAR(d(c.coefficients.c2), 1.0, 1e-7);
    EXPECT_NEAR(d(c.coefficients.c3), c3, 1e-7) << kg << " kg";
    ++n;
  }
  EXPECT_EQ(n, 5);
}

TEST(Table2, BetweenLoadsTheCorrectionIsInterpolated) {
  const ParameterTable table = default_parameter_table();
  // Halfway between 3 kg (0.20) and 7 kg (0.15): 0.175.
  const CorrectionResult c = test::corrections_of(table.correction, q<WheelLoadN>(5.0 * 9.81));
  ASSERT_EQ(c.status, EstimateStatus::ok);
  EXPECT_NEAR(d(c.coefficients.c3), 0.175, 1e-6);
  EXPECT_EQ(c.clamp, LoadClamp::none);
}

TEST(Table2, LoadsBeyondTheBreakpointsAreHeldAndReported) {
  const ParameterTable table = default_parameter_table();
  const CorrectionResult below = test::corrections_of(table.correction, q<WheelLoadN>(10.0));
  EXPECT_EQ(below.status, EstimateStatus::ok);
  EXPECT_EQ(below.clamp, LoadClamp::below_first);
  EXPECT_NEAR(d(below.coefficients.c3), 0.20, 1e-7);
  const CorrectionResult above = test::corrections_of(table.correction, q<WheelLoadN>(500.0));
  EXPECT_EQ(above.clamp, LoadClamp::above_last);
  EXPECT_NEAR(d(above.coefficients.c3), 0.13, 1e-7);
  const CorrectionResult zero = test::corrections_of(table.correction, WheelLoadN::zero());
  EXPECT_EQ(zero.status, EstimateStatus::invalid_load);
  CorrectionTable empty = table.correction;
  empty.count = 0U;
  EXPECT_EQ(test::corrections_of(empty, q<WheelLoadN>(50.0)).status, EstimateStatus::invalid_coefficient);
  // An unvalidated, non-increasing table still never divides by zero: a
  // segment [a, b) with a >= b holds no load, and every load between the
  // first and the last breakpoint lies in some segment.
  CorrectionTable unsorted = table.correction;
  unsorted.rows[2].load_n = unsorted.rows[1].load_n;
  for (double w : {30.0, 68.67, 80.0, 150.0}) {
    EXPECT_EQ(test::corrections_of(unsorted, q<WheelLoadN>(w)).status, EstimateStatus::ok) << w;
  }
}

TEST(Table2, Eq15TableIsConstant013) {
  const ParameterTable t = eq15_parameter_table();
  for (double w : {10.0, 29.43, 60.0, 196.2, 400.0}) {
    EXPECT_NEAR(d(test::corrections_of(t.correction, q<WheelLoadN>(w)).coefficients.c3), 0.13, 1e-7);
  }
}

TEST(Estimator, HandComputedExample) {
  // r = 0.15 m, W = 100 N, T = 10 N m, DP = 30 N, Eq. 15:
  // z = (10/100 - 0.15 (0.13 + 0.3)) / 1 = 0.1 - 0.0645 = 0.0355 m.
  const SinkageResult z = sinkage_from_pull(coeffs(1, 1, 0.13), q<LengthM>(0.15), q<WheelLoadN>(100.0),
                                            q<TorqueNm>(10.0), q<DrawbarPullN>(30.0));
  ASSERT_EQ(z.status, EstimateStatus::ok);
  EXPECT_NEAR(d(z.sinkage_m), 0.0355, 1e-6);
  const DrawbarPullResult dp = pull_from_sinkage(coeffs(1, 1, 0.13), q<LengthM>(0.15), q<WheelLoadN>(100.0),
                                                 q<TorqueNm>(10.0), q<SinkageM>(0.0355));
  ASSERT_EQ(dp.status, EstimateStatus::ok);
  EXPECT_NEAR(d(dp.drawbar_pull_n), 30.0, 1e-4);
}

TEST(Estimator, EveryInvalidInputHasItsStatus) {
  const Coefficients ok = coeffs(1, 1, 0.13);
  const auto z = [](const Coefficients& c, double r, double w) {
    return sinkage_from_pull(c, q<LengthM>(r), q<WheelLoadN>(w), q<TorqueNm>(1.0), q<DrawbarPullN>(1.0)).status;
  };
  const auto p = [](const Coefficients& c, double r, double w) {
    return pull_from_sinkage(c, q<LengthM>(r), q<WheelLoadN>(w), q<TorqueNm>(1.0), q<SinkageM>(0.01)).status;
  };
  for (auto f : {+z, +p}) {
    EXPECT_EQ(f(ok, 0.15, 30.0), EstimateStatus::ok);
    EXPECT_EQ(f(ok, 0.0, 30.0), EstimateStatus::invalid_radius);
    EXPECT_EQ(f(ok, -0.15, 30.0), EstimateStatus::invalid_radius);
    EXPECT_EQ(f(ok, 2.5, 30.0), EstimateStatus::invalid_radius);
    EXPECT_EQ(f(ok, 0.15, 0.0), EstimateStatus::invalid_load);
    EXPECT_EQ(f(ok, 0.15, -5.0), EstimateStatus::invalid_load);
    EXPECT_EQ(f(coeffs(1, 0, 0.13), 0.15, 30.0), EstimateStatus::invalid_coefficient);  // C2 = 0
    EXPECT_EQ(f(coeffs(1, -1, 0.13), 0.15, 30.0), EstimateStatus::invalid_coefficient);
    EXPECT_EQ(f(coeffs(0.1, 1, 0.13), 0.15, 30.0), EstimateStatus::invalid_coefficient);
    EXPECT_EQ(f(coeffs(5, 1, 0.13), 0.15, 30.0), EstimateStatus::invalid_coefficient);
    EXPECT_EQ(f(coeffs(1, 1, 1.5), 0.15, 30.0), EstimateStatus::invalid_coefficient);
    EXPECT_EQ(f(coeffs(1, 1, -1.5), 0.15, 30.0), EstimateStatus::invalid_coefficient);
  }
}

TEST(Estimator, OverflowIsAStatusNotANumber) {
  // T/W = 30000 / 2^-16 N: beyond Q31.32.
  const SinkageResult z = sinkage_from_pull(coeffs(4, 0.25, 0), q<LengthM>(2.0), WheelLoadN::from_raw(1),
                                            q<TorqueNm>(30000.0), q<DrawbarPullN>(0.0));
  EXPECT_EQ(z.status, EstimateStatus::overflow);
  EXPECT_EQ(z.sinkage_m, SinkageM::zero());
  // z = 4 * 30000 / 1 / 0.25 m: beyond Q7.24's 128 m.
  const SinkageResult z2 = sinkage_from_pull(coeffs(4, 0.25, 0), q<LengthM>(0.15), q<WheelLoadN>(1.0),
                                             q<TorqueNm>(30000.0), q<DrawbarPullN>(0.0));
  EXPECT_EQ(z2.status, EstimateStatus::overflow);
  // DP = 4 * 30000 / 0.01 N: beyond Q15.16.
  const DrawbarPullResult dp = pull_from_sinkage(coeffs(4, 1, 0), q<LengthM>(0.01), q<WheelLoadN>(30.0),
                                                 q<TorqueNm>(30000.0), q<SinkageM>(0.0));
  EXPECT_EQ(dp.status, EstimateStatus::overflow);
  EXPECT_EQ(dp.drawbar_pull_n, DrawbarPullN::zero());
}

/// Inputs check_estimator_inputs() accepts, drawn over their whole ranges
/// (C1, C2 in [1/4, 4], C3 in [-1, 1], r in [0.01, 2] m, W of every length),
/// and signed 32-bit values of every length for T, DP, DP_max/W and z_max.
struct Operands {
  Coefficients c;
  LengthM r;
  WheelLoadN w;
  std::int32_t t, dp, ratio, z;
};

std::int32_t any_raw(std::mt19937_64& rng) {
  switch (rng() % 8U) {
    case 0U:
      return INT32_MIN;
    case 1U:
      return INT32_MAX;
    case 2U:
      return 0;
    default: {
      const auto v = static_cast<std::int32_t>(rng() >> (32U + (rng() % 32U)));
      return ((rng() & 1U) != 0U) ? -v : v;
    }
  }
}

std::int32_t raw_in(std::mt19937_64& rng, Ratio lo, Ratio hi) {
  const auto span = static_cast<std::uint64_t>(static_cast<std::int64_t>(hi.raw()) - lo.raw()) + 1U;
  return static_cast<std::int32_t>(lo.raw() + static_cast<std::int64_t>(rng() % span));
}

Operands random_operands(std::mt19937_64& rng) {
  Operands o{};
  o.c = Coefficients{Ratio::from_raw(raw_in(rng, kMinC12, kMaxC12)), Ratio::from_raw(raw_in(rng, kMinC12, kMaxC12)),
                     Ratio::from_raw(raw_in(rng, kMinC3, kMaxC3))};
  o.r = LengthM::from_raw(raw_in(rng, Ratio::from_raw(kMinRadiusM.raw()), Ratio::from_raw(kMaxRadiusM.raw())));
  o.w = WheelLoadN::from_raw(std::max(1, static_cast<std::int32_t>(rng() >> (33U + (rng() % 31U)))));
  o.t = any_raw(rng);
  o.dp = any_raw(rng);
  o.ratio = any_raw(rng);
  o.z = any_raw(rng);
  return o;
}

/// Eq. 11's sinkage as the session 17 code formed it: the four signed
/// products of fx::wide::mul_32x32_64 (both magnitudes taken), r C3 rounded
/// by fx::detail::product_rounded, its product with W by wide_product_rounded.
SinkageResult sinkage_by_signed_products(const Operands& o) {
  const std::int64_t drive = fx::wide::mul_32x32_64(o.c.c1.raw(), o.t);
  const std::int64_t pull = fx::wide::mul_32x32_64(o.r.raw(), o.dp);
  const std::int32_t r_c3 = fx::detail::product_rounded<(2 * LengthQ::frac_bits) - 29>(o.r.raw(), o.c.c3.raw());
  const std::int64_t offset = fx::detail::wide_product_rounded<(29 + LoadQ::frac_bits) - 40>(r_c3, o.w.raw());
  using Moment = fx::Q<std::int64_t, 40>;
  fx::Status st;
  const LengthQ z = fx::divide_normalised<LengthQ>(Moment::from_raw((drive - pull) - offset),
                                                   Moment::from_raw(fx::wide::mul_32x32_64(o.c.c2.raw(), o.w.raw())), st);
  return st.ok() ? SinkageResult{SinkageM(z), EstimateStatus::ok} : SinkageResult{SinkageM::zero(), EstimateStatus::overflow};
}

/// The section 7 torque limit as the session 17 code formed it: the lever
/// from three signed products, its leading word times W, divided by C1.
TorqueLimitResult torque_limit_by_signed_products(const Operands& o) {
  const std::int64_t lever = (fx::wide::mul_32x32_64(o.r.raw(), o.ratio) + fx::wide::mul_32x32_64(o.r.raw(), o.c.c3.raw())) +
                             fx::wide::mul_32x32_64(o.c.c2.raw(), o.z);
  const std::uint64_t magnitude = fx::detail::magnitude(lever);
  const std::uint32_t bits = fx::wide::bit_length(magnitude);
  const std::uint64_t product =
      fx::wide::mul_32x32_64(fx::wide::leading_word(magnitude, bits), static_cast<std::uint32_t>(o.w.raw()));
  const fx::ScaledMagnitude n{lever < 0, product, ((16 + 48) + 32) - static_cast<std::int32_t>(bits)};
  fx::Status st;
  const LoadQ t = fx::divide_normalised<LoadQ>(n, fx::to_scaled(o.c.c1.q()), st);
  return st.ok() ? TorqueLimitResult{TorqueNm(t), EstimateStatus::ok}
                 : TorqueLimitResult{TorqueNm::zero(), EstimateStatus::overflow};
}

// Eq. 11 and the torque limit take the positive factors (r, W, C1, C2) as
// they are and only the others' magnitudes, and the limit's lever r times
// the sum of the two ratios (session 18): bit for bit, status for status,
// the signed products they replaced, over the whole accepted range with the
// signed operands at every length and at their extremes.
TEST(Estimator, SinkageAndTorqueLimitGiveTheSignedProductsBits) {
  std::mt19937_64 rng(20261128U);  // NOLINT(cert-msc32-c,cert-msc51-cpp): reproducible samples
  std::uint32_t sinkages = 0U;
  std::uint32_t limits = 0U;
  for (int k = 0; k < 500000; ++k) {
    const Operands o = random_operands(rng);
    ASSERT_EQ(check_estimator_inputs(o.c, o.r, o.w), EstimateStatus::ok);
    const SinkageResult z = sinkage_from_pull(o.c, o.r, o.w, TorqueNm::from_raw(o.t), DrawbarPullN::from_raw(o.dp));
    const SinkageResult z_expected = sinkage_by_signed_products(o);
    ASSERT_EQ(z.status, z_expected.status) << k;
    ASSERT_EQ(z.sinkage_m.raw(), z_expected.sinkage_m.raw()) << k;
    const TorqueLimitResult t = torque_limit(o.c, Ratio::from_raw(o.ratio), o.r, o.w, SinkageM::from_raw(o.z));
    const TorqueLimitResult t_expected = torque_limit_by_signed_products(o);
    ASSERT_EQ(t.status, t_expected.status) << k;
    ASSERT_EQ(t.torque_nm.raw(), t_expected.torque_nm.raw()) << k;
    sinkages += (z.status == EstimateStatus::ok) ? 1U : 0U;
    limits += (t.status == EstimateStatus::ok) ? 1U : 0U;
  }
  EXPECT_GT(sinkages, 100000U);  // both outcomes of each well represented
  EXPECT_LT(sinkages, 490000U);
  EXPECT_GT(limits, 100000U);
  EXPECT_LT(limits, 490000U);
}

// limit_from_torque (of_valid.hpp) against the fx::times_reciprocal form it
// replaced: the same current and the same refusals for every T_max, reciprocal
// (none, and scales on both sides of every branch) and no-load current.
CurrentLimitResult limit_by_times_reciprocal(const MotorParams& motor, const MotorDivisors& divisors, TorqueNm t_max) {
  using WideCurrentQ = fx::Q<std::int64_t, CurrentQ::frac_bits>;
  fx::Status st;
  const WideCurrentQ driving = fx::times_reciprocal<WideCurrentQ>(t_max.q(), divisors.inverse_gain, st);
  // A refused quotient is refused whatever the sum: tested first, so that a
  // saturated quotient (INT64_MAX) is never added to I0 (the form replaced
  // summed first; the sanitizer build found the overflow at the shifts <= 0
  // this test reaches, which a validated motor's reciprocal does not).
  if (!st.ok()) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), LoadClamp::none, EstimateStatus::overflow};
  }
  const std::int64_t total = driving.raw() + static_cast<std::int64_t>(motor.no_load_current_a.raw());
  if ((total < std::numeric_limits<std::int32_t>::min()) || (total > std::numeric_limits<std::int32_t>::max())) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), LoadClamp::none, EstimateStatus::overflow};
  }
  return CurrentLimitResult{CurrentA(CurrentQ::from_raw(static_cast<std::int32_t>(total))), t_max, LoadClamp::none,
                            EstimateStatus::ok};
}

TEST(LimitFromTorque, MatchesTimesReciprocalOverRandomAndEdgeOperands) {
  std::mt19937_64 rng(1415U);
  const std::int32_t edges[] = {0, 1, -1, 2, -2, std::numeric_limits<std::int32_t>::max(),
                                std::numeric_limits<std::int32_t>::min(), 1 << 16, -(1 << 16)};
  const CorrectionResult corr{};
  for (std::int32_t i = 0; i < 400000; ++i) {
    MotorParams motor{};
    MotorDivisors divisors{};
    const auto pick = static_cast<std::uint32_t>(rng() % 16U);
    auto t_raw = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()));
    if (pick < 4U) {
      t_raw = edges[rng() % (sizeof(edges) / sizeof(edges[0]))];
    } else if (pick < 8U) {
      t_raw >>= (rng() % 32U);
    }
    divisors.inverse_gain.mantissa = ((rng() % 50U) == 0U) ? 0U : static_cast<std::uint32_t>(rng() | 0x80000000ULL);
    divisors.inverse_gain.scale = static_cast<std::int32_t>(rng() % 90U) - 12;  // shift -16 .. 73
    auto i0 = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()));
    if ((rng() % 4U) != 0U) {
      i0 >>= (rng() % 32U);
    }
    motor.no_load_current_a = CurrentA(CurrentQ::from_raw(i0));
    const TorqueLimitResult t{TorqueNm(LoadQ::from_raw(t_raw)), EstimateStatus::ok};
    const CurrentLimitResult got = detail::limit_from_torque(corr, motor, divisors, t);
    const CurrentLimitResult want = limit_by_times_reciprocal(motor, divisors, t.torque_nm);
    ASSERT_EQ(got.status, want.status) << t_raw << " " << divisors.inverse_gain.mantissa << " "
                                       << divisors.inverse_gain.scale << " " << i0;
    ASSERT_EQ(got.current_limit_a.raw(), want.current_limit_a.raw())
        << t_raw << " " << divisors.inverse_gain.mantissa << " " << divisors.inverse_gain.scale << " " << i0;
    ASSERT_EQ(got.torque_limit_nm.raw(), want.torque_limit_nm.raw());
  }
}

// current_raw_from_validated_torque (of_valid.hpp, estimate_from's) leaves
// out current_raw_from_torque's refusals of a reciprocal without a mantissa
// and of a shift <= 0 (and its test of a shift >= 64). A motor within
// validate()'s ranges (param_table.cpp) meets none of them: the gain N eta Kt
// rises with each factor, so its reciprocal's shift is at its ends at the
// corners of the ranges.
TEST(LimitFromTorque, ValidatedMotorsShiftIsWithinItsRange) {
  constexpr GearRatio kGears[] = {GearRatio(fx::constant<GearQ>(1.0)), GearRatio(fx::constant<GearQ>(10000.0))};
  constexpr Efficiency kEfficiencies[] = {Efficiency(fx::constant<EfficiencyQ>(0.01)),
                                          Efficiency(fx::constant<EfficiencyQ>(1.0))};
  constexpr TorqueConstantNmPerA kKts[] = {TorqueConstantNmPerA(fx::constant<KtQ>(0.0001)),
                                           TorqueConstantNmPerA(fx::constant<KtQ>(4.0))};
  for (const GearRatio gear : kGears) {
    for (const Efficiency efficiency : kEfficiencies) {
      for (const TorqueConstantNmPerA kt : kKts) {
        MotorParams m{};
        m.gear_ratio = gear;
        m.efficiency = efficiency;
        m.kt_nm_per_a = kt;
        const MotorDivisors md = make_motor_divisors(m);
        EXPECT_NE(md.inverse_gain.mantissa, 0U) << gear.raw() << " " << efficiency.raw() << " " << kt.raw();
        const std::int32_t shift = (LoadQ::frac_bits + md.inverse_gain.scale) - CurrentQ::frac_bits;
        EXPECT_GE(shift, 8) << gear.raw() << " " << efficiency.raw() << " " << kt.raw();
        EXPECT_LE(shift, 43) << gear.raw() << " " << efficiency.raw() << " " << kt.raw();
      }
    }
  }
}

/// Whether the validated form gives the checked form's status and current
/// for one torque (current_raw_from_validated_torque against
/// current_raw_from_torque); counts the checked form's verdict in `kept` or
/// `refused`.
::testing::AssertionResult validated_is_checked(const MotorParams& motor, const MotorDivisors& divisors,
                                                std::int32_t t_raw, std::uint32_t& kept, std::uint32_t& refused) {
  std::int32_t want = 1;
  std::int32_t got = 2;
  const bool want_ok = detail::current_raw_from_torque(motor, divisors, t_raw, want);
  const bool got_ok = detail::current_raw_from_validated_torque(motor, divisors, t_raw, got);
  ++(want_ok ? kept : refused);
  if ((got_ok == want_ok) && (got == want)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "T raw " << t_raw << ", mantissa " << divisors.inverse_gain.mantissa
                                       << ", scale " << divisors.inverse_gain.scale << ": validated " << got_ok
                                       << " " << got << ", checked " << want_ok << " " << want;
}

// Where the shift lies in [1, 63] and the reciprocal has a mantissa (every
// validated motor's, above), the validated form is current_raw_from_torque
// bit for bit: the same current and the same refusal of a sum beyond Q11.20.
TEST(LimitFromTorque, ValidatedFormIsTheCheckedFormWithinItsShifts) {
  std::mt19937_64 rng(1416U);
  const std::int32_t edges[] = {0, 1, -1, 2, -2, std::numeric_limits<std::int32_t>::max(),
                                std::numeric_limits<std::int32_t>::min(), 1 << 16, -(1 << 16)};
  std::uint32_t refused = 0U;
  std::uint32_t kept = 0U;
  for (std::int32_t i = 0; i < 400000; ++i) {
    MotorParams motor{};
    MotorDivisors divisors{};
    auto t_raw = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()));
    const auto pick = static_cast<std::uint32_t>(rng() % 16U);
    if (pick < 4U) {
      t_raw = edges[rng() % (sizeof(edges) / sizeof(edges[0]))];
    } else if (pick < 12U) {
      t_raw >>= (rng() % 32U);
    }
    divisors.inverse_gain.mantissa = static_cast<std::uint32_t>(rng() | 0x80000000ULL);
    divisors.inverse_gain.scale = static_cast<std::int32_t>(rng() % 63U) + 5;  // shift 1 .. 63
    divisors = motor_divisors_of(divisors.inverse_gain);
    auto i0 = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()));
    if ((rng() % 4U) != 0U) {
      i0 >>= (rng() % 32U);
    }
    motor.no_load_current_a = CurrentA(CurrentQ::from_raw(i0));
    ASSERT_TRUE(validated_is_checked(motor, divisors, t_raw, kept, refused)) << "I0 raw " << i0;
  }
  EXPECT_GT(kept, 50000U);
  EXPECT_GT(refused, 50000U);
}

// shifted_by_prepared_words (of_valid.hpp, round 17): the product plus the
// prepared 2^(s-1), shifted on 32-bit words by the prepared counts, is
// shift_right_rounded's integer (and the word form's) for every shift in
// [1, 63], every mantissa and every torque magnitude up to 2^31, the ends
// included. A shift outside [1, 63] prepares nothing.
TEST(LimitFromTorque, PreparedWordsShiftIsTheRoundedShift) {
  std::mt19937_64 rng(1717U);
  const std::uint32_t t_edges[] = {0U, 1U, 2U, 0x7FFFFFFFU, 0x80000000U, 0xFFFFU, 0x10000U};
  const std::uint32_t m_edges[] = {0U, 1U, 0x80000000U, 0xFFFFFFFFU, 0x80000001U};
  for (std::int32_t s = 1; s <= 63; ++s) {
    const MotorDivisors md = motor_divisors_of(fx::NormalisedReciprocal{1U, s + CurrentQ::frac_bits - LoadQ::frac_bits});
    for (std::int32_t i = 0; i < 20000; ++i) {
      auto t = static_cast<std::uint32_t>(rng() >> (33U + (rng() % 31U)));  // below 2^31
      auto m = static_cast<std::uint32_t>(rng());
      if ((i % 7) == 0) {
        t = t_edges[rng() % (sizeof(t_edges) / sizeof(t_edges[0]))];
      }
      if ((i % 5) == 0) {
        m = m_edges[rng() % (sizeof(m_edges) / sizeof(m_edges[0]))];
      }
      MotorDivisors with_m = md;
      with_m.inverse_gain.mantissa = m;
      const std::uint64_t product = fx::wide::mul_32x32_64(t, m);
      const std::uint64_t want = fx::detail::shift_right_rounded(product, static_cast<std::uint32_t>(s));
      ASSERT_EQ(detail::shifted_by_prepared_words(with_m, t), want) << s << " " << t << " " << m;
      ASSERT_EQ(fx::detail::shift_right_rounded_by_words(product, static_cast<std::uint32_t>(s)), want);
    }
  }
  for (const std::int32_t s : {-3, 0, 64, 70}) {
    const MotorDivisors md =
        motor_divisors_of(fx::NormalisedReciprocal{0x80000000U, s + CurrentQ::frac_bits - LoadQ::frac_bits});
    EXPECT_EQ(md.current_rounding_raw, 0U) << s;
    EXPECT_EQ(md.current_low_shift + md.current_clear_shift + md.current_join_shift + md.current_high_shift, 0U)
        << s;
    EXPECT_EQ(md.inverse_gain.mantissa, 0x80000000U);
  }
}

// Over random motors that check_motor() accepts (N, eta and Kt anywhere in
// their ranges, param_table.cpp) the prepared divisors' validated current is
// current_raw_from_torque's, bit for bit, refusals included.
TEST(LimitFromTorque, ValidatedFormIsTheCheckedFormOverRandomMotors) {
  std::mt19937_64 rng(1718U);
  const std::int32_t gear_lo = fx::constant<GearQ>(1.0).raw();
  const std::int32_t gear_hi = fx::constant<GearQ>(10000.0).raw();
  const std::int32_t eff_lo = fx::constant<EfficiencyQ>(0.01).raw();
  const std::int32_t eff_hi = fx::constant<EfficiencyQ>(1.0).raw();
  const std::int32_t kt_lo = fx::constant<KtQ>(0.0001).raw();
  const std::int32_t kt_hi = fx::constant<KtQ>(4.0).raw();
  const auto between = [&rng](std::int32_t lo, std::int32_t hi) {
    const auto span = static_cast<std::uint64_t>(static_cast<std::int64_t>(hi) - static_cast<std::int64_t>(lo)) + 1U;
    const std::uint64_t pick = ((rng() % 4U) == 0U) ? ((rng() % 2U) * (span - 1U)) : (rng() % span);
    return static_cast<std::int32_t>(static_cast<std::int64_t>(lo) + static_cast<std::int64_t>(pick));
  };
  std::uint32_t refused = 0U;
  std::uint32_t kept = 0U;
  for (std::int32_t k = 0; k < 2000; ++k) {
    MotorParams motor{};
    motor.gear_ratio = GearRatio(GearQ::from_raw(between(gear_lo, gear_hi)));
    motor.efficiency = Efficiency(EfficiencyQ::from_raw(between(eff_lo, eff_hi)));
    motor.kt_nm_per_a = TorqueConstantNmPerA(KtQ::from_raw(between(kt_lo, kt_hi)));
    const MotorDivisors md = make_motor_divisors(motor);
    const std::int32_t shift = (LoadQ::frac_bits + md.inverse_gain.scale) - CurrentQ::frac_bits;
    ASSERT_GE(shift, 8);
    ASSERT_LE(shift, 43);
    for (std::int32_t i = 0; i < 200; ++i) {
      auto t_raw = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()));
      t_raw >>= (rng() % 32U);
      if ((i % 50) == 0) {
        t_raw = ((i % 100) == 0) ? std::numeric_limits<std::int32_t>::min() : std::numeric_limits<std::int32_t>::max();
      }
      auto i0 = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()));
      i0 >>= (rng() % 32U);
      motor.no_load_current_a = CurrentA(CurrentQ::from_raw(i0));
      ASSERT_TRUE(validated_is_checked(motor, md, t_raw, kept, refused)) << "I0 raw " << i0;
    }
  }
  EXPECT_GT(kept, 50000U);
  EXPECT_GT(refused, 10000U);
}

// times_positive (of_valid.hpp): the signed product where the core has one
// and the magnitudes' product with the sign put back on ARMv6-M, both the
// exact product of any 32-bit a and a positive b, at the ends of both ranges
// and at random values of every length.
TEST(TimesPositive, IsTheExactProductInBothForms) {
  std::mt19937_64 rng(1515U);
  const std::int32_t a_edges[] = {std::numeric_limits<std::int32_t>::min(),
                                  std::numeric_limits<std::int32_t>::min() + 1, -2, -1, 0, 1, 2,
                                  std::numeric_limits<std::int32_t>::max() - 1,
                                  std::numeric_limits<std::int32_t>::max()};
  const std::int32_t b_edges[] = {1, 2, 1 << 22, 1 << 26, std::numeric_limits<std::int32_t>::max() - 1,
                                  std::numeric_limits<std::int32_t>::max()};
  for (std::int32_t i = 0; i < 400000; ++i) {
    auto a = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()));
    a >>= (rng() % 32U);
    auto b = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()) >> (1U + (rng() % 31U)));
    b = (b == 0) ? 1 : b;
    if ((i % 3) == 0) {
      a = a_edges[rng() % (sizeof(a_edges) / sizeof(a_edges[0]))];
    }
    if ((i % 5) == 0) {
      b = b_edges[rng() % (sizeof(b_edges) / sizeof(b_edges[0]))];
    }
    const std::int64_t exact = static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b);
    ASSERT_EQ(detail::times_positive(a, b), exact) << a << " " << b;
    const std::int64_t by_magnitudes = detail::with_sign(
        a < 0, fx::wide::mul_32x32_64_halves(fx::detail::magnitude32(a), static_cast<std::uint32_t>(b)));
    ASSERT_EQ(by_magnitudes, exact) << a << " " << b;
  }
}

// product_of_non_negative (of_valid.hpp, Eq. 11's C2 W): the signed product
// where the core has one and the unsigned 16-bit products on ARMv6-M, both
// the exact product of two non-negative 32-bit values, the largest included.
TEST(ProductOfNonNegative, IsTheExactProductInBothForms) {
  std::mt19937_64 rng(1516U);
  const std::int32_t edges[] = {0, 1, 2, 1 << 22, 1 << 26, std::numeric_limits<std::int32_t>::max() - 1,
                                std::numeric_limits<std::int32_t>::max()};
  for (std::int32_t i = 0; i < 400000; ++i) {
    auto a = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()) >> (1U + (rng() % 31U)));
    auto b = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()) >> (1U + (rng() % 31U)));
    if ((i % 3) == 0) {
      a = edges[rng() % (sizeof(edges) / sizeof(edges[0]))];
    }
    if ((i % 5) == 0) {
      b = edges[rng() % (sizeof(edges) / sizeof(edges[0]))];
    }
    const std::uint64_t exact = static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b);
    ASSERT_EQ(detail::product_of_non_negative(a, b), exact) << a << " " << b;
    ASSERT_EQ(fx::wide::mul_32x32_64_halves(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)), exact)
        << a << " " << b;
  }
}

// r (DP_max/W + C3) (of_valid.hpp: radius_times_ratios, the core's own
// form, and radius_times_ratios_by_magnitude, ARMv6-M's, |sum| from the
// wrapping 32-bit sum) against the exact signed product, the sums at and
// beyond the ends of the 32-bit range included.
TEST(RadiusTimesRatios, IsTheExactSignedProduct) {
  std::mt19937_64 rng(2611U);
  const std::int32_t ratio_edges[] = {std::numeric_limits<std::int32_t>::min(),
                                      std::numeric_limits<std::int32_t>::min() + 1, -1, 0, 1,
                                      std::numeric_limits<std::int32_t>::max() - 1,
                                      std::numeric_limits<std::int32_t>::max()};
  const std::int32_t c3_edges[] = {-(1 << 24), -(1 << 24) + 1, -1, 0, 1, (1 << 24) - 1, 1 << 24};
  for (std::int32_t i = 0; i < 200000; ++i) {
    const std::int32_t r = static_cast<std::int32_t>(rng() % 0x7FFFFFFFU) + 1;
    auto ratio = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng()));
    std::int32_t c3 = static_cast<std::int32_t>(rng() % ((1U << 25U) + 1U)) - (1 << 24);
    if ((i % 3) == 0) {
      ratio = ratio_edges[rng() % 7U];
    }
    if ((i % 5) == 0) {
      c3 = c3_edges[rng() % 7U];
    }
    const std::int64_t expected = (static_cast<std::int64_t>(ratio) + c3) * static_cast<std::int64_t>(r);
    ASSERT_EQ(detail::radius_times_ratios(r, Ratio::from_raw(ratio), Ratio::from_raw(c3)), expected)
        << r << " " << ratio << " " << c3;
    ASSERT_EQ(detail::radius_times_ratios_by_magnitude(r, Ratio::from_raw(ratio), Ratio::from_raw(c3)), expected)
        << r << " " << ratio << " " << c3;
  }
}

// The current limit's quotient from the prepared reciprocal of the table's
// first C1 (round 17: CorrectionDivisors::c1_raw / c1_mantissa, taken by
// torque_limit_raw_of_valid where C1 equals it) against the long division
// (torque_limit_raw_core without it): the same T_max and the same refusals
// over random inputs check_estimator_inputs() accepts, the first row's C1 and
// other C1s (these keep the division), at the ends of C1's range and of Q15.16.
// A reciprocal one too small, or the estimate left uncorrected, fails it.
TEST(LimitByPreparedReciprocal, IsTheDividedLimitBitForBit) {
  std::mt19937_64 rng(1717U);
  const std::int32_t c1_edges[] = {kMinC12.raw(), kMinC12.raw() + 1, 0x00800000, 0x00FFFFFF, kMaxC12.raw() - 1,
                                   kMaxC12.raw()};
  CorrectionTable table = default_parameter_table().correction;
  std::int64_t by_reciprocal = 0;
  for (std::int32_t i = 0; i < 300000; ++i) {
    if ((i % 1000) == 0) {
      const std::int32_t c1 = ((i % 3000) == 0) ? c1_edges[rng() % 6U]
                                                : kMinC12.raw() + static_cast<std::int32_t>(
                                                                      rng() % static_cast<std::uint64_t>(
                                                                                  (kMaxC12.raw() - kMinC12.raw()) + 1));
      table.rows[0].c1 = Ratio::from_raw(c1);
    }
    const CorrectionDivisors divisors = make_correction_divisors(table);
    ASSERT_EQ(divisors.c1_raw, table.rows[0].c1.raw());
    ASSERT_EQ(divisors.c1_mantissa, fx::normalised_reciprocal(table.rows[0].c1.q()).mantissa);
    const std::int32_t c1 = ((i % 4) == 3) ? (kMinC12.raw() + static_cast<std::int32_t>(rng() % 0x3C00001U))
                                           : table.rows[0].c1.raw();
    const Coefficients c{Ratio::from_raw(c1),
                         Ratio::from_raw(kMinC12.raw() + static_cast<std::int32_t>(rng() % 0x3C00001U)),
                         Ratio::from_raw(static_cast<std::int32_t>(rng() % 0x2000001U) - (1 << 24))};
    const auto ratio = Ratio::from_raw(static_cast<std::int32_t>(static_cast<std::uint32_t>(rng())) >>
                                       static_cast<std::uint32_t>(rng() % 32U));
    const auto radius_span = static_cast<std::uint64_t>((kMaxRadiusM.raw() - kMinRadiusM.raw()) + 1);
    const auto r = LengthM::from_raw(kMinRadiusM.raw() + static_cast<std::int32_t>(rng() % radius_span));
    const auto w = WheelLoadN::from_raw(static_cast<std::int32_t>(rng() % 0x7FFFFFFFU) + 1);
    const auto z_max = SinkageM::from_raw(static_cast<std::int32_t>(static_cast<std::uint32_t>(rng())) >>
                                          static_cast<std::uint32_t>(rng() % 32U));
    ASSERT_EQ(check_estimator_inputs(c, r, w), EstimateStatus::ok);
    std::int32_t divided = 0;
    std::int32_t prepared = 0;
    const bool divided_fits = detail::torque_limit_raw_core(c, ratio, r, w, z_max, fx::PreparedReciprocal{}, divided);
    const bool prepared_fits = detail::torque_limit_raw_of_valid(c, ratio, r, w, z_max, divisors, prepared);
    ASSERT_EQ(prepared_fits, divided_fits) << i;
    ASSERT_EQ(prepared, divided) << i << " c1 " << c1 << " w " << w.raw();
    by_reciprocal += (c1 == divisors.c1_raw) ? 1 : 0;
  }
  EXPECT_GT(by_reciprocal, 200000);
  // A first row without a positive C1 prepares no reciprocal.
  table.rows[0].c1 = Ratio::zero();
  const CorrectionDivisors none = make_correction_divisors(table);
  EXPECT_EQ(none.c1_raw, 0);
  EXPECT_EQ(none.c1_mantissa, 0U);
}

TEST(Reference, TwinRefusesWhatTheFlightCodeRefuses) {
  namespace ref = sinkwatch::ground::reference;
  EXPECT_THROW(ref::sinkage_m({1, 1, 0.13}, 0.0, 30, 1, 1), std::invalid_argument);
  EXPECT_THROW(ref::sinkage_m({1, 1, 0.13}, 0.15, 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(ref::sinkage_m({1, 0, 0.13}, 0.15, 30, 1, 1), std::invalid_argument);
  EXPECT_THROW(ref::drawbar_pull_n({1, 1, 0.13}, 0.15, -1, 1, 1), std::invalid_argument);
  EXPECT_THROW(ref::corrections_at({}, 10.0), std::invalid_argument);
  EXPECT_NEAR(ref::sinkage_m({1, 1, 0.13}, 0.15, 100, 10, 30), 0.0355, 1e-15);
}

TEST(Reference, FromFlightConvertsTheDefaultTable) {
  namespace ref = sinkwatch::ground::reference;
  const ref::Parameters p = ref::from_flight(default_parameter_table());
  EXPECT_NEAR(p.wheel_radius_m, 0.15, 1e-7);
  ASSERT_EQ(p.correction.size(), 5U);
  EXPECT_NEAR(p.correction[0].load_n, 29.43, 1e-4);
  EXPECT_NEAR(p.correction[0].c3, 0.20, 1e-7);
  EXPECT_NEAR(p.motor.gear_ratio, 400.0, 1e-9);
}

}  // namespace
