/* An example luxloc source plugin in plain C (built by the project's CMake as
 * libluxloc_example_plugin.so and exercised by tests/plugins/external/).
 *
 *   --plugin build/libluxloc_example_plugin.so --source example-fixes:circle[,count=N,rate=HZ,radius=M,fail_after=K]
 *
 * Emits absolute 2-D fixes of a device going round a circle (centre 4, 3) at 0.5 m/s, and an
 * IMU at rest between them, timestamped from t = 1 s, paced like a device (one fix per 1/rate
 * seconds of wall time); `fail_after=K` ends with a failure after K fixes (to test the host's
 * error path). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "plugins/abi/luxloc_plugin.h"

#ifndef EXAMPLE_ABI_VERSION
#define EXAMPLE_ABI_VERSION LUXLOC_PLUGIN_ABI_VERSION
#endif

typedef struct {
  long count, emitted, fail_after;
  double rate_hz, radius_m;
} example_state;

static double param(const char* params, const char* key, double fallback) {
  size_t n = strlen(key);
  const char* p = params;
  while (p && *p) {
    if (strncmp(p, key, n) == 0 && p[n] == '=') return atof(p + n + 1);
    p = strchr(p, ',');
    if (p) ++p;
  }
  return fallback;
}

static void* example_open(const char* target, const char* params, char* err, size_t err_len) {
  if (strcmp(target, "circle") != 0) {
    snprintf(err, err_len, "example-fixes: unknown target '%s' (only 'circle')", target);
    return NULL;
  }
  example_state* s = (example_state*)calloc(1, sizeof *s);
  if (!s) {
    snprintf(err, err_len, "example-fixes: out of memory");
    return NULL;
  }
  s->count = (long)param(params, "count", 200);
  s->rate_hz = param(params, "rate", 10.0);
  s->radius_m = param(params, "radius", 1.5);
  s->fail_after = (long)param(params, "fail_after", -1);
  if (s->count <= 0 || !(s->rate_hz > 0) || !(s->radius_m > 0)) {
    snprintf(err, err_len, "example-fixes: count, rate and radius must be > 0");
    free(s);
    return NULL;
  }
  return s;
}

static int example_next(void* handle, const luxloc_host* host, char* err, size_t err_len) {
  example_state* s = (example_state*)handle;
  if (host->stop_requested(host->ctx) || s->emitted >= s->count) return LUXLOC_NEXT_END;
  if (s->fail_after >= 0 && s->emitted >= s->fail_after) {
    snprintf(err, err_len, "example-fixes: simulated device failure after %ld fixes", s->emitted);
    return LUXLOC_NEXT_FAILED;
  }
  /* A device delivers at its own pace: so does this one. */
  const double period = 1.0 / s->rate_hz;
  struct timespec pause = {(time_t)period, (long)((period - (double)(time_t)period) * 1e9)};
  nanosleep(&pause, NULL);
  const double t = 1.0 + (double)s->emitted / s->rate_hz;
  /* Ten IMU samples at rest per fix interval, then the fix. */
  for (int k = 0; k < 10; ++k) {
    luxloc_imu_sample imu;
    memset(&imu, 0, sizeof imu);
    imu.t_ns = (int64_t)llround((t - (10 - k) * 0.1 / s->rate_hz) * 1e9);
    imu.acc[2] = 9.80665;
    host->push_imu(host->ctx, &imu);
  }
  const double a = 0.5 * (t - 1.0) / s->radius_m;
  luxloc_fix_sample fix = {(int64_t)llround(t * 1e9), 4.0 + s->radius_m * cos(a), 3.0 + s->radius_m * sin(a), 0.05};
  host->push_fix(host->ctx, &fix);
  ++s->emitted;
  return LUXLOC_NEXT_MORE;
}

static void example_close(void* handle) { free(handle); }

static const luxloc_source_plugin descriptor = {
    EXAMPLE_ABI_VERSION, "example-fixes", "example plugin: fixes around a circle (plugins/examples)",
    example_open, example_next, example_close};

const luxloc_source_plugin* luxloc_plugin_entry(uint32_t host_abi_version) {
  (void)host_abi_version; /* the host checks descriptor.abi_version */
  return &descriptor;
}
