/* test_c_api.c: the flight module through its C interface, in C11, as a C
 * flight framework would call it. Exits non-zero on any failed check. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "sinkwatch/sinkwatch.h"

static int g_passed = 0;
static int g_failed = 0;

#define CHECK(cond)                                                     \
  do {                                                                  \
    if (cond) {                                                         \
      ++g_passed;                                                       \
    } else {                                                            \
      ++g_failed;                                                       \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                   \
  } while (0)

static sw_context g_ctx; /* static storage, as on a rover: no heap */

/* Level ground, every wheel driving forward at `current_q20`. */
/* Level ground at 5.5 cm/s. A live sensor's noise moves its last bits: a
 * dither of 0..2 LSB keeps the sensor health checks from calling a channel
 * stuck (flight/sensor_health.hpp). */
static sw_telemetry level_sample(uint32_t time_ms, int32_t current_q20) {
  sw_telemetry t;
  const int32_t dither = (int32_t)((time_ms / 100U) % 3U);
  memset(&t, 0, sizeof t);
  t.time_ms = time_ms;
  t.valid = 1U;
  for (unsigned i = 0U; i < SW_WHEELS; ++i) {
    t.direction[i] = SW_DIRECTION_FORWARD;
    t.current_a_q20[i] = current_q20 + dither;
  }
  t.pitch_rad_q28 = dither;
  t.roll_rad_q28 = dither;
  t.rocker_rad_q28[0] = dither;
  t.rocker_rad_q28[1] = dither;
  t.bogie_rad_q28[0] = dither;
  t.bogie_rad_q28[1] = dither;
  t.accel_valid = 1U;
  t.accel_mps2_q24 = 0;
  t.speed_valid = 1U;
  t.speed_mps_q24 = (int32_t)(0.050 * (1 << 24));
  t.rim_speed_valid = 1U;
  t.rim_speed_mps_q24 = (int32_t)(0.055 * (1 << 24));
  return t;
}

static void test_arguments(void) {
  sw_context fresh;
  sw_cycle_result out;
  sw_telemetry t = level_sample(100U, 0);
  memset(&fresh, 0, sizeof fresh);
  CHECK(sw_init(NULL) == SW_NULL_ARGUMENT);
  CHECK(sw_step(&fresh, &t, 100U, &out) == SW_NOT_INITIALISED);
  CHECK(sw_step(NULL, &t, 100U, &out) == SW_NULL_ARGUMENT);
  CHECK(sw_init(&fresh) == SW_OK);
  CHECK(sw_step(&fresh, NULL, 100U, &out) == SW_NULL_ARGUMENT);
  CHECK(sw_step(&fresh, &t, 100U, NULL) == SW_NULL_ARGUMENT);
  CHECK(sw_last_event(&fresh, SW_WHEELS, NULL) == 0);
}

static void test_bad_table_keeps_default(void) {
  static const uint8_t garbage[32] = {0x53U, 0x57U, 0x50U, 0x54U, 9U, 0U};
  CHECK(sw_init(&g_ctx) == SW_OK);
  CHECK(sw_active_table_crc(&g_ctx) == 0U);
  CHECK(sw_load_table(&g_ctx, garbage, sizeof garbage) == SW_REJECT_UNSUPPORTED_FORMAT_VERSION);
  CHECK(sw_load_table(&g_ctx, NULL, 0U) == SW_REJECT_NULL_BUFFER);
  CHECK(sw_active_table_crc(&g_ctx) == 0U); /* the default is still in force */
}

/* Every reject reason has its own name, the enumerator's without the prefix;
 * a value past the last reason has none. */
static void test_reject_reason_names(void) {
  unsigned i;
  unsigned j;
  CHECK(strcmp(sw_reject_reason_name(SW_REJECT_OK), "ok") == 0);
  CHECK(strcmp(sw_reject_reason_name(SW_REJECT_CRC_MISMATCH), "crc_mismatch") == 0);
  CHECK(strcmp(sw_reject_reason_name(SW_REJECT_EXTENSION_REJECTED), "extension_rejected") == 0);
  CHECK(strcmp(sw_reject_reason_name(SW_REJECT_ROVER_RADIUS_MISMATCH), "rover_radius_mismatch") == 0);
  CHECK(strcmp(sw_reject_reason_name((uint8_t)SW_REJECT_REASON_COUNT), "unknown") == 0);
  CHECK(strcmp(sw_reject_reason_name(255U), "unknown") == 0);
  for (i = 0U; i < (unsigned)SW_REJECT_REASON_COUNT; ++i) {
    const char* name = sw_reject_reason_name((uint8_t)i);
    CHECK(name != NULL && strcmp(name, "unknown") != 0);
    for (j = 0U; j < i; ++j) {
      CHECK(strcmp(name, sw_reject_reason_name((uint8_t)j)) != 0);
    }
  }
}

/* A current dropout is reported per channel; a whole side gone stops the
 * rover under the default table's stop policy. */
