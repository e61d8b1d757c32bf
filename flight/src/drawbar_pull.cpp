// Drawbar pull from the vehicle force balance; see drawbar_pull.hpp and
// docs/rover-loads.md, section 6. Twin: ground/reference/src/rover_loads.cpp.
#include "sinkwatch/flight/drawbar_pull.hpp"

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using W = WideQ;

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

/// The six pulls into `dp_raw` and the capped wheels into `capped_mask`;
/// not 0 when a pull overflowed. The shares are taken from |total| (raw
/// Q31.32), the load sum and the total's sign (false where saturated). One
/// loop for each of kSaturated's values, the test out of the loop (round 14).
template <bool kSaturated>
std::uint32_t pulls_into(const WheelLoadResult& loads, const DrawbarInput& input, std::uint64_t total_mag,
                         const detail::LoadSum& sum, bool negative, std::int32_t (&dp_raw)[kWheelCount],
                         std::uint32_t& capped_mask) noexcept {
  // Bit i: wheel i capped; bits kWheelCount and up: a pull overflowed (its
  // overflow word, below 2^17, shifted there). One accumulator, no branch
  // per wheel.
  std::uint32_t flags = 0U;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    // 0 <= load, 0 < ratio <= 2 (checked before).
    const auto load = static_cast<std::uint32_t>(loads.load_n[i].raw());
    const std::uint64_t share =
        detail::share_or_all(total_mag, kSaturated ? 0U : detail::load_fraction(load, sum), kSaturated);
    const detail::WheelPull pull =
        detail::wheel_pull(share, load, static_cast<std::uint32_t>(input.dp_max_ratio[i].raw()), negative);
    dp_raw[i] = pull.dp_raw;
    // Saturated, no share is limited: every wheel is at DP_max,i.
    const bool capped = pull.capped && !kSaturated;
    flags |= ((capped ? 1U : 0U) << i) | (pull.overflow << kWheelCount);
  }
  capped_mask = flags & ((1U << kWheelCount) - 1U);
  return flags >> kWheelCount;
}

/// The pulls for usable loads and parameters that passed
/// validate_rover_params().
DrawbarResult pulls_of_valid(const RoverParams& params, const WheelLoadResult& loads,
                             const DrawbarInput& input) noexcept {
  if (!motion_in_range(params, input)) {
    return failed(DrawbarStatus::invalid_input);
  }
  // sum W in raw Q15.16 units: six values in [0, 2^31) sum below 2^34. In
  // the loop that checks each ratio and load, the checks ORed and tested
  // once after it (round 14: a loop of its own, a branch per test, before);
  // a bad one is invalid_input whatever the sum.
  std::uint64_t load_sum = 0U;
  std::uint32_t out_of_range = 0U;  // not 0: a ratio or a load out of range
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    const auto load = static_cast<std::uint32_t>(loads.load_n[i].raw());
    out_of_range |= ratio_out_of_range(input.dp_max_ratio[i]) | (load >> 31U);  // the load's sign
    load_sum += load;
  }
  if (out_of_range != 0U) {
    return failed(DrawbarStatus::invalid_input);
  }
  if (load_sum == 0U) {
    return failed(DrawbarStatus::invalid_loads);
  }
  fx::Status st;
  // m (a + g sin(pitch)): the along-path force the tractions must supply.
  // The loads' sine when they were computed at this pitch (the step's case):
  // the same bits as computing it here.
  const fx::Q1_30 sin_pitch =
      (loads.pitch_rad == input.pitch_rad) ? loads.sin_pitch : fx::sin(input.pitch_rad.q(), st);
  // Mass and gravity are positive (validated), |a| <= 10 (motion_in_range).
  const std::int64_t total = detail::along_force_raw(static_cast<std::uint32_t>(params.mass_kg.raw()),
                                                     static_cast<std::uint32_t>(params.gravity_mps2.raw()),
                                                     sin_pitch.raw(), input.accel_mps2.raw());
  const DrawbarPullN total_n{fx::rescale<LoadQ>(W::from_raw(total), st)};
  const bool saturated = input.slip_known && (input.slip >= params.high_slip);
  const detail::LoadSum sum = detail::load_sum_of(load_sum);
  // Every pull is written before it is read: no zeroed array filled in.
  std::int32_t dp_raw[kWheelCount];
  std::uint32_t capped_mask = 0U;
  // Saturated, every wheel is at +DP_max,i: the total's sign is not used.
  const std::uint32_t overflowed =
      saturated ? pulls_into<true>(loads, input, 0U, sum, false, dp_raw, capped_mask)
                : pulls_into<false>(loads, input, fx::detail::magnitude(total), sum, total < 0, dp_raw, capped_mask);
  if ((overflowed != 0U) || !st.ok()) {
    return failed(DrawbarStatus::overflow);
  }
  DrawbarStatus status = DrawbarStatus::saturated;
  if (!saturated) {
    status = (capped_mask != 0U) ? DrawbarStatus::capped : DrawbarStatus::ok;
  }
  return DrawbarResult{{DrawbarPullN::from_raw(dp_raw[0]), DrawbarPullN::from_raw(dp_raw[1]),
                        DrawbarPullN::from_raw(dp_raw[2]), DrawbarPullN::from_raw(dp_raw[3]),
                        DrawbarPullN::from_raw(dp_raw[4]), DrawbarPullN::from_raw(dp_raw[5])},
                       total_n,
                       static_cast<std::uint8_t>(capped_mask),
                       status};
}

}  // namespace

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
