/* sinkwatch.h: the C interface of the flight module, for C flight frameworks
 * (cFS applications, plain C firmware).
 *
 * It wraps the per-cycle step (flight/rover_step.hpp: telemetry -> wheel
 * loads -> drawbar pulls -> Eq. 15 sinkage, current limits, wheel states and
 * the rover's stop-and-replan decision) and the parameter-table loader
 * (flight/param_table.hpp). No allocation: the caller owns the context's
 * storage, typically a static object. Every number crosses the interface as
 * the raw integer of its Q format, named in the field (q20 = 20 fraction
 * bits): there is no floating point on either side.
 *
 * Threading: a context is used by one task at a time.
 */
#ifndef SINKWATCH_H
#define SINKWATCH_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SW_WHEELS 6U
/* Storage for one context. The implementation checks at compile time that
 * its state fits; docs/firmware.md gives the measured size. */
#define SW_CONTEXT_BYTES 4096U

typedef struct sw_context {
  union {
    uint64_t align_; /* 8-byte alignment for the state inside */
    uint8_t bytes[SW_CONTEXT_BYTES];
  } opaque;
} sw_context;

/* Results of sw_init and sw_step. Values 1..11 mirror RoverStepStatus. */
typedef enum sw_status {
  SW_OK = 0,
  SW_INVALID_TABLE = 1,
  SW_INVALID_ROVER_PARAMS = 2,
  SW_TELEMETRY_INVALID = 3,
  SW_TELEMETRY_STALE = 4,
  SW_TELEMETRY_REPEATED = 5,
  SW_MOTION_OUT_OF_RANGE = 6,
  SW_LOADS_FAILED = 7,
  SW_TIP_OVER = 8,
  SW_NO_ACCELERATION = 9,
  SW_DRAWBAR_FAILED = 10,
  SW_RADIUS_MISMATCH = 11,
  SW_SENSOR_LOST = 12,
  SW_NULL_ARGUMENT = 100,
  SW_NOT_INITIALISED = 101
} sw_status;

/* Why sw_load_table refused a table: the values of RejectReason
 * (flight/param_table.hpp), one per check, so the ground knows which number to
 * fix. sw_reject_reason_name() gives each its name. */
typedef enum sw_reject_reason {
  SW_REJECT_OK = 0,
  SW_REJECT_NULL_BUFFER = 1,
  SW_REJECT_TOO_SHORT = 2,
  SW_REJECT_TOO_LONG = 3,
  SW_REJECT_BAD_MAGIC = 4,
  SW_REJECT_UNSUPPORTED_FORMAT_VERSION = 5,
  SW_REJECT_LENGTH_MISMATCH = 6,
  SW_REJECT_RESERVED_NOT_ZERO = 7,
  SW_REJECT_CRC_MISMATCH = 8,
  SW_REJECT_SECTION_TRUNCATED = 9,
  SW_REJECT_SECTION_LENGTH_MISMATCH = 10,
  SW_REJECT_UNKNOWN_SECTION = 11,
  SW_REJECT_DUPLICATE_SECTION = 12,
  SW_REJECT_MISSING_SECTION = 13,
  SW_REJECT_SECTION_COUNT_MISMATCH = 14,
  SW_REJECT_RADIUS_OUT_OF_RANGE = 15,
  SW_REJECT_GEAR_RATIO_OUT_OF_RANGE = 16,
  SW_REJECT_EFFICIENCY_OUT_OF_RANGE = 17,
  SW_REJECT_TORQUE_CONSTANT_OUT_OF_RANGE = 18,
  SW_REJECT_NO_LOAD_CURRENT_OUT_OF_RANGE = 19,
  SW_REJECT_CURRENT_RANGE_OUT_OF_RANGE = 20,
  SW_REJECT_CORRECTION_COUNT_OUT_OF_RANGE = 21,
  SW_REJECT_LOAD_BREAKPOINT_OUT_OF_RANGE = 22,
  SW_REJECT_LOAD_BREAKPOINTS_NOT_INCREASING = 23,
  SW_REJECT_C1_OUT_OF_RANGE = 24,
  SW_REJECT_C2_OUT_OF_RANGE = 25,
  SW_REJECT_C3_OUT_OF_RANGE = 26,
  SW_REJECT_DP_MAX_OUT_OF_RANGE = 27,
  SW_REJECT_ALLOWED_SINKAGE_OUT_OF_RANGE = 28,
  SW_REJECT_CAUTION_SINKAGE_OUT_OF_RANGE = 29,
  SW_REJECT_STOP_SINKAGE_OUT_OF_RANGE = 30,
  SW_REJECT_SINKAGE_HYSTERESIS_OUT_OF_RANGE = 31,
  SW_REJECT_CURRENT_CAUTION_FRACTION_OUT_OF_RANGE = 32,
  SW_REJECT_CURRENT_HYSTERESIS_OUT_OF_RANGE = 33,
  SW_REJECT_LOAD_ENVELOPE_OUT_OF_RANGE = 34,
  SW_REJECT_STALE_TIMEOUT_OUT_OF_RANGE = 35,
  SW_REJECT_WINDOW_OUT_OF_RANGE = 36,
  SW_REJECT_TRIP_COUNT_OUT_OF_RANGE = 37,
  SW_REJECT_CLEAR_COUNT_OUT_OF_RANGE = 38,
  SW_REJECT_INVALID_LIMIT_OUT_OF_RANGE = 39,
  SW_REJECT_WHEEL_COUNT_OUT_OF_RANGE = 40,
  SW_REJECT_ROVER_STOP_K_OUT_OF_RANGE = 41,
  SW_REJECT_ESCAPE_PHASE_OUT_OF_RANGE = 42,
  SW_REJECT_ESCAPE_CYCLES_OUT_OF_RANGE = 43,
  SW_REJECT_ESCAPE_PATIENCE_OUT_OF_RANGE = 44,
  SW_REJECT_ESCAPE_DECREASE_OUT_OF_RANGE = 45,
  SW_REJECT_ESCAPE_FREED_OUT_OF_RANGE = 46,
  SW_REJECT_EXTENSION_TOO_LONG = 47, /* retired: no longer returned (section 6 is typed) */
  SW_REJECT_EXTENSION_REJECTED = 48, /* section 6: another layout version or invalid rover parameters */
  SW_REJECT_BUFFER_TOO_SMALL = 49,
  SW_REJECT_ROVER_RADIUS_MISMATCH = 50,
  SW_REJECT_HEALTH_POLICY_OUT_OF_RANGE = 51,
  SW_REJECT_HEALTH_BLIND_WHEELS_OUT_OF_RANGE = 52,
  SW_REJECT_HEALTH_STEP_OUT_OF_RANGE = 53,
  SW_REJECT_HEALTH_BRIDGE_OUT_OF_RANGE = 54,
  SW_REJECT_ENVELOPE_OVERFLOW = 55, /* the table's own numbers overflow within its envelope (sensor torque, current limit) */
  SW_REJECT_TRACTION_LEVEL_OUT_OF_RANGE = 56, /* section 8: caution/stop coefficients or hysteresis out of range */
  SW_REJECT_TRACTION_DISTANCE_OUT_OF_RANGE = 57, /* section 8: lookahead or trend span out of range */
  SW_REJECT_REASON_COUNT = 58 /* not a reason: the number of reasons */
} sw_reject_reason;