static void test_sensor_health(void) {
  sw_cycle_result out;
  uint32_t time_ms = 1000U;
  int stopped_at = -1;
  CHECK(sw_init(&g_ctx) == SW_OK);
  for (int k = 0; k < 3; ++k) {
    sw_telemetry t = level_sample(time_ms, (int32_t)(0.2 * (1 << 20)));
    time_ms += 100U;
    CHECK(sw_step(&g_ctx, &t, t.time_ms, &out) == SW_OK);
    CHECK(out.sensor_health[SW_CHANNEL_CURRENT_LF + 1U] == SW_HEALTH_OK);
  }
  for (int k = 0; k < 20 && stopped_at < 0; ++k) {
    sw_telemetry t = level_sample(time_ms, (int32_t)(0.2 * (1 << 20)));
    time_ms += 100U;
    t.current_missing[0] = 1U;
    t.current_missing[1] = 1U;
    t.current_missing[2] = 1U;
    CHECK(sw_step(&g_ctx, &t, t.time_ms, &out) == SW_OK);
    CHECK(out.sensor_health[SW_CHANNEL_CURRENT_LF + 1U] == SW_HEALTH_MISSING);
    CHECK(out.sensor_health[SW_CHANNEL_CURRENT_LF + 3U] == SW_HEALTH_OK);
    CHECK(out.wheels_blind == 3U);
    CHECK(out.wheel[1].estimate_valid == 0U);
    if (out.decision == SW_DECISION_STOP_AND_REPLAN) {
      stopped_at = k;
    }
  }
  CHECK(stopped_at == 9); /* invalid_to_stop = 10 unusable samples */
}

static void test_nominal_then_overcurrent(void) {
  sw_cycle_result out;
  sw_event event;
  sw_stop_record stop;
  uint32_t time_ms = 1000U;
  int32_t limit_q20 = 0;
  int stopped_at = -1;
  CHECK(sw_init(&g_ctx) == SW_OK);
  CHECK(sw_last_stop(&g_ctx, &stop) == 0); /* no stop yet */
  CHECK(sw_last_stop(&g_ctx, NULL) == 0);

  /* Learn the current limit at a small current. */
  sw_telemetry t = level_sample(time_ms, (int32_t)(0.2 * (1 << 20)));
  CHECK(sw_step(&g_ctx, &t, time_ms, &out) == SW_OK);
  CHECK(out.loads_valid == 1U);
  CHECK(out.wheel[0].limit_valid == 1U);
  limit_q20 = out.wheel[0].current_limit_a_q20;
  CHECK(limit_q20 > 0);

  /* The six loads carry the rover's weight on level ground: 140 kg x 1.62. */
  {
    int64_t sum_q16 = 0;
    for (unsigned i = 0U; i < SW_WHEELS; ++i) {
      sum_q16 += out.wheel[i].load_n_q16;
    }
    const double sum_n = (double)sum_q16 / 65536.0;
    CHECK(sum_n > 226.0 && sum_n < 227.6);
  }

  /* Well below the limit: the drive continues. */
  for (int k = 0; k < 20; ++k) {
    time_ms += 100U;
    t = level_sample(time_ms, limit_q20 / 4);
    CHECK(sw_step(&g_ctx, &t, time_ms, &out) == SW_OK);
    CHECK(out.decision == SW_DECISION_CONTINUE);
  }

  /* Above the limit, persistently: the rover stops and records an event. */
  for (int k = 0; k < 40 && stopped_at < 0; ++k) {
    time_ms += 100U;
    t = level_sample(time_ms, limit_q20 + limit_q20 / 2);
    (void)sw_step(&g_ctx, &t, time_ms, &out);
    if (out.decision == SW_DECISION_STOP_AND_REPLAN) {
      stopped_at = k;
    }
  }
  CHECK(stopped_at > 0); /* not on the first sample: persistence */
  CHECK(sw_last_event(&g_ctx, 0U, &event) == 1);
  CHECK(event.peak_current_a_q20 >= limit_q20);
  /* The rover's record of the stop: the current rule, a sinkage from the
   * wheels' recent estimates, at the stop's time. */
  CHECK(sw_last_stop(&g_ctx, &stop) == 1);
  CHECK(stop.reason == 1U); /* StopReason::current */
  CHECK(stop.time_ms == time_ms);
  CHECK(stop.sinkage_valid == 1U);
  CHECK(stop.samples == SW_STOP_RECORD_SAMPLES);
  CHECK(stop.deepest_wheel < SW_WHEELS);

  /* The ground acknowledges; the wheels are nominal again. */
  sw_clear_stop(&g_ctx);
  time_ms += 100U;
  t = level_sample(time_ms, limit_q20 / 4);
  CHECK(sw_step(&g_ctx, &t, time_ms, &out) == SW_OK);
  CHECK(out.wheel[0].state == SW_WHEEL_NOMINAL);
}

static void test_invalid_telemetry_is_reported(void) {
  sw_cycle_result out;
  sw_telemetry t = level_sample(5000U, 0);
  CHECK(sw_init(&g_ctx) == SW_OK);
  t.valid = 0U;
  CHECK(sw_step(&g_ctx, &t, 5000U, &out) == SW_TELEMETRY_INVALID);
  t = level_sample(5100U, 0);
  t.pitch_rad_q28 = (int32_t)(1.2 * (1 << 28)); /* 69 degrees: beyond every limit */
  CHECK(sw_step(&g_ctx, &t, 5100U, &out) != SW_OK);
  CHECK(out.decision == SW_DECISION_STOP_AND_REPLAN || out.loads_valid == 0U);
}

int main(void) {
  test_arguments();
  test_bad_table_keeps_default();
  test_reject_reason_names();
  test_nominal_then_overcurrent();
  test_sensor_health();
  test_invalid_telemetry_is_reported();
  printf("c_api: %d passed, %d failed\n", g_passed, g_failed);
  return (g_failed == 0) ? 0 : 1;
}
