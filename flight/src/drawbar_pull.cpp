// Drawbar pull from the vehicle force balance; see drawbar_pull.hpp and
// docs/rover-loads.md, section 6. Twin: ground/reference/src/rover_loads.cpp.
#include "sinkwatch/flight/drawbar_pull.hpp"

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"

namespace sinkwatch {
namespace flight {
namespace {


constexpr Ratio kMaxSlip{fx::constant<RatioQ>(1.0)};

DrawbarResult failed(DrawbarStatus status) noexcept {
  DrawbarResult r{};
  r.status = status;
  return r;
}

/// Not 0 unless 0 < r <= kMaxDpMaxRatio (2^25 raw): r - 1 below 2^25 as an
/// unsigned value, which a non-positive r wraps beyond.
std::uint32_t ratio_out_of_range(Ratio r) noexcept {
  static_assert(kMaxDpMaxRatio.raw() == std::int32_t{0x2000000}, "the ratio's range is (0, 2^25] raw");
  return (static_cast<std::uint32_t>(r.raw()) - 1U) >> 25U;
}

/// The acceleration, the slope and the slip are in their accepted ranges
/// (the parameters are already validated).
bool motion_in_range(const RoverParams& params, const DrawbarInput& input) noexcept {
  const bool accel_ok = (input.accel_mps2 <= kMaxAbsAccel) && (input.accel_mps2.raw() >= -kMaxAbsAccel.raw());
  const bool pitch_ok = (input.pitch_rad <= params.attitude_limit_rad) &&
                        (input.pitch_rad.raw() >= -params.attitude_limit_rad.raw());
  const bool slip_ok = !input.slip_known || (input.slip <= kMaxSlip);
  return accel_ok && pitch_ok && slip_ok;
}

/// How the shares are taken: every wheel at DP_max (saturated), or split by
/// load with the fraction's one-word remainder (the sum at most
/// kWordRemainderSum: every validated rover) or its wide one.
enum class Split : std::uint8_t { saturated, by_word, wide };

/// The magnitude of the share of |total| (raw Q31.32) of a wheel of raw
/// load `load` in the form `kSplit` picks: share_or_all of load_fraction's
/// fraction, bit for bit. Split by word, a load below the sum has a
/// one-word fraction (load_fraction_below_sum), and a load equal to the
/// sum (every other wheel unloaded) the fraction one, whose share is
/// |total| (share_magnitude): one test per wheel instead of the fraction's
/// carry into a second word and share_magnitude's test of it (round 17).
template <Split kSplit>
SW_FX_INLINE std::uint64_t share_of(std::uint64_t total_mag, std::uint32_t load, const detail::LoadSum& sum) noexcept {
  if constexpr (kSplit == Split::saturated) {
    return detail::share_or_all(total_mag, 0U, true);
  } else {
    if constexpr (kSplit == Split::by_word) {
      return (load == static_cast<std::uint32_t>(sum.raw))
                 ? total_mag
                 : detail::share_magnitude_below_one(total_mag, detail::load_fraction_below_sum(load, sum));
    } else {
      return detail::share_magnitude(total_mag, detail::load_fraction_wide(load, sum));
    }
  }
}

/// The six pulls into `dp_n` and the capped wheels into `capped_mask`;
/// not 0 when a pull overflowed. The shares are taken from |total| (raw
/// Q31.32), the load sum and the total's sign (false where saturated). One
/// loop for each way of splitting, the tests out of the loop (round 14: the
/// saturation; round 15: the fraction's form, tested per wheel before).
template <Split kSplit>
std::uint32_t pulls_into(const WheelLoadResult& loads, const DrawbarInput& input, std::uint64_t total_mag,
                         const detail::LoadSum& sum, bool negative, DrawbarPullN (&dp_n)[kWheelCount],
                         std::uint32_t& capped_mask) noexcept {
  // Bit i: wheel i capped, the wheels taken from the last so that each
  // bit is shifted in by one (round 17: a shift by i per wheel before).
  // Not 0: a pull overflowed (its overflow word, below 2^17). No branch per
  // wheel.
  std::uint32_t capped_bits = 0U;
  std::uint32_t overflow = 0U;
  for (std::uint32_t n = kWheelCount; n > 0U; --n) {
    const std::uint32_t i = n - 1U;
    // 0 <= load, 0 < ratio <= 2 (checked before).
    const auto load = static_cast<std::uint32_t>(loads.load_n[i].raw());
    constexpr bool kSaturated = kSplit == Split::saturated;
    const std::uint64_t share = share_of<kSplit>(total_mag, load, sum);
    const detail::WheelPull pull =
        detail::wheel_pull(share, load, static_cast<std::uint32_t>(input.dp_max_ratio[i].raw()), negative);
    dp_n[i] = DrawbarPullN::from_raw(pull.dp_raw);
    // Saturated, no share is limited: every wheel is at DP_max,i.
    const bool capped = pull.capped && !kSaturated;
    capped_bits = (capped_bits << 1U) | (capped ? 1U : 0U);
    // Split by load, a pull's magnitude is at most its share's, which is at
    // most |total|'s (share_magnitude), with the total's sign: it leaves
    // Q15.16 only where the total's own rescale does, which pulls_in_range
    // refuses as well. Only DP_max,i itself (saturated) can leave it alone
    // (round 16: the overflow word was ORed for every wheel and split).
    if constexpr (kSaturated) {
      overflow |= pull.overflow;
    }
  }
  capped_mask = capped_bits;
  return overflow;
}

/// A load's raw Q15.16 value as an unsigned word (the load is >= 0).
SW_FX_INLINE std::uint32_t load_raw(WheelLoadN load_n) noexcept {
  return static_cast<std::uint32_t>(load_n.raw());
}

/// sum W in raw Q15.16 units: six values in [0, 2^31) sum below 2^34. As
/// three pairs, each below 2^32, added in one word (round 15: a loop of six
/// 64-bit additions, two words carried per wheel, before).
std::uint64_t load_sum_raw(const WheelLoadN (&load_n)[kWheelCount]) noexcept {
  static_assert(kWheelCount == 6U, "three pairs of loads below");
  const std::uint32_t front = load_raw(load_n[0U]) + load_raw(load_n[1U]);
  const std::uint32_t middle = load_raw(load_n[2U]) + load_raw(load_n[3U]);
  const std::uint32_t rear = load_raw(load_n[4U]) + load_raw(load_n[5U]);
  return (std::uint64_t{front} + middle) + rear;
}

/// No number: the pulls already written are taken back to zero. Out of
/// line, as no cycle of a validated rover overflows (docs/coverage.md).
[[gnu::noinline]] DrawbarStatus refused_as_overflow(DrawbarPullN (&dp_n)[kWheelCount]) noexcept {
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    dp_n[i] = DrawbarPullN::zero();
  }
  return DrawbarStatus::overflow;
}

/// The pulls for usable loads and parameters that passed
/// validate_rover_params().
DrawbarResult pulls_of_valid(const RoverParams& params, const WheelLoadResult& loads,
                             const DrawbarInput& input) noexcept {
  if (!motion_in_range(params, input)) {
    return failed(DrawbarStatus::invalid_input);
  }
  // Each ratio and load checked, the checks ORed and tested once after the
  // loop (round 14: a loop of its own, a branch per test, before); a bad one
  // is invalid_input whatever the sum.
  std::uint32_t out_of_range = 0U;  // not 0: a ratio or a load out of range
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    const auto load = static_cast<std::uint32_t>(loads.load_n[i].raw());
    out_of_range |= ratio_out_of_range(input.dp_max_ratio[i]) | (load >> 31U);  // the load's sign
  }
  if (out_of_range != 0U) {
    return failed(DrawbarStatus::invalid_input);
  }
  // The loads' sine when they were computed at this pitch (the step's case):
  // the same bits as computing it here. fx::sin cannot fail (trig.hpp: every
  // representable angle), so its status is not read (the coverage run of
  // round 15 found the refusal that read it never taken).
  fx::Status sine_status;
  const fx::Q1_30 sin_pitch =
      (loads.pitch_rad == input.pitch_rad) ? loads.sin_pitch : fx::sin(input.pitch_rad.q(), sine_status);
  DrawbarResult r{};
  r.status = detail::pulls_in_range(params, loads, input, sin_pitch, r.dp_n, r.total_n, r.capped_mask);
  return r;
}

}  // namespace

