// prop_q.cpp: every core Q operation (add, sub, neg, abs, min, max, clamp,
// comparisons, from_int, rescale, mul, div, sqrt, reciprocal) against an
// exact integer reference, over the whole representable range, in several
// formats (Q15_16, Q1_30, int32 with F = 0, Q31_32, int64 with F = 0 and
// F = 62) and mixed-format mul, div and rescale. Each property asserts the
// documented bound (docs/fixedpoint.md) exactly, in integers, and the exact
// saturation and status behaviour.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "fx_reference.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/sqrt.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fxref::I128;
using fxref::U128;

using QInt32 = fx::Q<std::int32_t, 0>;
using QInt64 = fx::Q<std::int64_t, 0>;
using Q1_62 = fx::Q<std::int64_t, 62>;
using Q7_24 = fx::Q<std::int32_t, 24>;
using Q23_40 = fx::Q<std::int64_t, 40>;

// ------------------------------------------------------------ operations

template <typename QT>
std::string check_add(QT a, QT b) {
  fx::Status s;
  const QT r = fx::add(a, b, s);
  return fxref::check_exact(r, s, static_cast<I128>(a.raw()) + b.raw());
}

template <typename QT>
std::string check_sub(QT a, QT b) {
  fx::Status s;
  const QT r = fx::sub(a, b, s);
  return fxref::check_exact(r, s, static_cast<I128>(a.raw()) - b.raw());
}

template <typename QT>
std::string check_neg_abs(QT a) {
  fx::Status s1;
  const std::string e1 = fxref::check_exact(fx::neg(a, s1), s1, -static_cast<I128>(a.raw()));
  if (!e1.empty()) {
    return "neg: " + e1;
  }
  fx::Status s2;
  const I128 x = a.raw();
  const std::string e2 = fxref::check_exact(fx::abs(a, s2), s2, (x < 0) ? -x : x);
  return e2.empty() ? e2 : "abs: " + e2;
}

template <typename QT>
std::string check_min_max_cmp(QT a, QT b) {
  const auto x = a.raw();
  const auto y = b.raw();
  if (fx::min(a, b).raw() != std::min(x, y) || fx::max(a, b).raw() != std::max(x, y)) {
    return "min/max";
  }
  if ((a == b) != (x == y) || (a != b) != (x != y) || (a < b) != (x < y) || (a <= b) != (x <= y) ||
      (a > b) != (x > y) || (a >= b) != (x >= y)) {
    return "comparison";
  }
  return "";
}

template <typename QT>
std::string check_clamp(QT a, QT lo, QT hi) {
  fx::Status s;
  const QT r = fx::clamp(a, lo, hi, s);
  if (hi < lo) {
    if (s.bits() != static_cast<std::uint8_t>(fx::Flag::domain) || r != lo) {
      return "clamp with lo > hi must raise domain only and return lo";
    }
    return "";
  }
  if (!s.ok() || r.raw() != std::clamp(a.raw(), lo.raw(), hi.raw())) {
    return "clamp";
  }
  return "";
}

template <typename QT>
std::string check_from_int(std::int64_t v) {
  fx::Status s;
  const QT r = QT::from_int(v, s);
  const fxref::Rational x = fxref::scaled(v < 0, fxref::mag(v), QT::frac_bits);
  return fxref::check_rounded(r, s, x.negative, x.num, x.den, x.num_too_big);
}

template <typename Out, typename In>
std::string check_rescale(In a) {
  fx::Status s;
  const Out r = fx::rescale<Out>(a, s);
  const fxref::Rational x = fxref::scaled(a.raw() < 0, fxref::mag(a.raw()), Out::frac_bits - In::frac_bits);
  return fxref::check_rounded(r, s, x.negative, x.num, x.den, x.num_too_big);
}

template <typename Out, typename QA, typename QB>
std::string check_mul(QA a, QB b) {
  fx::Status s;
  const Out r = fx::mul<Out>(a, b, s);
  const bool negative = (a.raw() < 0) != (b.raw() < 0);
  const U128 p = fxref::mag(a.raw()) * fxref::mag(b.raw());
  const fxref::Rational x = fxref::scaled(negative, p, Out::frac_bits - QA::frac_bits - QB::frac_bits);
  return fxref::check_rounded(r, s, x.negative, x.num, x.den, x.num_too_big);
}

