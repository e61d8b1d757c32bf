// drawbar_pull.hpp: each wheel's drawbar pull DP from the rover's motion, the
// paper's key technology 4 ("drawbar-pull estimation from the rover's
// behaviour", section 7), for Eq. 15.
//
// Along the path the wheels' net tractions balance gravity and inertia:
//
//     sum_i DP_i = m (a + g sin(pitch))          (docs/rover-loads.md, 6.1)
//
// with a the acceleration along the path (IMU or odometry / VO) and pitch the
// path slope. The total is split in proportion to the wheel loads,
// DP_i = total W_i / sum(W), so that every wheel has the same DP/W, the
// paper's own normalisation (choice justified in docs/rover-loads.md, 6.2).
// Each share is limited to +-DP_max,i = +-(DP_max/W)_i W_i, the soil-bin
// plateau at high slip (Fig. 10); when the measured slip is at or above the
// high-slip level, every wheel is taken at DP_max,i, as the paper proposes.
//
// Fixed point: total in Q31.32, shares rounded once to Q15.16; the error
// bound is in docs/rover-loads.md, section 7, asserted by
// props/rover/prop_drawbar_pull.cpp against ground/reference rover_loads.hpp.
#ifndef SINKWATCH_FLIGHT_DRAWBAR_PULL_HPP
#define SINKWATCH_FLIGHT_DRAWBAR_PULL_HPP

#include <cstdint>
#include <limits>

