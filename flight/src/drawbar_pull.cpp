// Drawbar pull from the vehicle force balance; see drawbar_pull.hpp and
// docs/rover-loads.md, section 6. Twin: ground/reference/src/rover_loads.cpp.
#include "sinkwatch/flight/drawbar_pull.hpp"

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
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

bool ratio_in_range(Ratio r) noexcept { return (r.raw() > 0) && (r <= kMaxDpMaxRatio); }

/// The acceleration, the slope, the slip and every ratio and load are in
/// their accepted ranges (the parameters are already validated).
bool inputs_in_range(const RoverParams& params, const WheelLoadResult& loads, const DrawbarInput& input) noexcept {
  const bool accel_ok = (input.accel_mps2 <= kMaxAbsAccel) && (input.accel_mps2.raw() >= -kMaxAbsAccel.raw());
  const bool pitch_ok = (input.pitch_rad <= params.attitude_limit_rad) &&
                        (input.pitch_rad.raw() >= -params.attitude_limit_rad.raw());
  const bool slip_ok = !input.slip_known || (input.slip <= kMaxSlip);
  if (!accel_ok || !pitch_ok || !slip_ok) {
    return false;
  }
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    if (!ratio_in_range(input.dp_max_ratio[i]) || (loads.load_n[i].raw() < 0)) {
      return false;
    }
  }
  return true;
}

/// The sum of the loads S in raw Q15.16 units (six values in [0, 2^31), so
/// S < 2^34) and its normalised reciprocal M 2^-(31 + n), n = bit_length(S)
/// (fixedpoint/reciprocal.hpp): one reciprocal per call instead of a 64-bit
/// library division.
struct LoadSum {
  std::uint64_t raw{0U};
  fx::NormalisedReciprocal reciprocal{};
};

/// W_i / sum W in Q31.32, bit for bit fx::div(W_i, sum W) of the loads
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
W load_fraction(WheelLoadN load, const LoadSum& sum) noexcept {
  const auto l = static_cast<std::uint32_t>(load.raw());  // 0 <= load (inputs_in_range)
  const std::uint64_t n = static_cast<std::uint64_t>(l) << 32U;
  // The reciprocal's scale is 31 + n (no fraction bits), n >= 1: the sum is positive.
  const auto shift = static_cast<std::uint32_t>(sum.reciprocal.scale - 32);
  std::uint64_t q = fx::wide::shr(fx::wide::mul_32x32_64(l, sum.reciprocal.mantissa), shift);
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
  // W_i <= sum W: the fraction is at most 1 (2^32 raw), well inside Q31.32.
  const std::uint64_t rounded = (remainder >= (sum.raw - remainder)) ? (q + 1U) : q;
  return W::from_raw(static_cast<std::int64_t>(rounded));
}

/// The pulls for usable loads and parameters that passed
/// validate_rover_params().
DrawbarResult pulls_of_valid(const RoverParams& params, const WheelLoadResult& loads,
                             const DrawbarInput& input) noexcept {
  if (!inputs_in_range(params, loads, input)) {
    return failed(DrawbarStatus::invalid_input);
  }
  fx::Status st;
  // sum W in raw Q15.16 units: six values in [0, 2^31) sum below 2^34.
  std::uint64_t load_sum = 0U;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    load_sum += static_cast<std::uint64_t>(loads.load_n[i].raw());
  }
  if (load_sum == 0U) {
    return failed(DrawbarStatus::invalid_loads);
  }
  const LoadSum sum{load_sum, fx::normalised_reciprocal(load_sum, 0)};

  // m (a + g sin(pitch)): the along-path force the tractions must supply.
  // The loads' sine when they were computed at this pitch (the step's case):
  // the same bits as computing it here.
  const fx::Q1_30 sin_pitch_q =
      (loads.pitch_rad == input.pitch_rad) ? loads.sin_pitch : fx::sin(input.pitch_rad.q(), st);
  const W sin_pitch = fx::rescale<W>(sin_pitch_q, st);
  const W g_along = fx::mul<W>(params.gravity_mps2.q(), sin_pitch, st);
  const W accel = fx::add(fx::rescale<W>(input.accel_mps2.q(), st), g_along, st);
  const W total = fx::mul<W>(params.mass_kg.q(), accel, st);

  DrawbarResult r{};
  r.total_n = DrawbarPullN{fx::rescale<LoadQ>(total, st)};
  const bool saturated = input.slip_known && (input.slip >= params.high_slip);
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    const W load = fx::rescale<W>(loads.load_n[i].q(), st);
    const W cap = fx::mul<W>(input.dp_max_ratio[i].q(), load, st);
    W dp = cap;
    if (!saturated) {
      // total * (W_i / sum W): the fraction is in [0, 1], so the product
      // never exceeds |total|.
      const W share = fx::mul(total, load_fraction(loads.load_n[i], sum), st);
      dp = fx::clamp(share, fx::neg(cap, st), cap, st);
      if (dp != share) {
        r.capped_mask = static_cast<std::uint8_t>(r.capped_mask | (1U << i));
      }
    }
    r.dp_n[i] = DrawbarPullN{fx::rescale<LoadQ>(dp, st)};
  }
  if (!st.ok()) {
    return failed(DrawbarStatus::overflow);
  }
  if (saturated) {
    r.status = DrawbarStatus::saturated;
  } else {
    r.status = (r.capped_mask != 0U) ? DrawbarStatus::capped : DrawbarStatus::ok;
  }
  return r;
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