template <typename Out, typename QA, typename QB>
std::string check_div(QA a, QB b) {
  fx::Status s;
  const Out r = fx::div<Out>(a, b, s);
  if (b.raw() == 0) {
    const I128 expected = (a.raw() == 0) ? 0 : ((a.raw() < 0) ? fxref::raw_min<Out>() : fxref::raw_max<Out>());
    if (s.bits() != static_cast<std::uint8_t>(fx::Flag::div_by_zero) || r.raw() != expected) {
      return "division by zero: expected div_by_zero only and " + fxref::to_string(expected) + ", got " +
             fxref::to_string(static_cast<I128>(r.raw()));
    }
    return "";
  }
  // raw_out = a_raw * 2^k / b_raw, k = Fo + FB - FA; every tested format
  // has |k| <= 62, so both sides stay below 2^127.
  const int k = Out::frac_bits + QB::frac_bits - QA::frac_bits;
  const bool negative = (a.raw() < 0) != (b.raw() < 0);
  const U128 num = fxref::mag(a.raw()) << std::max(k, 0);
  const U128 den = fxref::mag(b.raw()) << std::max(-k, 0);
  return fxref::check_rounded(r, s, negative, num, den);
}

/// floor(sqrt(x)) for x < 2^127, independently of the library: a long
/// double estimate corrected in exact integers.
inline U128 isqrt_reference(U128 x) {
  U128 r = static_cast<U128>(std::sqrt(static_cast<long double>(x)));
  while (r * r > x) {
    --r;
  }
  while ((r + 1) * (r + 1) <= x) {
    ++r;
  }
  return r;
}

template <typename Out, typename In>
std::string check_sqrt(In a) {
  fx::Status s;
  const Out r = fx::sqrt<Out>(a, s);
  if (a.raw() < 0) {
    if (s.bits() != static_cast<std::uint8_t>(fx::Flag::domain) || r.raw() != 0) {
      return "sqrt of a negative: expected domain only and zero";
    }
    return "";
  }
  // raw_out = sqrt(X), X = a_raw * 2^(2 Fo - Fi) (an integer, < 2^127 here).
  const U128 x = static_cast<U128>(a.raw()) << (2 * Out::frac_bits - In::frac_bits);
  const U128 fl = isqrt_reference(x);
  const U128 rounded = (x - fl * fl > fl) ? fl + 1 : fl;
  const auto ctx = [&]() { return " x " + fxref::to_string(x) + " got " + fxref::to_string(static_cast<I128>(r.raw())); };
  if (rounded > static_cast<U128>(fxref::raw_max<Out>())) {
    if (s.bits() != static_cast<std::uint8_t>(fx::Flag::overflow) || r != Out::max()) {
      return "sqrt: expected saturation" + ctx();
    }
    return "";
  }
  if (!s.ok() || r.raw() < 0) {
    return "sqrt: unexpected flag or sign" + ctx();
  }
  // Documented bound |r - sqrt(X)| <= 1/2, in integers:
  // (2r - 1)^2 <= 4X <= (2r + 1)^2 (no equality can occur: 4X is even).
  const U128 rr = static_cast<U128>(r.raw());
  const U128 lo = (rr == 0) ? 0 : (2 * rr - 1) * (2 * rr - 1);
  const U128 hi = (2 * rr + 1) * (2 * rr + 1);
  if (!(lo <= 4 * x && 4 * x <= hi) || rr != rounded) {
    return "sqrt: more than 1/2 LSB off" + ctx();
  }
  return "";
}

template <typename Out, typename In>
std::string check_reciprocal(In a) {
  fx::Status s;
  const Out r = fx::reciprocal<Out>(a, s);
  if (a.raw() == 0) {
    if (s.bits() != static_cast<std::uint8_t>(fx::Flag::div_by_zero) || r != Out::max()) {
      return "reciprocal of zero: expected div_by_zero only and max";
    }
    return "";
  }
  // raw_out = 2^(Fo + Fi) / a_raw.
  return fxref::check_rounded(r, s, a.raw() < 0, fxref::pow2(Out::frac_bits + In::frac_bits), fxref::mag(a.raw()));
}