#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/units.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace sinkwatch {
namespace flight {

/// Accepted magnitude of the along-path acceleration: far above anything a
/// rover does at walking pace, so a larger value is a sensor fault.
constexpr AccelMps2 kMaxAbsAccel{fx::constant<AccelQ>(10.0)};
/// Accepted range of DP_max/W (the correction table's own range).
constexpr Ratio kMaxDpMaxRatio{fx::constant<RatioQ>(2.0)};

struct DrawbarInput {
  AccelMps2 accel_mps2;  ///< along the path (body x), positive speeding up forward
  AngleRad pitch_rad;    ///< path slope; the body pitch, positive nose up
  bool slip_known{false};  ///< whether `slip` holds a measurement this cycle
  Ratio slip;            ///< rover slip 1 - v/(r w), at most 1
  Ratio dp_max_ratio[kWheelCount];  ///< (DP_max/W) at each wheel's load, (0, 2]
};

enum class DrawbarStatus : std::uint8_t {
  ok = 0U,
  capped = 1U,          ///< a share beyond +-DP_max was limited (see capped_mask)
  saturated = 2U,       ///< slip at or above params.high_slip: every wheel at DP_max
  invalid_loads = 3U,   ///< the wheel loads were not ok
  invalid_input = 4U,   ///< acceleration, slope, slip or a ratio out of range
  overflow = 5U,
};

struct DrawbarResult {
  DrawbarPullN dp_n[kWheelCount];  ///< zero unless status is ok, capped or saturated
  DrawbarPullN total_n;            ///< m (a + g sin(pitch)) before any limit
  std::uint8_t capped_mask{0U};    ///< bit i: wheel i was limited
  DrawbarStatus status{DrawbarStatus::invalid_input};  ///< a default result is never usable
};

/// True for the statuses whose dp_n may be used.
[[nodiscard]] constexpr bool usable(DrawbarStatus s) noexcept {
  return (s == DrawbarStatus::ok) || (s == DrawbarStatus::capped) || (s == DrawbarStatus::saturated);
}

namespace detail {
// The arithmetic of drawbar_pulls() on raw integers, in 32 x 32 -> 64-bit
// products: bit for bit the fx operations on Q31.32 it replaced in session
// 18 (their 128-bit products and per-operation saturation tests cost the
// Cortex-M0 about 460 instructions per wheel). Here, not in the source, so
// that host_tests/rover/test_drawbar_pull.cpp can compare each with that
// chain of fx operations.

/// p / 2^s for s in [0, 63], from shifts of 32-bit words (a 64-bit shift by
/// a run-time count is a library call on 32-bit cores).
[[nodiscard]] constexpr std::uint64_t shr_by_words(std::uint64_t p, std::uint32_t s) noexcept {
  const auto hi = static_cast<std::uint32_t>(p >> 32U);
  const auto lo = static_cast<std::uint32_t>(p);
  if (s >= 32U) {
    return hi >> (s - 32U);
  }
  if (s == 0U) {
    return p;
  }
  return (static_cast<std::uint64_t>(hi >> s) << 32U) | (hi << (32U - s)) | (lo >> s);
}

/// The sum S of the loads in raw Q15.16 units (six values in [0, 2^31), so
/// 0 < S < 2^34) and its normalised reciprocal M 2^-(31 + n), n =
/// bit_length(S) (fixedpoint/reciprocal.hpp): one reciprocal per call
/// instead of a 64-bit library division.
struct LoadSum {
  std::uint64_t raw;
  std::uint32_t mantissa;  ///< M
  std::uint32_t shift;     ///< n - 1: L M / 2^(n - 1) is within 2 of L 2^32 / S
};

/// The sum `raw` (> 0) and its reciprocal.
[[nodiscard]] constexpr LoadSum load_sum_of(std::uint64_t raw) noexcept {
  const fx::NormalisedReciprocal r = fx::normalised_reciprocal(raw, 0);
  // The reciprocal's scale is 31 + n (no fraction bits), n >= 1: the sum is positive.
  return LoadSum{raw, r.mantissa, static_cast<std::uint32_t>(r.scale - 32)};
}

/// The largest sum whose remainders fit 32 bits in load_fraction: 3 S <=
/// 2^32. Every validated rover's loads sum below it (m g <= 10 kN, 6.6e8 raw
/// against 1.4e9).
inline constexpr std::uint64_t kWordRemainderSum{0x55555555U};

/// W_i / sum W in Q31.32 (raw), bit for bit fx::div(W_i, sum W) of the loads
/// widened to Q31.32: both are whole multiples of 2^-16, so the quotient is
/// round(N / S), N = L 2^32, of the raw Q15.16 integers L <= S (L < 2^31,
/// S < 2^34), rounded half up as fx::div rounds a magnitude. Exact, with
/// 32 x 32 and 64 x 64 -> 64-bit products only (no 128-bit product, no
/// division; docs/performance.md, session 13):
///  * estimate q' = floor(L M / 2^(n - 1)) ~ N / S. M is within 2^-31
///    relative of 2^(31 + n) / S (below it when S < 2^32, where the
///    normalised divisor is exact; either side when the normalisation drops
///    S's low bits), and N / S <= 2^32, so q' is within 2 of q = floor(N / S);
///  * q' S (< 2^63 + 2 S, no wrap) against N: at most two steps down, then
///    two up, give q and the remainder r = N - q S exactly;
///  * rounding up when r >= S - r.
/// Where 3 S <= 2^32 (kWordRemainderSum; session 18) the remainder is one
/// 32-bit word: S < 2^32 puts q' at or below q, so N - q' S is in [0, 3 S),
/// and it is the low word of N - q' S, that is 0 - q'_lo S mod 2^32 (N's low
/// word is zero): one 32-bit product, no step down, 32-bit steps up.
/// At most 2^32 (one): L <= S.
/// load_fraction where sum.raw <= kWordRemainderSum (the caller tests it,
/// once per cycle).
[[nodiscard]] SW_FX_INLINE constexpr std::uint64_t load_fraction_by_word(std::uint32_t load_raw,
                                                                         const LoadSum& sum) noexcept {
  const auto s = static_cast<std::uint32_t>(sum.raw);
  // S < 2^31: n <= 31 and L <= S < 2^n, so a = L 2^(32 - n) is below
  // 2^32, and floor(a M / 2^31) = floor(L M / 2^(n - 1)) is q' with a
  // shift by a constant (round 14: a 64-bit shift by n - 1 before).
  std::uint64_t q = fx::wide::mul_32x32_64(load_raw << (31U - sum.shift), sum.mantissa) >> 31U;
  std::uint32_t r = 0U - (static_cast<std::uint32_t>(q) * s);
  for (std::uint32_t step = 0U; step < 2U; ++step) {
    if (r >= s) {
      ++q;
      r -= s;
    }
  }
  return (r >= (s - r)) ? (q + 1U) : q;
}

/// load_fraction_by_word for a load below the sum (L < S <= kWordRemainderSum),
/// in one word (round 17). The same value: q = floor(L 2^32 / S) <=
/// L 2^32 / S <= 2^32 - 2^32 / S < 2^32 - 2 (S < 2^31), and the estimate
/// q' <= q, so neither q', its steps up nor the rounded q + 1 leave the word.
/// host_tests/rover/test_drawbar_pull.cpp
/// (LoadFractionBelowTheSumIsTheWordsForm) compares the two.
[[nodiscard]] SW_FX_INLINE constexpr std::uint32_t load_fraction_below_sum(std::uint32_t load_raw,
                                                                          const LoadSum& sum) noexcept {
  const auto s = static_cast<std::uint32_t>(sum.raw);
  auto q = static_cast<std::uint32_t>(fx::wide::mul_32x32_64(load_raw << (31U - sum.shift), sum.mantissa) >> 31U);
  std::uint32_t r = 0U - (q * s);
  for (std::uint32_t step = 0U; step < 2U; ++step) {
    if (r >= s) {
      ++q;
      r -= s;
    }
  }
  return q + ((r >= (s - r)) ? 1U : 0U);
}

/// load_fraction where sum.raw > kWordRemainderSum.
[[nodiscard]] constexpr std::uint64_t load_fraction_wide(std::uint32_t load_raw, const LoadSum& sum) noexcept {
  const std::uint64_t estimate = fx::wide::mul_32x32_64(load_raw, sum.mantissa);
  // By words where a 64-bit shift by a run-time count is a library call
  // (ARMv6-M, the cores without a widening multiply).
  std::uint64_t q = fx::wide::kMul32x32BySoftware ? shr_by_words(estimate, sum.shift) : (estimate >> sum.shift);
  const std::uint64_t n = static_cast<std::uint64_t>(load_raw) << 32U;
  std::uint64_t product = fx::wide::mul_64x64_low(q, sum.raw);
  for (std::uint32_t step = 0U; step < 2U; ++step) {
    if (product > n) {
      --q;
      product -= sum.raw;
    }
  }
  for (std::uint32_t step = 0U; step < 2U; ++step) {
    if ((n - product) >= sum.raw) {
      ++q;
      product += sum.raw;
    }
  }
  const std::uint64_t remainder = n - product;
  return (remainder >= (sum.raw - remainder)) ? (q + 1U) : q;
}

/// W_i / sum W (above) for any sum: drawbar_pulls() picks the form once per
/// cycle; the tests call this.
[[nodiscard]] constexpr std::uint64_t load_fraction(std::uint32_t load_raw, const LoadSum& sum) noexcept {
  return (sum.raw <= kWordRemainderSum) ? load_fraction_by_word(load_raw, sum) : load_fraction_wide(load_raw, sum);
}

/// a b for a < 2^16 from two 16 x 32-bit products, each below 2^32 (a
/// MULS on ARMv6-M) where mul_32x32_64 takes four. The host tests call it
/// directly, as it is not on the host's path.
[[nodiscard]] constexpr std::uint64_t mul_16x32_64_by_halves(std::uint32_t a, std::uint32_t b) noexcept {
  const std::uint32_t high = a * (b >> 16U);    // < 2^32: a < 2^16
  const std::uint32_t low = a * (b & 0xFFFFU);  // < 2^32
  return (static_cast<std::uint64_t>(high) << 16U) + low;
}

/// a b for a < 2^16: by halves where the core has no widening multiply
/// (ARMv6-M), else the one widening multiply.
[[nodiscard]] constexpr std::uint64_t mul_16x32_64(std::uint32_t a, std::uint32_t b) noexcept {
  if constexpr (fx::wide::kMul32x32BySoftware) {
    return mul_16x32_64_by_halves(a, b);
  } else {
    return fx::wide::mul_32x32_64(a, b);
  }
}

/// |t| f / 2^32 rounded half up, for |t| < 2^63 and a fraction f <= 2^32:
/// the magnitude of fx::mul(total, fraction) in Q31.32. With |t| = hi 2^32 +
/// lo it is hi f + round(lo f / 2^32) exactly (2^32 divides hi f 2^32), and
/// lo f + 2^31 < 2^64: two 32 x 32 -> 64-bit products, no 128-bit one. At
/// most |t|. A total of the validated rover is below 2^47 (20 kN): hi below
/// 2^16.
/// share_magnitude (below) for a fraction f < 2^32 (the split by word's,
/// load_fraction_below_sum).
[[nodiscard]] SW_FX_INLINE constexpr std::uint64_t share_magnitude_below_one(std::uint64_t t_mag,
                                                                            std::uint32_t f) noexcept {
  const auto hi = static_cast<std::uint32_t>(t_mag >> 32U);
  const std::uint64_t high = (hi <= 0xFFFFU) ? mul_16x32_64(hi, f) : fx::wide::mul_32x32_64(hi, f);
  return high + fx::wide::mul_32x32_rounded_high(static_cast<std::uint32_t>(t_mag), f);
}

[[nodiscard]] constexpr std::uint64_t share_magnitude(std::uint64_t t_mag, std::uint64_t fraction) noexcept {
  if ((fraction >> 32U) != 0U) {
    return t_mag;  // the whole load: f = 2^32
  }
  return share_magnitude_below_one(t_mag, static_cast<std::uint32_t>(fraction));
}

/// One wheel's pull in Q15.16 (raw), whether its share was capped, and
/// whether it left Q15.16 (the raw value is then not a pull: drawbar_pulls()
/// refuses the cycle's pulls with overflow).
struct WheelPull {
  std::int32_t dp_raw;
  bool capped;
  /// Not 0: the pull left Q15.16. The bits above the low word of the
  /// overflow test's sum (below), which drawbar_pulls() ORs over the wheels
  /// as they are, without a branch or a bool per wheel.
  std::uint32_t overflow;
};

/// A pull of magnitude `mag` (raw Q31.32, below 2^63) and sign `negative`
/// in Q15.16 (raw), bit for bit fx::rescale<Q15.16> of the signed Q31.32
/// value wherever that rescale does not overflow: the magnitude rounded
/// half up, m = (mag + 2^15) / 2^16 floored, then signed (a negative zero
/// is zero, as the rescale gives). It overflows beyond 2^31 - 1 (2^31 for
/// a negative pull): where m + 2^31 - 1, or m + 2^31 for a positive pull,
/// reaches 2^32 (`overflow` not 0; `capped` false). Nothing is saturated
/// (round 14): an overflowing pull is never used. pulls_in_range rounds
/// the total with it too (round 16: fx::rescale and its status before).
[[nodiscard]] SW_FX_INLINE constexpr WheelPull rounded_pull(std::uint64_t mag, bool negative) noexcept {
  const std::uint64_t scaled = (mag + (std::uint64_t{1U} << 15U)) >> 16U;  // < 2^48
  const std::uint64_t beyond = scaled + (negative ? 0x7FFFFFFFU : 0x80000000U);
  const auto value = static_cast<std::int64_t>(scaled);
  return WheelPull{static_cast<std::int32_t>(negative ? -value : value), false,
                   static_cast<std::uint32_t>(beyond >> 32U)};  // < 2^17
}

/// The magnitude of a wheel's share of the total for wheel_pull: the share
/// of |total| (< 2^63, raw Q31.32) at the fraction W_i / sum W (raw Q31.32,
/// <= 2^32, from load_fraction), or, where the slip is at or above the
/// high-slip level (`saturated`), the largest magnitude, which wheel_pull
/// limits to DP_max,i itself.
[[nodiscard]] constexpr std::uint64_t share_or_all(std::uint64_t total_mag, std::uint64_t fraction,
                                                   bool saturated) noexcept {
  return saturated ? ~std::uint64_t{0U} : share_magnitude(total_mag, fraction);
}

/// The pull of a wheel of raw load L (>= 0) and DP_max/W ratio r (in
/// (0, 2^25], Q7.24) from its share's magnitude `share` (share_or_all) and
/// the total's sign (`negative`; false where saturated). Bit for bit
///   cap   = fx::mul<Q31.32>(r, W_i widened to Q31.32),
///   share = fx::mul(total, fraction),
///   dp    = saturated ? cap : fx::clamp(share, fx::neg(cap), cap),
///   dp_n  = fx::rescale<Q15.16>(dp), capped when dp != share
/// wherever that rescale does not overflow (host_tests/rover/
/// test_drawbar_pull.cpp); `capped` is not read where saturated:
///  * cap = r L 2^16 / 2^24 rounded half up = (r L + 2^7) / 2^8 floored
///    (r L < 2^56, exact in 64 bits; 2^16 divides both terms);
///  * the clamp takes the share's magnitude down to cap, keeping its sign
///    (a negative zero rescales to zero, as fx::mul's positive zero does);
///  * the rescale is rounded_pull (above).
[[nodiscard]] SW_FX_INLINE constexpr WheelPull wheel_pull(std::uint64_t share, std::uint32_t load_raw, std::uint32_t ratio_raw,
                                             bool negative) noexcept {
  const std::uint64_t cap = (fx::wide::mul_32x32_64(ratio_raw, load_raw) + 128U) >> 8U;
  const bool capped = share > cap;
  WheelPull pull = rounded_pull(capped ? cap : share, negative);
  pull.capped = capped;
  return pull;
}

/// m (a + g sin(pitch)) in Q31.32 (raw) from the raw mass (Q15.16, in
/// (0, 1000 kg]), gravity (Q7.24, in (0, 10]), sine (Q1.30) and acceleration
/// (Q7.24, |a| <= 10): bit for bit
///   fx::mul<Q31.32>(m, fx::add(a widened, fx::mul<Q31.32>(g, sin widened))),
/// each product rounded half up on its magnitude:
///  * g sin: g |s| 4 / 2^24 = (g |s| + 2^21) / 2^22 floored (g < 2^28,
///    |s| <= 2^30: below 2^58);
///  * the sum A (|A| < 2^37) is exact;
///  * m |A| / 2^16 rounded (m < 2^26: below 2^63), from A's two words.
[[nodiscard]] constexpr std::int64_t along_force_raw(std::uint32_t mass_raw, std::uint32_t gravity_raw,
                                                     std::int32_t sin_raw, std::int32_t accel_raw) noexcept {
  const std::uint64_t g_sin_mag =
      (fx::wide::mul_32x32_64(gravity_raw, fx::detail::magnitude32(sin_raw)) + (std::uint64_t{1U} << 21U)) >> 22U;
  const auto g_sin = static_cast<std::int64_t>(g_sin_mag);
  const std::int64_t sum = (static_cast<std::int64_t>(accel_raw) * 256) + ((sin_raw < 0) ? -g_sin : g_sin);
  const std::uint64_t sum_mag = fx::detail::magnitude(sum);
  const std::uint64_t low = fx::wide::mul_32x32_64(mass_raw, static_cast<std::uint32_t>(sum_mag));
  const std::uint64_t high = fx::wide::mul_32x32_64(mass_raw, static_cast<std::uint32_t>(sum_mag >> 32U));
  const auto total = static_cast<std::int64_t>((high << 16U) + ((low + (std::uint64_t{1U} << 15U)) >> 16U));
  return (sum < 0) ? -total : total;
}

/// drawbar_pulls() past its range checks, for inputs already known to be in
/// range: loads with status ok of rover parameters that passed
/// validate_rover_params(), |a| <= kMaxAbsAccel, |pitch| <= the attitude
/// limit, slip <= 1, every load >= 0 and every ratio in (0, kMaxDpMaxRatio],
/// and `sin_pitch` the sine of the input's pitch. The per-cycle step (rover_step.cpp) calls it directly: its
/// stages have checked all of these (docs/rover-loads.md, section 8), so
/// checking them again was work without an outcome (round 15). The pulls
/// are written into `dp_n` (zero when the status is overflow, untouched for
/// invalid_loads), the total and the capped wheels into `total_n` and
/// `capped_mask` when the status is usable; the status is returned: ok,
/// capped, saturated, invalid_loads (every load zero) or overflow.
[[nodiscard]] DrawbarStatus pulls_in_range(const RoverParams& params, const WheelLoadResult& loads,
                                           const DrawbarInput& input, fx::Q1_30 sin_pitch,
                                           DrawbarPullN (&dp_n)[kWheelCount], DrawbarPullN& total_n,
                                           std::uint8_t& capped_mask) noexcept;

}  // namespace detail

/// The drawbar pulls for rover parameters checked once per load (prepare(),
/// prepared_params.hpp): invalid_input unless prepared.ready(), and no
/// validation per call.
[[nodiscard]] DrawbarResult drawbar_pulls(const PreparedParameters& prepared, const WheelLoadResult& loads,
                                          const DrawbarInput& input) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_DRAWBAR_PULL_HPP
