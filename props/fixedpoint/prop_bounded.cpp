// prop_bounded.cpp: the operations of bounded values (fixedpoint/bounded.hpp)
// against the exact integer reference: sums, differences and negations
// exact, products within half an LSB with ties away from zero, and each the
// bits of the checked operation of q.hpp (and the products' ARMv6-M form by
// 32-bit words), over the whole of their bounds.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <string>

#include "fx_reference.hpp"
#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/q.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fxref::I128;
using fxref::U128;
using Q6_25 = fx::Q<std::int32_t, 25>;

/// A raw value in [-m, m], its ends weighted in.
rc::Gen<std::int32_t> within(std::uint32_t m) {
  const auto top = static_cast<std::int32_t>(m);
  return rc::gen::weightedOneOf<std::int32_t>(
      {{1, rc::gen::element(top, -top, 0)}, {7, rc::gen::inRange<std::int32_t>(-top, top)}});
}

template <typename Out, typename QA, std::uint32_t A, typename QB, std::uint32_t B>
std::string check_product(std::int32_t ra, std::int32_t rb) {
  const auto a = fx::Bounded<QA, A>::trusted(ra);
  const auto b = fx::Bounded<QB, B>::trusted(rb);
  const auto r = fx::mul<Out>(a, b);
  const bool negative = (ra < 0) != (rb < 0);
  const U128 p = fxref::mag(ra) * fxref::mag(rb);
  const fxref::Rational x = fxref::scaled(negative, p, Out::frac_bits - QA::frac_bits - QB::frac_bits);
  const std::string e = fxref::check_rounded(r.q(), fx::Status{}, x.negative, x.num, x.den, x.num_too_big);
  if (!e.empty()) {
    return e;
  }
  fx::Status st;
  if ((fx::mul<Out>(a.q(), b.q(), st).raw() != r.raw()) || !st.ok()) {
    return "differs from fx::mul";
  }
  // The ARMv6-M forms, which the host does not take in mul: the words' one.
  constexpr std::int32_t kShift = (QA::frac_bits + QB::frac_bits) - Out::frac_bits;
  if constexpr (fx::detail::kRoundsInWords<kShift>) {
    if (fx::detail::product_rounded_by_words<kShift>(ra, rb) != r.raw()) {
      return "the words' form differs";
    }
  }
  const I128 mag = fxref::mag(r.raw());
  return (mag <= static_cast<I128>(decltype(r)::max_mag)) ? std::string() : "beyond its bound";
}

constexpr std::uint32_t kLink = 2U << 25U;   // 2 m in Q6.25
constexpr std::uint32_t kUnit = 1U << 30U;   // 1 in Q1.30
constexpr std::uint32_t kSlope = 942229340U;  // 3.51 in Q3.28

RC_GTEST_PROP(FxBounded, LengthTimesSineWithinHalfLsb, ()) {
  const std::int32_t a = *within(kLink);
  const std::int32_t b = *within(kUnit);
  const std::string error = check_product<Q6_25, Q6_25, kLink, fx::Q1_30, kUnit>(a, b);
  RC_ASSERT(error.empty());
}

RC_GTEST_PROP(FxBounded, PositionTimesSlopeWithinHalfLsb, ()) {
  const std::int32_t a = *within(5U * kLink);
  const std::int32_t b = *within(kSlope);
  const std::string error = check_product<Q6_25, Q6_25, 5U * kLink, fx::Q3_28, kSlope>(a, b);
  RC_ASSERT(error.empty());
}

RC_GTEST_PROP(FxBounded, CoarseProductsWithinHalfLsb, ()) {
  using Q15_16 = fx::Q<std::int32_t, 16>;
  const std::int32_t a = *within(0x7FFFFFFFU);
  const std::int32_t b = *within(kUnit);
  const std::string error = check_product<Q15_16, Q15_16, 0x7FFFFFFFU, fx::Q1_30, kUnit>(a, b);
  RC_ASSERT(error.empty());
}

RC_GTEST_PROP(FxBounded, SumsDifferencesNegationsAreExact, ()) {
  using Half = fx::Bounded<Q6_25, 0x3FFFFFFFU>;
  const Half a = Half::trusted(*within(Half::max_mag));
  const Half b = Half::trusted(*within(Half::max_mag));
  RC_ASSERT(static_cast<I128>(fx::add(a, b).raw()) == static_cast<I128>(a.raw()) + b.raw());
  RC_ASSERT(static_cast<I128>(fx::sub(a, b).raw()) == static_cast<I128>(a.raw()) - b.raw());
  RC_ASSERT(static_cast<I128>(fx::neg(a).raw()) == -static_cast<I128>(a.raw()));
}

RC_GTEST_PROP(FxBounded, BoundToIsTheIdentityWithinAndSaturatesBeyond, ()) {
  const std::int32_t v = *rc::gen::arbitrary<std::int32_t>();
  fx::Status st;
  const auto b = fx::bound_to<kLink>(Q6_25::from_raw(v), st);
  const I128 m = kLink;
  const I128 expected = (v > m) ? m : ((v < -m) ? -m : v);
  RC_ASSERT(static_cast<I128>(b.raw()) == expected);
  RC_ASSERT(st.has(fx::Flag::overflow) == (static_cast<I128>(v) != expected));
}

}  // namespace