/// from_double (the run-time twin of constant): the double's exact value
/// M 2^E (M a 53-bit integer) in raw units is M 2^(E + F); correctly rounded,
/// ties away, saturated with overflow; NaN gives domain and zero.
template <typename QT>
std::string check_from_double(double v) {
  fx::Status s;
  const QT r = fx::from_double<QT>(v, s);
  if (std::isnan(v)) {
    if (s.bits() != static_cast<std::uint8_t>(fx::Flag::domain) || r.raw() != 0) {
      return "from_double(NaN): expected domain only and zero";
    }
    return "";
  }
  if (std::isinf(v)) {
    return fxref::check_rounded(r, s, v < 0, 0, 1, true);
  }
  int e = 0;
  const double f = std::frexp(std::fabs(v), &e);  // |v| = f 2^e, f in [0.5, 1)
  const U128 m = static_cast<U128>(std::ldexp(f, 53));
  const int shift = e - 53 + QT::frac_bits;
  if (shift < -120) {
    // |v| 2^F < 2^53 2^-120: rounds to zero, which is not an error.
    if (!s.ok() || r.raw() != 0) {
      return "from_double(tiny): expected zero and a clean status";
    }
    return "";
  }
  const fxref::Rational x = fxref::scaled(std::signbit(v), m, shift);
  return fxref::check_rounded(r, s, x.negative, x.num, x.den, x.num_too_big);
}

/// Doubles: every bit pattern (NaN, infinities, subnormals included), exact
/// ties k/2 LSB and their neighbours one ulp away, and values near the edges.
template <typename QT>
double from_double_arg() {
  const int mode = *rc::gen::inRange(0, 4);
  if (mode == 0) {
    const std::uint64_t bits = *fxref::full_range<std::uint64_t>();
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  const auto k = *fxref::raw<std::int32_t>();
  double v = std::ldexp(static_cast<double>(k) + ((mode == 1) ? 0.5 : 0.0), -QT::frac_bits);
  if (mode == 3) {
    v = std::ldexp(static_cast<double>(*fxref::raw<typename QT::storage_type>()), -QT::frac_bits);
  }
  switch (*rc::gen::inRange(0, 3)) {
    case 0:
      return std::nextafter(v, -std::numeric_limits<double>::infinity());
    case 1:
      return std::nextafter(v, std::numeric_limits<double>::infinity());
    default:
      return v;
  }
}

// ------------------------------------------------------------ generators next to overflow

/// A value next to the boundary `target` (exact, in raw units of S).
template <typename S>
S near(I128 target) {
  const int delta = *rc::gen::inRange(-2, 3);
  return fxref::clamp_to<S>(target + delta);
}

/// An (a, b) pair for add / sub whose exact result is next to max or min.
template <typename QT>
std::pair<QT, QT> add_pair(bool subtract) {
  using S = typename QT::storage_type;
  const QT b = *fxref::q<QT>();
  if (*rc::gen::inRange(0, 3) != 0) {
    return {*fxref::q<QT>(), b};
  }
  const I128 edge = *rc::gen::arbitrary<bool>() ? fxref::raw_max<QT>() : fxref::raw_min<QT>();
  const I128 a = subtract ? edge + b.raw() : edge - b.raw();
  return {QT::from_raw(near<S>(a)), b};
}

/// An (a, b) pair whose product in Out is next to Out's max or min.
template <typename Out, typename QA, typename QB>
std::pair<QA, QB> mul_pair() {
  const QA a = *fxref::q<QA>();
  if (a.raw() == 0 || *rc::gen::inRange(0, 3) != 0) {
    return {a, *fxref::q<QB>()};
  }
  // b = edge * 2^(FA + FB - Fo) / a.
  const bool neg = *rc::gen::arbitrary<bool>();
  const int sh = QA::frac_bits + QB::frac_bits - Out::frac_bits;
  I128 t = neg ? fxref::raw_min<Out>() : fxref::raw_max<Out>();
  t = (sh >= 0) ? t * (static_cast<I128>(1) << sh) : t / (static_cast<I128>(1) << -sh);
  return {a, QB::from_raw(near<typename QB::storage_type>(t / a.raw()))};
}

/// An (a, b) pair whose quotient in Out is next to Out's max or min.
template <typename Out, typename QA, typename QB>
std::pair<QA, QB> div_pair() {
  const QB b = *fxref::q<QB>();
  if (b.raw() == 0 || *rc::gen::inRange(0, 3) != 0) {
    return {*fxref::q<QA>(), b};
  }
  // a = edge * b * 2^(FA - FB - Fo); b limited so that this stays in I128.
  const bool neg = *rc::gen::arbitrary<bool>();
  const int sh = QA::frac_bits - QB::frac_bits - Out::frac_bits;
  const I128 edge = neg ? fxref::raw_min<Out>() : fxref::raw_max<Out>();
  const I128 bb = static_cast<I128>(b.raw()) >> 8;  // keep |edge * b| < 2^119
  I128 t = edge * (bb == 0 ? 1 : bb);
  t = (sh >= 0) ? ((fxref::bit_length(fxref::mag(t)) + sh < 126) ? t * (static_cast<I128>(1) << sh) : t)
                : t / (static_cast<I128>(1) << -sh);
  return {QA::from_raw(near<typename QA::storage_type>(t)), QB::from_raw(static_cast<typename QB::storage_type>(bb == 0 ? 1 : bb))};
}

/// A value of In next to the edge of Out (for rescale).
template <typename Out, typename In>
In rescale_arg() {
  if (*rc::gen::inRange(0, 3) != 0) {
    return *fxref::q<In>();
  }
  const int sh = In::frac_bits - Out::frac_bits;
  I128 t = *rc::gen::arbitrary<bool>() ? fxref::raw_max<Out>() : fxref::raw_min<Out>();
  t = (sh >= 0) ? ((sh < 60) ? t * (static_cast<I128>(1) << sh) : t) : t / (static_cast<I128>(1) << -sh);
  return In::from_raw(near<typename In::storage_type>(t));
}

/// int64 values next to the edge of QT's integer range.
template <typename QT>
std::int64_t from_int_arg() {
  if (*rc::gen::inRange(0, 3) != 0) {
    return *fxref::raw<std::int64_t>();
  }
  const I128 t = (*rc::gen::arbitrary<bool>() ? fxref::raw_max<QT>() : fxref::raw_min<QT>()) >> QT::frac_bits;
  return near<std::int64_t>(t);
}

}  // namespace

