// fixedpoint_check.cpp: instantiates every fixed-point operation for the
// formats the flight code uses, so that the strict flight warning set
// (-Wconversion -Wsign-conversion -Wshadow -Wold-style-cast ... -Werror)
// sees every template body under g++ and clang++. Nothing here is called.
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/sqrt.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"
#if !defined(SINKWATCH_FIRMWARE)
#include "sinkwatch/fixedpoint/host_convert.hpp"
#endif

namespace sinkwatch {
namespace fx {
namespace check {

using QInt32 = Q<std::int32_t, 0>;
using QInt64 = Q<std::int64_t, 0>;
using Q1_62 = Q<std::int64_t, 62>;

template <typename T>
T all_core(T a, T b, Status& s) {
  T r = add(a, b, s);
  r = sub(r, b, s);
  r = neg(r, s);
  r = abs(r, s);
  r = min(r, a);
  r = max(r, b);
  r = clamp(r, a, b, s);
  r = mul(r, a, s);
  r = div(r, b, s);
  r = sqrt(r, s);
  r = reciprocal<T>(r, s);
  r = add(r, T::from_int(3, s), s);
  r = add(r, T::one(s), s);
  static_cast<void>(sin(r, s));
  static_cast<void>(cos(r, s));
  static_cast<void>(asin(r, s));
  static_cast<void>(acos(r, s));
  static_cast<void>(entry_angle(r, s));
  static_cast<void>(atan2(r, a, s));
  return r;
}

Q15_16 check_q15_16(Q15_16 a, Q15_16 b, Status& s) { return all_core(a, b, s); }
Q1_30 check_q1_30(Q1_30 a, Q1_30 b, Status& s) { return all_core(a, b, s); }
Q3_28 check_q3_28(Q3_28 a, Q3_28 b, Status& s) { return all_core(a, b, s); }
QInt32 check_int32(QInt32 a, QInt32 b, Status& s) { return all_core(a, b, s); }
Q31_32 check_q31_32(Q31_32 a, Q31_32 b, Status& s) { return all_core(a, b, s); }
QInt64 check_int64(QInt64 a, QInt64 b, Status& s) { return all_core(a, b, s); }
Q1_62 check_q1_62(Q1_62 a, Q1_62 b, Status& s) { return all_core(a, b, s); }

// Mixed formats: narrowing and widening in both storages.
Q15_16 check_mixed(Q1_30 a, Q31_32 b, QInt32 c, Status& s) {
  const Q15_16 p = mul<Q15_16>(a, b, s);
  const Q15_16 q = div<Q15_16>(c, a, s);
  const Q31_32 r = rescale<Q31_32>(a, s);
  const Q1_30 t = rescale<Q1_30>(b, s);
  const Q15_16 u = sqrt<Q15_16>(Q1_30::max(), s);
  const Q3_28 v = mul<Q3_28>(c, t, s);
  static_cast<void>(r);
  static_cast<void>(v);
  return add(add(p, q, s), u, s);
}

constexpr Q15_16 k_c3 = constant<Q15_16>(0.13);
constexpr Q31_32 k_big = constant<Q31_32>(-12345.678);
Q31_32 check_constants(Status& s) { return add(k_big, rescale<Q31_32>(k_c3, s), s); }

}  // namespace check
}  // namespace fx
}  // namespace sinkwatch
