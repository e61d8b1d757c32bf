# Cortex-M0: ARMv6-M, no FPU, no hardware divide, no 32x32->64 multiply
# instruction: the hardest target for 64-bit fixed-point intermediates.
set(SINKWATCH_CPU_FLAGS "-mcpu=cortex-m0 -mthumb -mfloat-abi=soft")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi-common.cmake)
