// prop_trig.cpp: sin, cos, sincos, asin, acos and entry_angle against long double
// references (glibc's sinl, cosl, asinl, acosl: correctly reduced, within a
// few units of 2^-64 relative, i.e. ~1e-9 output LSB), over the whole
// representable range of several input formats, with the edges weighted in,
// plus exhaustive runs over 2^20-value ranges.
//
// Documented bound (docs/fixedpoint.md): every result within 1 LSB of the
// exact value of the exact input. Asserted as |result - reference| <= 1 LSB
// + k_reference_slack, the slack covering the reference's own error only.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>

#include "fx_reference.hpp"
#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fxref::I128;

using QInt32 = fx::Q<std::int32_t, 0>;
using QInt64 = fx::Q<std::int64_t, 0>;
using Q1_62 = fx::Q<std::int64_t, 62>;
using Q12_19 = fx::Q<std::int32_t, 19>;
using Q2_29 = fx::Q<std::int32_t, 29>;

/// The reference functions' error, far below an LSB (see the header).
constexpr long double k_reference_slack = 1e-6L;
constexpr long double k_bound_lsb = 1.0L;

template <typename QT>
long double value_of(QT x) {
  return std::ldexp(static_cast<long double>(x.raw()), -QT::frac_bits);  // exact: raw has <= 64 bits
}

/// Largest |error| seen, in LSB, per function: printed by the exhaustive
/// tests as measured figures.
struct Worst {
  long double lsb = 0.0L;
  void see(long double e) {
    if (std::fabs(e) > lsb) {
      lsb = std::fabs(e);
    }
  }
};

template <typename Out>
std::string check_value(const char* fn, Out r, fx::Status s, long double reference, const std::string& input,
                        Worst* worst) {
  if (!s.ok()) {
    return std::string(fn) + "(" + input + "): unexpected status " + std::to_string(s.bits());
  }
  const long double err = static_cast<long double>(r.raw()) - std::ldexp(reference, Out::frac_bits);
  if (worst != nullptr) {
    worst->see(err);
  }
  if (!(std::fabs(err) <= k_bound_lsb + k_reference_slack)) {
    return std::string(fn) + "(" + input + "): error " + std::to_string(static_cast<double>(err)) + " LSB";
  }
  return "";
}

template <typename QT>
std::string input_name(QT x) {
  return fxref::to_string(static_cast<I128>(x.raw())) + " * 2^-" + std::to_string(QT::frac_bits);
}

template <typename QT>
std::string check_sin_cos(QT x, Worst* worst = nullptr) {
  fx::Status s1;
  const fx::Q1_30 sn = fx::sin(x, s1);
  std::string e = check_value("sin", sn, s1, sinl(value_of(x)), input_name(x), worst);
  if (!e.empty()) {
    return e;
  }
  fx::Status s2;
  const fx::Q1_30 cs = fx::cos(x, s2);
  e = check_value("cos", cs, s2, cosl(value_of(x)), input_name(x), worst);
  if (!e.empty()) {
    return e;
  }
  // sincos: the same bound against the references, and bit for bit the
  // values of sin() and cos() apart (one reduction shared).
  fx::Status s4;
  const fx::SinCos sc = fx::sincos(x, s4);
  e = check_value("sincos.sin", sc.sin, s4, sinl(value_of(x)), input_name(x), worst);
  if (e.empty()) {
    e = check_value("sincos.cos", sc.cos, s4, cosl(value_of(x)), input_name(x), worst);
  }
  if (!e.empty()) {
    return e;
  }
  if ((sc.sin != sn) || (sc.cos != cs)) {
    return "sincos differs from sin/cos at " + input_name(x);
  }
  // Symmetry, bit for bit: sin odd, cos even (sign-magnitude evaluation).
  if (x.raw() != std::numeric_limits<typename QT::storage_type>::min()) {
    fx::Status s3;
    const QT mx = fx::neg(x, s3);
    if (fx::sin(mx, s3).raw() != -sn.raw() || fx::cos(mx, s3) != cs || !s3.ok()) {
      return "sin/cos symmetry broken at " + input_name(x);
    }
  }
  return "";
}