// ------------------------------------------------------------ properties, per format

#define FX_CORE_PROPS(Suffix, QT)                                                               \
  RC_GTEST_PROP(FxCore_##Suffix, AddIsExactOrSaturates, ()) {                                   \
    const auto ab = add_pair<QT>(false);                                                        \
    RC_ASSERT(check_add(ab.first, ab.second) == std::string());                                 \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, SubIsExactOrSaturates, ()) {                                   \
    const auto ab = add_pair<QT>(true);                                                         \
    RC_ASSERT(check_sub(ab.first, ab.second) == std::string());                                 \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, NegAbsAreExactOrSaturate, ()) {                                \
    RC_ASSERT(check_neg_abs(*fxref::q<QT>()) == std::string());                                 \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, MinMaxComparisonsMatchRaw, ()) {                               \
    RC_ASSERT(check_min_max_cmp(*fxref::q<QT>(), *fxref::q<QT>()) == std::string());            \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, ClampIsExactOrReportsLoAboveHi, ()) {                          \
    RC_ASSERT(check_clamp(*fxref::q<QT>(), *fxref::q<QT>(), *fxref::q<QT>()) == std::string()); \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, FromIntIsExactOrSaturates, ()) {                               \
    RC_ASSERT(check_from_int<QT>(from_int_arg<QT>()) == std::string());                         \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, MulWithinHalfLsb, ()) {                                        \
    const auto ab = mul_pair<QT, QT, QT>();                                                     \
    RC_ASSERT(check_mul<QT>(ab.first, ab.second) == std::string());                             \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, DivWithinHalfLsb, ()) {                                        \
    const auto ab = div_pair<QT, QT, QT>();                                                     \
    RC_ASSERT(check_div<QT>(ab.first, ab.second) == std::string());                             \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, SqrtWithinHalfLsb, ()) {                                       \
    RC_ASSERT((check_sqrt<QT, QT>(*fxref::q<QT>())) == std::string());                          \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, ReciprocalWithinHalfLsb, ()) {                                 \
    RC_ASSERT((check_reciprocal<QT, QT>(*fxref::q<QT>())) == std::string());                    \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, FromDoubleWithinHalfLsb, ()) {                                \
    RC_ASSERT(check_from_double<QT>(from_double_arg<QT>()) == std::string());                   \
  }                                                                                             \
  RC_GTEST_PROP(FxCore_##Suffix, StatusIsSticky, ()) {                                          \
    fx::Status s;                                                                               \
    const auto initial = *rc::gen::inRange(0, 8);                                               \
    if ((initial & 1) != 0) s.raise(fx::Flag::overflow);                                        \
    if ((initial & 2) != 0) s.raise(fx::Flag::div_by_zero);                                     \
    if ((initial & 4) != 0) s.raise(fx::Flag::domain);                                          \
    const std::uint8_t before = s.bits();                                                       \
    const QT a = *fxref::q<QT>();                                                               \
    const QT b = *fxref::q<QT>();                                                               \
    static_cast<void>(fx::div(fx::mul(fx::add(a, b, s), b, s), a, s));                          \
    static_cast<void>(fx::sqrt(fx::sub(a, b, s), s));                                           \
    RC_ASSERT((s.bits() & before) == before);                                                   \
  }

