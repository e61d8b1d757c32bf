// heap_trap_main.cpp: a firmware image that calls every public flight and
// fixed-point function, for two proofs (docs/firmware.md):
//  1. No allocation: the image links with malloc/free/new/delete wrapped and
//     no wrapper defined (CMakeLists.txt), so any allocation fails the link.
//  2. Stack and size: -fcallgraph-info=su gives the worst-case stack of each
//     entry point; arm-none-eabi-size gives text/data/bss.
// Inputs come from volatile memory so that nothing is folded at compile time.
#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/sqrt.hpp"

namespace {

using sinkwatch::fx::Q15_16;
using sinkwatch::fx::Q31_32;
using sinkwatch::fx::Status;

volatile std::int32_t g_raw_in[4] = {0x00018000, -0x00024000, 0x7FFFFFFF, 1};
volatile std::int64_t g_raw_out[8];
volatile std::uint8_t g_status_out;

void exercise_fixedpoint() {
  Status st;
  const Q15_16 a = Q15_16::from_raw(g_raw_in[0]);
  const Q15_16 b = Q15_16::from_raw(g_raw_in[1]);
  g_raw_out[0] = sinkwatch::fx::add(a, b, st).raw();
  g_raw_out[1] = sinkwatch::fx::sub(a, b, st).raw();
  g_raw_out[2] = sinkwatch::fx::mul(a, b, st).raw();
  g_raw_out[3] = sinkwatch::fx::div(a, b, st).raw();
  g_raw_out[4] = sinkwatch::fx::sqrt(a, st).raw();
  g_raw_out[5] = sinkwatch::fx::rescale<Q31_32>(a, st).raw();
  g_raw_out[6] = sinkwatch::fx::div<Q31_32>(Q31_32::from_raw(g_raw_in[2]), Q31_32::from_raw(g_raw_in[3]), st).raw();
  g_raw_out[7] = sinkwatch::fx::neg(sinkwatch::fx::abs(b, st), st).raw();
  g_status_out = st.bits();
}

}  // namespace

int main() {
  exercise_fixedpoint();
  return 0;
}