/// asin and acos: domain error beyond |x| > 1, else within 1 LSB.
template <typename QT>
std::string check_asin_acos(QT x, Worst* worst = nullptr) {
  const long double v = value_of(x);
  fx::Status s1;
  const fx::Q3_28 as = fx::asin(x, s1);
  fx::Status s2;
  const fx::Q3_28 ac = fx::acos(x, s2);
  if (std::fabs(v) > 1.0L) {
    if (s1.bits() != static_cast<std::uint8_t>(fx::Flag::domain) || as.raw() != 0 ||
        s2.bits() != static_cast<std::uint8_t>(fx::Flag::domain) || ac.raw() != 0) {
      return "asin/acos(" + input_name(x) + "): expected domain only and zero";
    }
    return "";
  }
  std::string e = check_value("asin", as, s1, asinl(v), input_name(x), worst);
  if (e.empty()) {
    e = check_value("acos", ac, s2, acosl(v), input_name(x), worst);
  }
  if (e.empty() && x.raw() != std::numeric_limits<typename QT::storage_type>::min()) {
    fx::Status s3;
    if (fx::asin(fx::neg(x, s3), s3).raw() != -as.raw()) {
      return "asin symmetry broken at " + input_name(x);
    }
  }
  return e;
}

/// entry_angle: domain error outside [0, 2], else within 1 LSB of
/// arccos(1 - ratio), referenced as 2 asin(sqrt(ratio / 2)) (accurate near
/// zero) and as acos(1 - ratio) past 1 (1 - ratio is exact in long double).
template <typename QT>
std::string check_entry_angle(QT ratio, Worst* worst = nullptr) {
  const long double v = value_of(ratio);
  fx::Status s;
  const fx::Q3_28 th = fx::entry_angle(ratio, s);
  if (v < 0.0L || v > 2.0L) {
    if (s.bits() != static_cast<std::uint8_t>(fx::Flag::domain) || th.raw() != 0) {
      return "entry_angle(" + input_name(ratio) + "): expected domain only and zero";
    }
    return "";
  }
  const long double reference = (v <= 1.0L) ? 2.0L * asinl(sqrtl(v / 2.0L)) : acosl(1.0L - v);
  return check_value("entry_angle", th, s, reference, input_name(ratio), worst);
}

/// atan2: domain error at (0, 0), else within 1 LSB of atan2l (the inputs
/// share a format, so y / x is exact in long double whenever both raws are).
template <typename QT>
std::string check_atan2(QT y, QT x, Worst* worst = nullptr) {
  fx::Status s;
  const fx::Q3_28 r = fx::atan2(y, x, s);
  if (y.raw() == 0 && x.raw() == 0) {
    if (s.bits() != static_cast<std::uint8_t>(fx::Flag::domain) || r.raw() != 0) {
      return "atan2(0, 0): expected domain only and zero";
    }
    return "";
  }
  return check_value("atan2", r, s, atan2l(value_of(y), value_of(x)), input_name(y) + ", " + input_name(x), worst);
}

// ------------------------------------------------------------ generators

/// Raw values next to the interesting points of asin's domain: +-1, +-1/2
/// (the switch between the direct and the square-root branch), 0.
template <typename QT>
QT near_unit(int numerator_halves) {
  using S = typename QT::storage_type;
  const I128 one = static_cast<I128>(1) << QT::frac_bits;
  const I128 centre = (one * numerator_halves) / 2;
  const I128 delta = *rc::gen::oneOf(rc::gen::inRange<std::int64_t>(-3, 4), rc::gen::inRange<std::int64_t>(-100000, 100000));
  return QT::from_raw(fxref::clamp_to<S>(centre + delta));
}