FX_CORE_PROPS(Q15_16, fx::Q15_16)
FX_CORE_PROPS(Q1_30, fx::Q1_30)
FX_CORE_PROPS(Q3_28, fx::Q3_28)
FX_CORE_PROPS(Int32, QInt32)
FX_CORE_PROPS(Q31_32, fx::Q31_32)
FX_CORE_PROPS(Int64, QInt64)
FX_CORE_PROPS(Q1_62, Q1_62)

// ------------------------------------------------------------ mixed formats

#define FX_MIXED_MUL_DIV(Name, Out, QA, QB)                                    \
  RC_GTEST_PROP(FxMixed, Mul_##Name, ()) {                                     \
    const auto ab = mul_pair<Out, QA, QB>();                                   \
    RC_ASSERT((check_mul<Out>(ab.first, ab.second)) == std::string());         \
  }                                                                            \
  RC_GTEST_PROP(FxMixed, Div_##Name, ()) {                                     \
    const auto ab = div_pair<Out, QA, QB>();                                   \
    RC_ASSERT((check_div<Out>(ab.first, ab.second)) == std::string());         \
  }

FX_MIXED_MUL_DIV(Q15_16_from_Q1_30_Q31_32, fx::Q15_16, fx::Q1_30, fx::Q31_32)
FX_MIXED_MUL_DIV(Q31_32_from_Q15_16_Q1_30, fx::Q31_32, fx::Q15_16, fx::Q1_30)
FX_MIXED_MUL_DIV(Q1_30_from_Int32_Q15_16, fx::Q1_30, QInt32, fx::Q15_16)
FX_MIXED_MUL_DIV(Q15_16_from_Q1_30_Int32, fx::Q15_16, fx::Q1_30, QInt32)
FX_MIXED_MUL_DIV(Q3_28_from_Q15_16_Q15_16, fx::Q3_28, fx::Q15_16, fx::Q15_16)
FX_MIXED_MUL_DIV(Q1_30_from_Q31_32_Q15_16, fx::Q1_30, fx::Q31_32, fx::Q15_16)
FX_MIXED_MUL_DIV(Q1_62_from_Q31_32_Q31_32, Q1_62, fx::Q31_32, fx::Q31_32)
FX_MIXED_MUL_DIV(Int64_from_Q1_62_Int32, QInt64, Q1_62, QInt32)
FX_MIXED_MUL_DIV(Q7_24_from_Q1_30_Q1_30, Q7_24, fx::Q1_30, fx::Q1_30)
// Two 32-bit operands into 64 bits: the products that cannot saturate
// (exact with no shift, as Eq. 11's Q23.40 terms; INT32_MIN squared is 2^62).
FX_MIXED_MUL_DIV(Int64_from_Int32_Int32, QInt64, QInt32, QInt32)
FX_MIXED_MUL_DIV(Q23_40_from_Q7_24_Q15_16, Q23_40, Q7_24, fx::Q15_16)

#define FX_MIXED_RESCALE(Name, Out, In)                                          \
  RC_GTEST_PROP(FxMixed, Rescale_##Name, ()) {                                   \
    RC_ASSERT((check_rescale<Out, In>(rescale_arg<Out, In>())) == std::string()); \
  }