enum { SW_DIRECTION_FORWARD = 0, SW_DIRECTION_REVERSE = 1 };
enum { SW_WHEEL_NOMINAL = 0, SW_WHEEL_CAUTION = 1, SW_WHEEL_STOP = 2 };
enum { SW_DECISION_CONTINUE = 0, SW_DECISION_STOP_AND_REPLAN = 1 };
/* Sensor channels and their health (flight/sensor_health.hpp). */
#define SW_SENSOR_CHANNELS 9U
enum { SW_CHANNEL_CURRENT_LF = 0, SW_CHANNEL_IMU = 6, SW_CHANNEL_JOINTS = 7, SW_CHANNEL_CLOCK = 8 };
enum {
  SW_HEALTH_OK = 0,
  SW_HEALTH_MISSING = 1,
  SW_HEALTH_STUCK = 2,
  SW_HEALTH_SPIKE = 3,
  SW_HEALTH_NOISY = 4,
  SW_HEALTH_IMPLAUSIBLE = 5,
  SW_HEALTH_RECOVERING = 6
};

/* One cycle's raw telemetry. Wheel order: left front, left middle, left rear,
 * right front, right middle, right rear (flight/rover_geometry.hpp). */
typedef struct sw_telemetry {
  uint32_t time_ms;                  /* when the sample was taken */
  uint8_t valid;                     /* the source's own validity flag */
  uint8_t direction[SW_WHEELS];      /* SW_DIRECTION_* commanded per wheel */
  int32_t current_a_q20[SW_WHEELS];  /* motor current, A, Q11.20, + drives forward */
  int32_t pitch_rad_q28;             /* IMU pitch, rad, Q3.28, nose up + */
  int32_t roll_rad_q28;              /* IMU roll, rad, Q3.28, right side down + */
  int32_t rocker_rad_q28[2];         /* left, right; rad, Q3.28 */
  int32_t bogie_rad_q28[2];          /* left, right; rad, Q3.28 */
  uint8_t accel_valid;
  int32_t accel_mps2_q24;            /* along the path, m/s^2, Q7.24 */
  uint8_t speed_valid;
  int32_t speed_mps_q24;             /* over the ground, m/s, Q7.24 */
  uint8_t rim_speed_valid;
  int32_t rim_speed_mps_q24;         /* mean r*omega of the driven wheels, m/s, Q7.24 */
  /* Per-sensor dropouts (flight/sensor_health.hpp): non-zero marks the value
   * absent. Zero, as a zeroed struct has it, means present. */
  uint8_t current_missing[SW_WHEELS];
  uint8_t attitude_missing;
  uint8_t joints_missing;
} sw_telemetry;

