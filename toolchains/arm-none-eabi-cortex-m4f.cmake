# Cortex-M4F: Thumb-2, hardware divide, single-precision FPU (unused by the
# flight code, which is integer-only).
set(SINKWATCH_CPU_FLAGS "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi-common.cmake)
