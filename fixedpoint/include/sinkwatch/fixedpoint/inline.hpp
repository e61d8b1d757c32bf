// inline.hpp: SW_FX_INLINE, the forced inlining of the small fixed-point
// helpers (wide.hpp, q.hpp).
//
// The flight firmware is built with -Os, where GCC keeps the small helpers
// (compare, add, shift, bit length, the 32x32 and 64x64-bit products, the
// sign-magnitude scale and pack) as calls, so a shift by a constant becomes a
// call and then a library shift. Forcing them inline changes no arithmetic
// and cuts the six-wheel step on the Cortex-M0 by about a quarter
// (docs/performance.md, "Forced inlining with a coverage switch").
//
// The coverage build (g++ -O0 --coverage) must not inline them: gcov counts
// the branches of every inlined copy apart, and the branch figure of the
// fixed-point headers fell from 95 % to 45 % with the attribute
// (docs/coverage.md). The `coverage` preset alone sets the CMake option
// SINKWATCH_FX_PLAIN_INLINE, which defines SINKWATCH_FX_PLAIN_INLINE for
// every user of sinkwatch::fixedpoint; the helpers are then plain `inline`.
// Either way the same source computes the same bits.
//
// An object-like macro for a declaration specifier: MISRA C++:2023 rule
// 19.0.2 (no function-like macros) is kept; the use of the preprocessor to
// choose a compiler attribute is deviation D-07 (docs/misra.md).
#ifndef SINKWATCH_FIXEDPOINT_INLINE_HPP
#define SINKWATCH_FIXEDPOINT_INLINE_HPP

#if defined(SINKWATCH_FX_PLAIN_INLINE)
#define SW_FX_INLINE inline
#else
#define SW_FX_INLINE [[gnu::always_inline]] inline
#endif

#endif  // SINKWATCH_FIXEDPOINT_INLINE_HPP