typedef struct sw_wheel_result {
  uint8_t state;                /* SW_WHEEL_* */
  uint8_t sample_status;        /* SampleStatus of flight/monitor.hpp */
  uint8_t stop_reason;          /* StopReason: 0 none, 1 current, 2 sinkage, 3 telemetry, 4 slip */
  uint8_t stop_tripped;         /* entered STOP this cycle: read sw_last_event */
  uint8_t estimate_valid;       /* torque and sinkage hold this cycle's numbers */
  uint8_t limit_valid;          /* current limit holds this cycle's number */
  int32_t load_n_q16;           /* wheel load, N, Q15.16 (valid when loads_valid) */
  int32_t drawbar_pull_n_q16;   /* drawbar pull, N, Q15.16 (valid when drawbar_valid) */
  int32_t torque_nm_q16;        /* drive torque, N*m, Q15.16 */
  int32_t sinkage_m_q24;        /* Eq. 15 sinkage, m, Q7.24 */
  int32_t current_limit_a_q20;  /* maximum drive current, A, Q11.20 */
} sw_wheel_result;

typedef struct sw_cycle_result {
  uint8_t status;         /* sw_status of the step */
  uint8_t decision;       /* SW_DECISION_* */
  uint8_t loads_valid;
  uint8_t drawbar_valid;
  uint8_t wheels_in_stop;
  uint8_t wheels_in_caution;
  uint8_t wheels_blind;   /* wheels whose current sensor is faulty this cycle */
  uint8_t degraded;       /* driving on with blind wheels (the table's loss policy) */
  uint8_t attitude_bridged;  /* the IMU's last good attitude stands in this cycle */
  uint8_t joints_bridged;    /* the joints' last good angles stand in this cycle */
  uint8_t sensor_health[SW_SENSOR_CHANNELS];  /* SW_HEALTH_* per SW_CHANNEL_* */
  sw_wheel_result wheel[SW_WHEELS];
} sw_cycle_result;

/* Written when a wheel enters STOP: what the ground needs to reproduce it. */
typedef struct sw_event {
  uint8_t wheel;
  uint8_t reason;                /* StopReason */
  uint8_t peak_sinkage_valid;
  uint8_t max_estimate_valid;
  uint32_t time_ms;
  int32_t peak_current_a_q20;    /* largest drive current of the episode */
  int32_t load_at_peak_n_q16;
  int32_t peak_sinkage_m_q24;    /* Eq. 15 at the peak current with DP = DP_max */
  int32_t max_estimate_m_q24;    /* largest per-cycle sinkage estimate */
} sw_event;

/* Written when the rover's decision turns to stop-and-replan, whatever made
 * it (flight/stop_record.hpp): the deepest wheel's median sinkage over its
 * last SW_STOP_RECORD_SAMPLES valid estimates. */
#define SW_STOP_RECORD_SAMPLES 9U
typedef struct sw_stop_record {
  uint32_t time_ms;
  uint8_t reason;                /* StopReason of the episode's first STOP: 5 traction, 0 the step's own (tip-over) */
  uint8_t deepest_wheel;
  uint8_t samples;               /* estimates in the deepest wheel's median */
  uint8_t sinkage_valid;
  int32_t recent_sinkage_m_q24;  /* the deepest wheel's median Eq. 15 sinkage, m, Q7.24 */
} sw_stop_record;

/* Puts a context in its initial state: the default parameter table (Table 2's
 * corrections) and the Yutu-like rover on the Moon. */
sw_status sw_init(sw_context* ctx);

/* Loads a parameter table from bytes (flight/load.hpp: decoded, validated and
 * prepared in one call). Returns SW_REJECT_OK when it is in force, else the
 * sw_reject_reason and the previous table stays in force. A table with a
 * rover-geometry section replaces the rover parameters too; one without it
 * runs with the Yutu-like rover on the Moon. */
uint8_t sw_load_table(sw_context* ctx, const uint8_t* bytes, size_t size);

/* The name of a reject reason ("crc_mismatch"), the enumerator's name in
 * lower case without the prefix; "unknown" for a value that is not a reason.
 * Static storage: never freed. */
const char* sw_reject_reason_name(uint8_t reason);

/* CRC-32 of the table in force (0 for the built-in default). */
uint32_t sw_active_table_crc(const sw_context* ctx);

/* One control cycle; `now_ms` is the monitor's clock. */
sw_status sw_step(sw_context* ctx, const sw_telemetry* telemetry, uint32_t now_ms, sw_cycle_result* out);

/* The ground's acknowledgement after a re-plan: every wheel back to NOMINAL. */
void sw_clear_stop(sw_context* ctx);

/* The last event of a wheel. Returns 1 and fills `out` when there is one. */
int sw_last_event(const sw_context* ctx, uint8_t wheel, sw_event* out);

/* The record of the last stop-and-replan decision. Returns 1 and fills `out`
 * when there is one (it stays readable after sw_clear_stop until the next stop). */
int sw_last_stop(const sw_context* ctx, sw_stop_record* out);

#ifdef __cplusplus
}
#endif

#endif /* SINKWATCH_H */
