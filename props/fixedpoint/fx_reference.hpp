// fx_reference.hpp: generators and exact references for the fixed-point
// property tests (host only, x86-64: the exact reference is GCC/clang's
// unsigned __int128, which the library itself must not use).
//
// Generators produce RAW integers, with the edges weighted in: zero, +-1 LSB,
// min, min+1, max, max-1, half-range, powers of two and their neighbours,
// rounding ties (low bits 100..0), values of every bit length, and uniformly
// random full-range values. RapidCheck's double generator never reaches the
// edges of a fixed-point format.
//
// References are exact: an operation's real result is a rational num/den
// (both magnitudes < 2^127 in every format tested), the expected raw result
// is that rational rounded half away from zero, and the documented bound
// |result - exact| <= 1/2 LSB is asserted in integers as
// 2 |result * den - num| <= den. Checkers return "" on success and a
// description of the mismatch otherwise, so that RC_ASSERT and EXPECT_EQ show
// it.
#ifndef SINKWATCH_PROPS_FIXEDPOINT_FX_REFERENCE_HPP
#define SINKWATCH_PROPS_FIXEDPOINT_FX_REFERENCE_HPP

#include <rapidcheck.h>

#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"

namespace fxref {

namespace fx = sinkwatch::fx;

__extension__ typedef unsigned __int128 U128;
__extension__ typedef __int128 I128;

inline std::string to_string(U128 v) {
  if (v == 0) {
    return "0";
  }
  std::string s;
  while (v != 0) {
    s.insert(s.begin(), static_cast<char>('0' + static_cast<int>(v % 10)));
    v /= 10;
  }
  return s;
}
inline std::string to_string(I128 v) {
  if (v < 0) {
    return "-" + to_string(static_cast<U128>(0) - static_cast<U128>(v));
  }
  return to_string(static_cast<U128>(v));
}

inline U128 mag(I128 v) { return (v < 0) ? (static_cast<U128>(0) - static_cast<U128>(v)) : static_cast<U128>(v); }

inline int bit_length(U128 v) {
  int n = 0;
  while (v != 0) {
    v >>= 1;
    ++n;
  }
  return n;
}

inline U128 pow2(int n) { return static_cast<U128>(1) << n; }

// ---------------------------------------------------------------- generators

/// Every bit pattern with equal probability (RapidCheck's arbitrary is scaled
/// by the size; at the nominal size it draws all bits).
template <typename S>
rc::Gen<S> full_range() {
  return rc::gen::resize(rc::kNominalSize, rc::gen::arbitrary<S>());
}

/// A random value of a random bit length, with a random sign: small and
/// large magnitudes equally likely.
template <typename S>
rc::Gen<S> any_length() {
  using US = typename std::make_unsigned<S>::type;
  constexpr int bits = std::numeric_limits<US>::digits;
  return rc::gen::apply(
      [](int len, US random_bits, bool negative) {
        const US masked = (len >= bits) ? random_bits : static_cast<US>(random_bits & ((US{1} << len) - 1U));
        const S v = static_cast<S>(masked);  // two's complement wrap (C++20 semantics, GCC/clang in C++17)
        return (negative && v != std::numeric_limits<S>::min()) ? static_cast<S>(-v) : v;
      },
      rc::gen::inRange(0, bits + 1), full_range<US>(), rc::gen::arbitrary<bool>());
}

/// +-2^k and +-2^k +- 1.
template <typename S>
rc::Gen<S> near_powers_of_two() {
  using US = typename std::make_unsigned<S>::type;
  constexpr int bits = std::numeric_limits<US>::digits;
  return rc::gen::apply(
      [](int k, int delta, bool negative) {
        const I128 v = (static_cast<I128>(1) << k) + delta;
        const I128 s = negative ? -v : v;
        const I128 lo = std::numeric_limits<S>::min();
        const I128 hi = std::numeric_limits<S>::max();
        return static_cast<S>((s < lo) ? lo : ((s > hi) ? hi : s));
      },
      rc::gen::inRange(0, bits), rc::gen::inRange(-1, 2), rc::gen::arbitrary<bool>());
}

/// Values whose low `s` bits are exactly 100..0: rounding ties for a right
/// shift by s.
template <typename S>
rc::Gen<S> ties() {
  using US = typename std::make_unsigned<S>::type;
  constexpr int bits = std::numeric_limits<US>::digits;
  return rc::gen::apply(
      [](int s, US high, bool negative) {
        const US half = static_cast<US>(US{1} << (s - 1));
        const US v = static_cast<US>((static_cast<US>(high << s) | half) & (std::numeric_limits<US>::max() >> 1U));
        const S sv = static_cast<S>(v);
        return negative ? static_cast<S>(-sv) : sv;
      },
      rc::gen::inRange(1, bits - 1), full_range<US>(), rc::gen::arbitrary<bool>());
}

/// The fixed edges of a storage type.
template <typename S>
rc::Gen<S> edges() {
  using L = std::numeric_limits<S>;
  return rc::gen::element<S>(S{0}, S{1}, S{-1}, S{2}, S{-2}, L::max(), L::min(), static_cast<S>(L::max() - 1),
                             static_cast<S>(L::min() + 1), static_cast<S>(L::max() / 2), static_cast<S>(L::min() / 2),
                             static_cast<S>(L::max() / 2 + 1), static_cast<S>(L::min() / 2 - 1));
}

/// The raw-value generator used by every property.
template <typename S>
rc::Gen<S> raw() {
  return rc::gen::weightedOneOf<S>({{3, edges<S>()},
                                    {4, full_range<S>()},
                                    {4, any_length<S>()},
                                    {2, near_powers_of_two<S>()},
                                    {2, ties<S>()}});
}

template <typename QT>
rc::Gen<QT> q() {
  return rc::gen::map(raw<typename QT::storage_type>(), [](typename QT::storage_type r) { return QT::from_raw(r); });
}

/// Clamps an exact value into storage S (for building values next to an
/// overflow boundary).
template <typename S>
S clamp_to(I128 v) {
  const I128 lo = std::numeric_limits<S>::min();
  const I128 hi = std::numeric_limits<S>::max();
  return static_cast<S>((v < lo) ? lo : ((v > hi) ? hi : v));
}

// ---------------------------------------------------------------- references

template <typename QT>
constexpr I128 raw_min() {
  return static_cast<I128>(std::numeric_limits<typename QT::storage_type>::min());
}
template <typename QT>
constexpr I128 raw_max() {
  return static_cast<I128>(std::numeric_limits<typename QT::storage_type>::max());
}

inline std::string describe(const char* what, const std::string& detail) { return std::string(what) + ": " + detail; }

/// Checks an exact (unrounded-free) result: the exact integer raw value
/// `exact` (any size) must come back unchanged with a clean status, or
/// saturated with Flag::overflow when it does not fit.
template <typename QT>
std::string check_exact(QT result, fx::Status status, I128 exact, bool exact_too_big = false) {
  const I128 r = result.raw();
  if (exact_too_big || exact > raw_max<QT>() || exact < raw_min<QT>()) {
    const I128 sat = (exact < 0) ? raw_min<QT>() : raw_max<QT>();
    if (!status.has(fx::Flag::overflow) || r != sat) {
      return describe("expected saturation", "exact " + to_string(exact) + " got " + to_string(r) +
                                                 " status " + std::to_string(status.bits()));
    }
    if (status.bits() != static_cast<std::uint8_t>(fx::Flag::overflow)) {
      return describe("extra flags on overflow", std::to_string(status.bits()));
    }
    return "";
  }
  if (!status.ok() || r != exact) {
    return describe("expected exact", "exact " + to_string(exact) + " got " + to_string(r) + " status " +
                                          std::to_string(status.bits()));
  }
  return "";
}

/// Checks a rounded result against the exact real value (negative ? -1 : 1)
/// * num / den in raw units of QT (num, den magnitudes, den > 0):
///  * status clean and |result - exact| <= 1/2 LSB, ties away from zero,
///    and the sign of the exact value (or zero), whenever the correctly
///    rounded value fits;
///  * else saturation to min or max by sign, with Flag::overflow only.
/// `num_too_big` says that num did not fit 127 bits (the value is then far
/// beyond every format).
template <typename QT>
std::string check_rounded(QT result, fx::Status status, bool negative, U128 num, U128 den,
                          bool num_too_big = false) {
  const I128 r = result.raw();
  // Built only on failure: the exhaustive tests call this millions of times.
  const auto ctx = [&]() {
    return " exact " + std::string(negative ? "-" : "") + to_string(num) + "/" + to_string(den) + " got " +
           to_string(r) + " status " + std::to_string(status.bits());
  };
  bool fits = false;
  if (!num_too_big) {
    // The correctly rounded magnitude, ties away from zero.
    U128 q = num / den;
    const U128 rem = num % den;
    if (rem >= den - rem) {
      ++q;
    }
    const U128 limit = negative ? mag(raw_min<QT>()) : static_cast<U128>(raw_max<QT>());
    fits = (q <= limit);
  }
  if (!fits) {
    const I128 sat = negative ? raw_min<QT>() : raw_max<QT>();
    if (!status.has(fx::Flag::overflow) || r != sat) {
      return describe("expected saturation", ctx());
    }
    if (status.bits() != static_cast<std::uint8_t>(fx::Flag::overflow)) {
      return describe("extra flags on overflow", ctx());
    }
    return "";
  }
  if (!status.ok()) {
    return describe("unexpected flag", ctx());
  }
  // Sign: the result is zero or has the sign of the exact value.
  if ((r < 0 && !negative) || (r > 0 && negative)) {
    return describe("wrong sign", ctx());
  }
  // Bound: 2 |(|r| den) - num| <= den, in integers.
  const U128 prod = mag(r) * den;
  const U128 diff = (prod > num) ? (prod - num) : (num - prod);
  if (diff > den - diff || diff > den) {
    return describe("more than 1/2 LSB off", ctx());
  }
  // Tie rule: exactly halfway goes away from zero.
  if (diff == den - diff && prod < num) {
    return describe("tie not rounded away from zero", ctx());
  }
  return "";
}

/// Exact real value of a * b in raw units of Out as num/den.
struct Rational {
  bool negative;
  U128 num;
  U128 den;
  bool num_too_big;
};

/// |a| * 2^shift as a Rational with den = 1 (shift >= 0) or 2^-shift.
inline Rational scaled(bool negative, U128 m, int shift) {
  if (shift >= 0) {
    if (m != 0 && bit_length(m) + shift > 127) {
      return Rational{negative, 0, 1, true};
    }
    return Rational{negative, m << shift, 1, false};
  }
  return Rational{negative, m, pow2(-shift), false};
}

}  // namespace fxref

#endif  // SINKWATCH_PROPS_FIXEDPOINT_FX_REFERENCE_HPP