template <typename QT>
QT asin_arg() {
  if (*rc::gen::inRange(0, 2) == 0) {
    return *fxref::q<QT>();
  }
  return near_unit<QT>(*rc::gen::element(-2, -1, 0, 1, 2));
}

template <typename QT>
QT entry_arg() {
  if (*rc::gen::inRange(0, 2) == 0) {
    return *fxref::q<QT>();
  }
  return near_unit<QT>(*rc::gen::element(0, 1, 2, 3, 4));
}

/// Angles next to multiples of pi/2 (where the reduction cancels most).
template <typename QT>
QT near_quadrant() {
  using S = typename QT::storage_type;
  const long double k = static_cast<long double>(*rc::gen::inRange(-64, 65));
  const long double a = std::ldexp(k * 1.5707963267948966192313216916397514L, QT::frac_bits);
  const long double lim = std::ldexp(1.0L, static_cast<int>(QT::total_bits) - 2);
  if (std::fabs(a) >= lim) {
    return *fxref::q<QT>();
  }
  const I128 delta = *rc::gen::inRange<std::int64_t>(-5, 6);
  return QT::from_raw(fxref::clamp_to<S>(static_cast<I128>(llroundl(a)) + delta));
}

template <typename QT>
QT angle_arg() {
  if (*rc::gen::inRange(0, 3) == 0) {
    return near_quadrant<QT>();
  }
  return *fxref::q<QT>();
}

}  // namespace

#define FX_TRIG_PROPS(Suffix, QT)                                                     \
  RC_GTEST_PROP(FxTrig_##Suffix, SinCosWithinOneLsb, ()) {                            \
    RC_ASSERT(check_sin_cos(angle_arg<QT>()) == std::string());                       \
  }                                                                                   \
  RC_GTEST_PROP(FxTrig_##Suffix, AsinAcosWithinOneLsbOrDomain, ()) {                  \
    RC_ASSERT(check_asin_acos(asin_arg<QT>()) == std::string());                      \
  }                                                                                   \
  RC_GTEST_PROP(FxTrig_##Suffix, EntryAngleWithinOneLsbOrDomain, ()) {                \
    RC_ASSERT(check_entry_angle(entry_arg<QT>()) == std::string());                   \
  }

#define FX_ATAN2_PROP(Suffix, QT)                                                     \
  RC_GTEST_PROP(FxTrig_##Suffix, Atan2WithinOneLsbOrDomain, ()) {                     \
    const QT y = *fxref::q<QT>();                                                     \
    /* Half the time x is next to +-y or +-y tan(pi/8): the octant seams. */          \
    const int mode = *rc::gen::inRange(0, 4);                                         \
    const I128 yr = y.raw();                                                          \
    const I128 target = (mode == 0) ? yr : ((mode == 1) ? -yr : (yr * 5741) / 2378);  \
    const QT x = (mode == 3) ? *fxref::q<QT>()                                        \
                             : QT::from_raw(fxref::clamp_to<typename QT::storage_type>( \
                                   target + *rc::gen::inRange<std::int64_t>(-2, 3))); \
    RC_ASSERT(check_atan2(y, x) == std::string());                                    \
    RC_ASSERT(check_atan2(x, y) == std::string());                                    \
  }

FX_ATAN2_PROP(Q15_16, fx::Q15_16)
FX_ATAN2_PROP(Q1_30, fx::Q1_30)
FX_ATAN2_PROP(Int32, QInt32)
FX_ATAN2_PROP(Q31_32, fx::Q31_32)
FX_ATAN2_PROP(Int64, QInt64)

FX_TRIG_PROPS(Q15_16, fx::Q15_16)
FX_TRIG_PROPS(Q1_30, fx::Q1_30)
FX_TRIG_PROPS(Q2_29, Q2_29)
FX_TRIG_PROPS(Int32, QInt32)
FX_TRIG_PROPS(Q31_32, fx::Q31_32)
FX_TRIG_PROPS(Int64, QInt64)
FX_TRIG_PROPS(Q1_62, Q1_62)

