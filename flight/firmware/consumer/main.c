/* A C firmware's control task calling sinkwatch once per cycle. */
#include <stdint.h>

#include "sinkwatch/sinkwatch.h"

static sw_context g_sinkwatch;
volatile uint8_t g_decision;

int main(void) {
  sw_telemetry telemetry = {0};
  sw_cycle_result result;
  (void)sw_init(&g_sinkwatch);
  for (uint32_t cycle = 1U; cycle <= 10U; ++cycle) {
    telemetry.time_ms = cycle * 100U;
    telemetry.valid = 1U;
    if (sw_step(&g_sinkwatch, &telemetry, telemetry.time_ms, &result) == SW_OK) {
      g_decision = result.decision;
    }
  }
  return 0;
}
