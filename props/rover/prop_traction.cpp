// The motion-resistance coefficient and the trend carried ahead
// (flight/traction.hpp) against their double twins (ground/rover_loads.hpp)
// over the whole input envelope: any loads in the default table's
// [load_min, load_max], torques to +-200 N m, pulls to +-500 N, radii
// 0.01..2 m (the table's whole range). Bounds (docs/traction.md, "Arithmetic
// and error"): 1/r is prepared in Q7.24 (off by at most 2^-25 1/m), the
// thrust sum T (1/r) and the pull are exact in 64 bits, the quotient rounds
// once into Q7.24:
//   |rho_fixed - rho_ref| <= 2^-25 (1 + |sum T| / sum W);
// the carried term rounds once: |ahead_fixed - ahead_ref| <= 2^-25.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>

#include "rover_test_support.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/traction.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace sinkwatch {
namespace {

using rover_test::d;
using rover_test::q;

std::int32_t uniform_in(std::int32_t lo, std::int32_t hi) {
  return *rc::gen::resize(rc::kNominalSize, rc::gen::inRange<std::int32_t>(lo, hi + 1));
}

template <typename Quantity>
Quantity raw_within(double lo, double hi) {
  return Quantity::from_raw(uniform_in(q<Quantity>(lo).raw(), q<Quantity>(hi).raw()));
}

RC_GTEST_PROP(TractionProp, CoefficientWithinBoundOfTheTwin, ()) {
  const flight::ParameterTable table = flight::default_parameter_table();
  const bool reverse = *rc::gen::arbitrary<bool>();
  flight::TractionInput in{};
  in.loads_valid = true;
  std::array<double, flight::kWheelCount> t{};
  std::array<double, flight::kWheelCount> p{};
  std::array<double, flight::kWheelCount> w{};
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    in.load_n[i] = raw_within<flight::WheelLoadN>(d(table.monitor.load_min_n), d(table.monitor.load_max_n));
    in.torque_nm[i] = raw_within<flight::TorqueNm>(-200.0, 200.0);
    in.drawbar_pull_n[i] = raw_within<flight::DrawbarPullN>(-500.0, 500.0);
    in.torque_valid[i] = true;
    in.direction[i] = reverse ? flight::DriveDirection::reverse : flight::DriveDirection::forward;
    t[i] = d(in.torque_nm[i]);
    p[i] = reverse ? -d(in.drawbar_pull_n[i]) : d(in.drawbar_pull_n[i]);
    w[i] = d(in.load_n[i]);
  }
  const flight::LengthM radius = raw_within<flight::LengthM>(0.01, 2.0);
  const double twin = ground::resistance_coefficient(t, p, w, d(radius));
  flight::TractionMonitor m;
  flight::TractionOutput out{};
  m.step(in, table.traction, table.monitor, flight::inverse_radius(radius), out);
  if (std::fabs(twin) >= 127.0) {
    RC_ASSERT(!out.rho_valid || std::fabs(d(out.resistance)) >= 127.0);  // saturated or reported
    return;
  }
  RC_ASSERT(out.rho_valid);
  double load = 0.0;
  double torque = 0.0;
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    load += w[i];
    torque += t[i];
  }
  const double bound = std::ldexp(1.0, -25) * (1.0 + std::fabs(torque) / load) + 1e-12 * std::fabs(twin);
  RC_ASSERT(std::fabs(d(out.resistance) - twin) <= bound);
}

RC_GTEST_PROP(TractionProp, CarriedAheadWithinHalfAnLsbOfTheTwin, ()) {
  // Any two medians in the levels' range and beyond, any lookahead the table
  // accepts, any distance the history can span (trend_span_m to two spans of
  // the longest, 10 m).
  const flight::Ratio rho_med = raw_within<flight::Ratio>(-4.0, 4.0);
  const flight::Ratio rho_back = raw_within<flight::Ratio>(-4.0, 4.0);
  const flight::LengthM lookahead = raw_within<flight::LengthM>(0.0, 10.0);
  const std::int64_t distance = *rc::gen::inRange<std::int64_t>(q<flight::LengthM>(0.2).raw(),
                                                                 std::int64_t{10} * q<flight::LengthM>(1.0).raw());
  flight::Ratio ahead{};
  const bool ok = flight::carried_ahead(rho_med, rho_back, distance, lookahead, ahead);
  const double twin =
      ground::resistance_ahead(d(rho_med), d(rho_back), std::ldexp(static_cast<double>(distance), -24), d(lookahead));
  if (std::fabs(twin) >= 127.0) {
    RC_ASSERT(!ok || std::fabs(d(ahead)) >= 127.0);
    return;
  }
  RC_ASSERT(ok);
  RC_ASSERT(std::fabs(d(ahead) - twin) <= std::ldexp(1.0, -25) + 1e-12 * std::fabs(twin));
}

// The twelfth round of issue 15 (docs/traction.md): the quotient and the
// cycle's distance without a 64-bit library division, the same bits as the
// plain rounded divisions for any operands.
RC_GTEST_PROP(TractionProp, RoundedQuotientIsThePlainRoundedDivision, ()) {
  // Divisors of every width up to 34 bits (the load sums), dividends up to
  // 2^63 (the resistance) and ties.
  const int bits = *rc::gen::inRange(1, 35);
  const std::uint64_t d = *rc::gen::inRange<std::uint64_t>(std::uint64_t{1} << (bits - 1), std::uint64_t{1} << bits);
  const std::uint64_t n = *rc::gen::oneOf(rc::gen::inRange<std::uint64_t>(0U, std::uint64_t{1} << 63U),
                                          rc::gen::map(rc::gen::inRange<std::uint64_t>(0U, std::uint64_t{1} << 31U),
                                                       [d](std::uint64_t q) { return (q * d) + (d / 2U); }));
  std::uint64_t plain = n / d;
  const std::uint64_t remainder = n - (plain * d);
  if (remainder >= (d - remainder)) {
    ++plain;
  }
  RC_ASSERT(flight::detail::rounded_quotient(n, d) == plain);
}

RC_GTEST_PROP(TractionProp, TravelledIsThePlainRoundedThousandth, ()) {
  const std::uint32_t speed = *rc::gen::inRange<std::uint32_t>(0U, 0x80000001U);
  const std::uint32_t dt_ms = *rc::gen::inRange<std::uint32_t>(0U, 2001U);
  RC_ASSERT(flight::detail::travelled_q24(speed, dt_ms) == ((static_cast<std::uint64_t>(speed) * dt_ms) + 500U) / 1000U);
}

}  // namespace
}  // namespace sinkwatch