FX_MIXED_RESCALE(Q15_16_to_Q1_30, fx::Q1_30, fx::Q15_16)
FX_MIXED_RESCALE(Q1_30_to_Q15_16, fx::Q15_16, fx::Q1_30)
FX_MIXED_RESCALE(Q31_32_to_Q15_16, fx::Q15_16, fx::Q31_32)
FX_MIXED_RESCALE(Q15_16_to_Q31_32, fx::Q31_32, fx::Q15_16)
FX_MIXED_RESCALE(Q31_32_to_Q1_30, fx::Q1_30, fx::Q31_32)
FX_MIXED_RESCALE(Int32_to_Q3_28, fx::Q3_28, QInt32)
FX_MIXED_RESCALE(Q1_62_to_Int32, QInt32, Q1_62)
FX_MIXED_RESCALE(Int64_to_Q1_62, Q1_62, QInt64)
FX_MIXED_RESCALE(Q1_30_to_Int64, QInt64, fx::Q1_30)
FX_MIXED_RESCALE(Q1_62_to_Q31_32, fx::Q31_32, Q1_62)

#define FX_MIXED_SQRT_RECIP(Name, Out, In)                                          \
  RC_GTEST_PROP(FxMixed, Sqrt_##Name, ()) {                                         \
    RC_ASSERT((check_sqrt<Out, In>(*fxref::q<In>())) == std::string());             \
  }                                                                                 \
  RC_GTEST_PROP(FxMixed, Reciprocal_##Name, ()) {                                   \
    RC_ASSERT((check_reciprocal<Out, In>(*fxref::q<In>())) == std::string());       \
  }

FX_MIXED_SQRT_RECIP(Q15_16_from_Int32, fx::Q15_16, QInt32)
FX_MIXED_SQRT_RECIP(Q1_30_from_Q15_16, fx::Q1_30, fx::Q15_16)
FX_MIXED_SQRT_RECIP(Q31_32_from_Q15_16, fx::Q31_32, fx::Q15_16)
FX_MIXED_SQRT_RECIP(Q15_16_from_Q31_32, fx::Q15_16, fx::Q31_32)
FX_MIXED_SQRT_RECIP(Q1_30_from_Int64, fx::Q1_30, QInt64)

// ------------------------------------------------------------ divisions without a divide instruction

// The forms the Cortex-M0 takes (wide.hpp; the host takes the built-in
// division): the 64 / 32-bit long division by reciprocal, the one by digits,
// and the normalising division of any 64-bit dividend by a one-word divisor,
// each against the built-in quotient and remainder. RapidCheck's integers
// weight 0, 1 and the extremes.
RC_GTEST_PROP(FxWideDivision, LongDivisionFormsEqualTheBuiltInDivision, ()) {
  const auto v = *rc::gen::arbitrary<std::uint32_t>() | 0x80000000U;
  const auto raw = *rc::gen::arbitrary<std::uint64_t>();
  // u < v 2^32: below it as drawn, or its top edge, or a quotient with the largest remainder.
  const std::uint64_t top = std::uint64_t{v} << 32U;
  std::uint64_t u = raw % top;
  switch (*rc::gen::inRange(0, 3)) {
    case 0:
      u = top - 1U - (raw % 4096U);
      break;
    case 1:
      u = (std::uint64_t{static_cast<std::uint32_t>(raw)} * v) + (v - 1U);
      break;
    default:
      break;
  }
  const fx::wide::DivMod<std::uint32_t> by_reciprocal = fx::wide::divide_64_by_32_by_reciprocal(u, v);
  const fx::wide::DivMod<std::uint32_t> by_digits = fx::wide::divide_64_by_32_by_digits(u, v);
  RC_ASSERT(by_reciprocal.quotient == u / v);
  RC_ASSERT(by_reciprocal.remainder == u % v);
  RC_ASSERT(by_digits.quotient == u / v);
  RC_ASSERT(by_digits.remainder == u % v);
}

RC_GTEST_PROP(FxWideDivision, OneWordDivisorEqualsTheBuiltInDivision, ()) {
  const auto num = *rc::gen::arbitrary<std::uint64_t>();
  const auto shift = static_cast<std::uint32_t>(*rc::gen::inRange(0, 32));
  const std::uint32_t den = (*rc::gen::arbitrary<std::uint32_t>() >> shift) | 1U;
  const fx::wide::DivMod<std::uint64_t> qr = fx::wide::divmod_by_word_normalising(num, den);
  RC_ASSERT(qr.quotient == num / den);
  RC_ASSERT(qr.remainder == num % den);
}

