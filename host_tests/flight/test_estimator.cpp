// Eq. 11 (both ways), the correction table and the paper's published tables.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/reference.hpp"
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
