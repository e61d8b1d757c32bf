// test_cov_correction.cpp: what corrections_at and the estimator's input
// check do with inputs a validated parameter table never contains: a row
// count past the array, breakpoints whose spacing does not fit the load
// format, and a C2 above its range. Each must give a status, never a number.
#include <gtest/gtest.h>

#include "quantity_support.hpp"
#include "dividing_oracle.hpp"
#include "prepared_support.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace {

using namespace sinkwatch::flight;
namespace test = sinkwatch::test;
namespace oracle = sinkwatch::oracle;
using sinkwatch::test::d;
using sinkwatch::test::q;

CorrectionRow row(double load_n, double c3) {
  return CorrectionRow{q<WheelLoadN>(load_n), q<Ratio>(1.0), q<Ratio>(1.0), q<Ratio>(c3), q<Ratio>(0.5)};
}

TEST(CorrectionsAt, RowCountPastTheArrayIsAMalformedTable) {
  CorrectionTable t = default_parameter_table().correction;
  t.count = kMaxCorrectionRows + 1U;
  const CorrectionResult r = test::corrections_of(t, q<WheelLoadN>(50.0));
  EXPECT_EQ(r.status, EstimateStatus::invalid_coefficient);
  EXPECT_EQ(r.coefficients.c3, Ratio::zero());
}

TEST(CorrectionsAt, BreakpointSpacingBeyondTheLoadFormatFailsInsteadOfInterpolating) {
  // -30000 N .. +30000 N: the span, 60000 N, does not fit Q15.16 (max 32768).
  CorrectionTable t{};
  t.count = 2U;
  t.rows[0] = row(-30000.0, 0.2);
  t.rows[1] = row(30000.0, 0.1);
  const CorrectionResult r = test::corrections_of(t, q<WheelLoadN>(100.0));
  EXPECT_EQ(r.status, EstimateStatus::invalid_coefficient);
  EXPECT_EQ(r.dp_max_ratio, Ratio::zero());
}

TEST(CorrectionsAt, SameBreakpointsWithinTheFormatInterpolate) {
  // The control for the case above: a span that fits interpolates linearly.
  CorrectionTable t{};
  t.count = 2U;
  t.rows[0] = row(-10000.0, 0.2);
  t.rows[1] = row(10000.0, 0.1);
  const CorrectionResult r = test::corrections_of(t, q<WheelLoadN>(0.5));
  ASSERT_EQ(r.status, EstimateStatus::ok);
  EXPECT_EQ(r.clamp, LoadClamp::none);
  const double fraction = (0.5 + 10000.0) / 20000.0;
  EXPECT_NEAR(d(r.coefficients.c3), 0.2 + (0.1 - 0.2) * fraction, 1e-7);  // Q7.24 LSB: 6e-8
}

// Prepared divisors (make_correction_divisors) of tables validate() refuses:
// a segment whose width overflows, one that does not increase, a row count
// past the array. Those segments keep no reciprocal, and the prepared
// corrections_at must give exactly the plain answer at every load.
TEST(CorrectionsAtPrepared, MalformedTablesGiveThePlainAnswerAtEveryLoad) {
  CorrectionTable overflowing{};
  overflowing.count = 3U;
  overflowing.rows[0] = row(-30000.0, 0.2);
  overflowing.rows[1] = row(30000.0, 0.1);
  overflowing.rows[2] = row(30500.0, 0.05);
  CorrectionTable falling{};
  falling.count = 3U;
  falling.rows[0] = row(50.0, 0.2);
  falling.rows[1] = row(40.0, 0.15);
  falling.rows[2] = row(200.0, 0.1);
  CorrectionTable too_many = default_parameter_table().correction;
  too_many.count = kMaxCorrectionRows + 3U;
  for (const CorrectionTable* t : {&overflowing, &falling, &too_many}) {
    const CorrectionDivisors divisors = make_correction_divisors(*t);
    for (const double load : {0.5, 30.0, 45.0, 100.0, 150.0, 30200.0, 31000.0}) {
      const CorrectionResult plain = oracle::corrections_at(*t, q<WheelLoadN>(load));
      const CorrectionResult prepared = corrections_at(*t, divisors, q<WheelLoadN>(load));
      EXPECT_EQ(prepared.status, plain.status) << load;
      EXPECT_EQ(prepared.clamp, plain.clamp) << load;
      EXPECT_EQ(prepared.coefficients.c3, plain.coefficients.c3) << load;
      EXPECT_EQ(prepared.dp_max_ratio, plain.dp_max_ratio) << load;
    }
  }
  // The overflowing and the falling segments have no normalised width; the good ones do.
  EXPECT_EQ(make_correction_divisors(overflowing).width[0].normalised, 0U);
  EXPECT_NE(make_correction_divisors(overflowing).width[1].normalised, 0U);
  EXPECT_EQ(make_correction_divisors(falling).width[0].normalised, 0U);
  EXPECT_NE(make_correction_divisors(falling).width[1].normalised, 0U);
  // The interpolation in the falling table's good segment is a number.
  EXPECT_EQ(corrections_at(falling, make_correction_divisors(falling), q<WheelLoadN>(100.0)).status, EstimateStatus::ok);
}

TEST(EstimatorInputs, C2AboveItsRangeIsAnInvalidCoefficient) {
  const Coefficients c{q<Ratio>(1.0), q<Ratio>(4.5), q<Ratio>(0.1)};
  EXPECT_EQ(check_estimator_inputs(c, q<LengthM>(0.15), q<WheelLoadN>(50.0)), EstimateStatus::invalid_coefficient);
  const SinkageResult s = sinkage_from_pull(c, q<LengthM>(0.15), q<WheelLoadN>(50.0), q<TorqueNm>(2.0),
                                            q<DrawbarPullN>(5.0));
  EXPECT_EQ(s.status, EstimateStatus::invalid_coefficient);
  EXPECT_EQ(s.sinkage_m, SinkageM::zero());
  const Coefficients at_max{q<Ratio>(4.0), q<Ratio>(4.0), q<Ratio>(1.0)};
  EXPECT_EQ(check_estimator_inputs(at_max, q<LengthM>(0.15), q<WheelLoadN>(50.0)), EstimateStatus::ok);
}

}  // namespace