DrawbarStatus detail::pulls_in_range(const RoverParams& params, const WheelLoadResult& loads,
                                     const DrawbarInput& input, fx::Q1_30 sin_pitch,
                                     DrawbarPullN (&dp_n)[kWheelCount], DrawbarPullN& total_n,
                                     std::uint8_t& capped_mask) noexcept {
  const std::uint64_t load_sum = load_sum_raw(loads.load_n);
  if (load_sum == 0U) {
    return DrawbarStatus::invalid_loads;  // dp_n untouched: the caller's zeros
  }
  // m (a + g sin(pitch)): the along-path force the tractions must supply.
  // Mass and gravity are positive (validated), |a| <= 10 (in range).
  const std::int64_t total = detail::along_force_raw(static_cast<std::uint32_t>(params.mass_kg.raw()),
                                                     static_cast<std::uint32_t>(params.gravity_mps2.raw()),
                                                     sin_pitch.raw(), input.accel_mps2.raw());
  const std::uint64_t total_mag = fx::detail::magnitude(total);
  const detail::WheelPull total_pull = detail::rounded_pull(total_mag, total < 0);
  const bool saturated = input.slip_known && (input.slip >= params.high_slip);
  const detail::LoadSum sum = detail::load_sum_of(load_sum);
  std::uint32_t mask = 0U;
  // Saturated, every wheel is at +DP_max,i: the total's sign is not used.
  std::uint32_t overflowed = total_pull.overflow;
  if (saturated) {
    overflowed |= pulls_into<Split::saturated>(loads, input, 0U, sum, false, dp_n, mask);
  } else if (load_sum <= detail::kWordRemainderSum) {
    overflowed |= pulls_into<Split::by_word>(loads, input, total_mag, sum, total < 0, dp_n, mask);
  } else {
    overflowed |= pulls_into<Split::wide>(loads, input, total_mag, sum, total < 0, dp_n, mask);
  }
  if (overflowed != 0U) {
    return refused_as_overflow(dp_n);
  }
  total_n = DrawbarPullN::from_raw(total_pull.dp_raw);
  capped_mask = static_cast<std::uint8_t>(mask);
  if (saturated) {
    return DrawbarStatus::saturated;
  }
  return (mask != 0U) ? DrawbarStatus::capped : DrawbarStatus::ok;
}

DrawbarResult drawbar_pulls(const PreparedParameters& prepared, const WheelLoadResult& loads,
                            const DrawbarInput& input) noexcept {
  if (loads.status != WheelLoadStatus::ok) {
    return failed(DrawbarStatus::invalid_loads);
  }
  if (!prepared.ready()) {
    return failed(DrawbarStatus::invalid_input);
  }
  return pulls_of_valid(prepared.rover(), loads, input);
}

}  // namespace flight
}  // namespace sinkwatch
