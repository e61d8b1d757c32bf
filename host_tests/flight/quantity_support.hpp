// quantity_support.hpp: test helpers between the flight module's unit types
// and double, shared by the flight host tests.
#ifndef SINKWATCH_HOST_TESTS_FLIGHT_QUANTITY_SUPPORT_HPP
#define SINKWATCH_HOST_TESTS_FLIGHT_QUANTITY_SUPPORT_HPP

#include <gtest/gtest.h>

#include "sinkwatch/fixedpoint/host_convert.hpp"

namespace sinkwatch {
namespace test {

/// The quantity nearest to `v`; a value that does not fit fails the test.
template <typename Qty>
Qty q(double v) {
  fx::Status st;
  const auto x = fx::from_double<typename Qty::q_type>(v, st);
  EXPECT_TRUE(st.ok()) << v;
  return Qty(x);
}

/// The exact value of a quantity, as a double.
template <typename Qty>
double d(Qty v) {
  return fx::to_double(v.q());
}

}  // namespace test
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_FLIGHT_QUANTITY_SUPPORT_HPP