// ---------------------------------------------------- sincos of a bounded angle

// fx::sincos of an fx::Bounded Q3.28 angle (the flight code's joints and
// attitude) within the bounded form's limit, 2.015 rad: within 1 LSB of the
// references and bit for bit fx::sincos of the same angle (the cheaper
// reduction keeps the bits; docs/fixedpoint.md, 5.4).
RC_GTEST_PROP(FxTrigBounded, SinCosOfABoundedQ3_28AngleIsSinCos, ()) {
  constexpr auto kLimit = static_cast<std::uint32_t>(fx::detail::trig::k_near_limit<28>);
  const auto limit = static_cast<std::int32_t>(kLimit);
  // A third of the draws next to pi/4, pi/2 or the limit, where the
  // quadrant and the cosine's sign turn.
  const int mode = *rc::gen::inRange(0, 3);
  const std::int32_t centre = *rc::gen::element(210828714, 421657428, limit);
  const std::int32_t raw =
      (mode == 0) ? *rc::gen::inRange(-limit, limit + 1) : (centre - *rc::gen::inRange(0, 9)) * ((mode == 1) ? 1 : -1);
  fx::Status s;
  const fx::SinCos b = fx::sincos(fx::Bounded<fx::Q3_28, kLimit>::trusted(raw), s);
  const fx::SinCos f = fx::sincos(fx::Q3_28::from_raw(raw), s);
  RC_ASSERT(b.sin == f.sin);
  RC_ASSERT(b.cos == f.cos);
  RC_ASSERT(s.ok());
  const long double x = std::ldexp(static_cast<long double>(raw), -28);
  RC_ASSERT(std::fabs(static_cast<long double>(b.sin.raw()) - std::ldexp(sinl(x), 30)) <= 1.0L + k_reference_slack);
  RC_ASSERT(std::fabs(static_cast<long double>(b.cos.raw()) - std::ldexp(cosl(x), 30)) <= 1.0L + k_reference_slack);
}

// Integers closest to multiples of pi/2 (numerators of the continued-fraction
// convergents of pi/2, computed with mpmath): the hardest range reductions an
// int64 angle can ask for.
TEST(FxTrigReduction, ConvergentsOfHalfPi) {
  const std::int64_t hard[] = {1, 2, 3, 11, 344, 355, 51819, 52174, 260515, 573204, 4846147, 5419351,
                               37362253, 42781604, 122925461, 411557987, 534483448, 2549491779, 3083975227,
                               17969367914, 21053343141, 881156436695, 902209779836, 2685575996367,
                               8958937768937, 65398140378926, 74357078147863, 139755218526789,
                               214112296674652, 5920787228742393, 6134899525417045, 12055686754159438,
                               18190586279576483, 48436859313312404, 66627445592888887, 181691750499090178,
                               248319196091979065, 430010946591069243, 1108341089274117551,
                               1538352035865186794, 2646693125139304345};
  for (const std::int64_t n : hard) {
    for (std::int64_t d = -1; d <= 1; ++d) {
      EXPECT_EQ(check_sin_cos(QInt64::from_raw(n + d)), "");
      EXPECT_EQ(check_sin_cos(QInt64::from_raw(-(n + d))), "");
    }
  }
}

// ------------------------------------------------------------ exhaustive

// sin and cos of every Q15_16 angle in [-8, 8] rad (2^20 + 1 values: every
// quadrant and octant seam twice).
TEST(FxTrigExhaustive, SinCosQ15_16Within8Rad) {
  Worst worst;
  std::int64_t failures = 0;
  std::string first;
  for (std::int32_t r = -(1 << 19); r <= (1 << 19); ++r) {
    const std::string e = check_sin_cos(fx::Q15_16::from_raw(r), &worst);
    if (!e.empty() && failures++ == 0) {
      first = e;
    }
  }
  EXPECT_EQ(failures, 0) << first;
  std::cout << "sin/cos Q15_16 [-8, 8] rad: worst error " << static_cast<double>(worst.lsb) << " LSB\n";
}