// ------------------------------------------------------------ exhaustive

// sqrt in Q15_16 over the 2^20 smallest and the 2^16 largest raw values,
// and the 4096 negative raw values next to zero, and min.
TEST(FxExhaustive, SqrtQ15_16Edges) {
  std::int64_t failures = 0;
  std::string first;
  auto run = [&](std::int32_t raw) {
    const std::string e = check_sqrt<fx::Q15_16, fx::Q15_16>(fx::Q15_16::from_raw(raw));
    if (!e.empty() && failures++ == 0) {
      first = e;
    }
  };
  for (std::int32_t r = -4096; r < (1 << 20); ++r) {
    run(r);
  }
  for (std::int32_t r = INT32_MAX - (1 << 16); r < INT32_MAX; ++r) {
    run(r);
  }
  run(INT32_MAX);
  run(INT32_MIN);
  EXPECT_EQ(failures, 0) << first;
}

// mul and div of every Q<int32, 4> pair in [-512, 512)^2 raw.
TEST(FxExhaustive, MulDivSmallFormat) {
  using Q4 = fx::Q<std::int32_t, 4>;
  std::int64_t failures = 0;
  std::string first;
  for (std::int32_t a = -512; a < 512; ++a) {
    for (std::int32_t b = -512; b < 512; ++b) {
      std::string e = check_mul<Q4>(Q4::from_raw(a), Q4::from_raw(b));
      if (e.empty()) {
        e = check_div<Q4>(Q4::from_raw(a), Q4::from_raw(b));
      }
      if (!e.empty() && failures++ == 0) {
        first = e;
      }
    }
  }
  EXPECT_EQ(failures, 0) << first;
}

// ------------------------------------------------------------ the checkers can fail

// The reference checkers must reject wrong results, or every property above
// would pass vacuously.
TEST(FxReference, CheckersRejectWrongResults) {
  fx::Status clean;
  fx::Status overflowed;
  overflowed.raise(fx::Flag::overflow);
  // 7/2 = 3.5 rounds to 4 (tie away from zero); -3.5 to -4.
  EXPECT_EQ(fxref::check_rounded(fx::Q15_16::from_raw(4), clean, false, 7, 2), "");
  EXPECT_NE(fxref::check_rounded(fx::Q15_16::from_raw(3), clean, false, 7, 2), "");  // tie toward zero
  EXPECT_EQ(fxref::check_rounded(fx::Q15_16::from_raw(-4), clean, true, 7, 2), "");
  EXPECT_NE(fxref::check_rounded(fx::Q15_16::from_raw(-3), clean, true, 7, 2), "");  // asymmetric
  EXPECT_NE(fxref::check_rounded(fx::Q15_16::from_raw(4), clean, true, 7, 2), "");   // wrong sign
  // 10/3 = 3.33: 3 is right, 4 is 0.67 LSB off.
  EXPECT_EQ(fxref::check_rounded(fx::Q15_16::from_raw(3), clean, false, 10, 3), "");
  EXPECT_NE(fxref::check_rounded(fx::Q15_16::from_raw(4), clean, false, 10, 3), "");
  // Right value, but a flag raised, or none where saturation was due.
  EXPECT_NE(fxref::check_rounded(fx::Q15_16::from_raw(3), overflowed, false, 10, 3), "");
  const U128 too_big = static_cast<U128>(1) << 40;
  EXPECT_EQ(fxref::check_rounded(fx::Q15_16::max(), overflowed, false, too_big, 1), "");
  EXPECT_NE(fxref::check_rounded(fx::Q15_16::max(), clean, false, too_big, 1), "");
  EXPECT_NE(fxref::check_rounded(fx::Q15_16::min(), overflowed, false, too_big, 1), "");
  EXPECT_EQ(fxref::check_exact(fx::Q15_16::from_raw(5), clean, 5), "");
  EXPECT_NE(fxref::check_exact(fx::Q15_16::from_raw(5), clean, 6), "");
  EXPECT_NE(fxref::check_exact(fx::Q15_16::max(), clean, static_cast<I128>(1) << 40), "");
}