// asin and acos of every Q12_19 value in [-1, 1] and 16 past each end
// (2^20 + 33 values), with monotonicity: asin never decreases.
TEST(FxTrigExhaustive, AsinAcosQ12_19) {
  Worst worst;
  std::int64_t failures = 0;
  std::string first;
  std::int32_t previous = std::numeric_limits<std::int32_t>::min();
  for (std::int32_t r = -(1 << 19) - 16; r <= (1 << 19) + 16; ++r) {
    const Q12_19 x = Q12_19::from_raw(r);
    std::string e = check_asin_acos(x, &worst);
    fx::Status s;
    const std::int32_t a = fx::asin(x, s).raw();
    if (e.empty() && s.ok()) {
      if (a < previous) {
        e = "asin decreases at " + input_name(x);
      }
      previous = a;
    }
    if (!e.empty() && failures++ == 0) {
      first = e;
    }
  }
  EXPECT_EQ(failures, 0) << first;
  std::cout << "asin/acos Q12_19 [-1, 1]: worst error " << static_cast<double>(worst.lsb) << " LSB\n";
}

// entry_angle of every Q12_19 sinkage ratio in [0, 2] and 16 past each end.
TEST(FxTrigExhaustive, EntryAngleQ12_19) {
  Worst worst;
  std::int64_t failures = 0;
  std::string first;
  std::int32_t previous = std::numeric_limits<std::int32_t>::min();
  for (std::int32_t r = -16; r <= (1 << 20) + 16; ++r) {
    const Q12_19 x = Q12_19::from_raw(r);
    std::string e = check_entry_angle(x, &worst);
    fx::Status s;
    const std::int32_t a = fx::entry_angle(x, s).raw();
    if (e.empty() && s.ok()) {
      if (a < previous) {
        e = "entry_angle decreases at " + input_name(x);
      }
      previous = a;
    }
    if (!e.empty() && failures++ == 0) {
      first = e;
    }
  }
  EXPECT_EQ(failures, 0) << first;
  std::cout << "entry_angle Q12_19 [0, 2]: worst error " << static_cast<double>(worst.lsb) << " LSB\n";
}

// The top 2^19 ratios of Q2_29 below 2 and the 2^19 smallest ones: the two
// ends of the entry angle, where arccos(1 - x) is steepest.
TEST(FxTrigExhaustive, EntryAngleQ2_29Ends) {
  Worst worst;
  std::int64_t failures = 0;
  std::string first;
  auto run = [&](std::int32_t r) {
    const std::string e = check_entry_angle(Q2_29::from_raw(r), &worst);
    if (!e.empty() && failures++ == 0) {
      first = e;
    }
  };
  for (std::int32_t r = 0; r < (1 << 19); ++r) {
    run(r);
  }
  for (std::int32_t r = (1 << 30) - (1 << 19); r <= (1 << 30) + 4; ++r) {
    run(r);
  }
  EXPECT_EQ(failures, 0) << first;
  std::cout << "entry_angle Q2_29 ends: worst error " << static_cast<double>(worst.lsb) << " LSB\n";
}

// atan2 of every (y, x) on a 1024 x 1024 grid of Q15_16 raws around the
// origin: every octant and every seam.
TEST(FxTrigExhaustive, Atan2GridQ15_16) {
  Worst worst;
  std::int64_t failures = 0;
  std::string first;
  for (std::int32_t y = -512; y < 512; ++y) {
    for (std::int32_t x = -512; x < 512; ++x) {
      const std::string e = check_atan2(fx::Q15_16::from_raw(y), fx::Q15_16::from_raw(x), &worst);
      if (!e.empty() && failures++ == 0) {
        first = e;
      }
    }
  }
  EXPECT_EQ(failures, 0) << first;
  std::cout << "atan2 Q15_16 grid: worst error " << static_cast<double>(worst.lsb) << " LSB\n";
}
