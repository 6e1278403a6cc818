/* luxloc external source plugins: the versioned C ABI (`luxloc run --plugin PATH.so`).
 *
 * A plugin is a shared library exporting one function,
 *
 *     const luxloc_source_plugin* luxloc_plugin_entry(uint32_t host_abi_version);
 *
 * which returns its descriptor (or NULL when it cannot serve that host version). The
 * descriptor names the source kind it provides (`--source KIND:TARGET[,key=value...]`).
 * The host owns the threads and the queues: it calls `next` again and again from the
 * source's own pipeline thread; during each call the plugin pushes zero or more
 * timestamped samples through the host's callbacks (copied at once: the plugin keeps
 * ownership of its buffers). All times are int64 nanoseconds on the plugin's clock; use
 * CLOCK_MONOTONIC to share the timeline of luxloc's own live sources. Units and frames are
 * SPEC.md's (SI, body FLU, world ENU).
 *
 * Versioning: LUXLOC_PLUGIN_ABI_VERSION changes whenever a struct below changes; the host
 * refuses a descriptor whose abi_version differs from its own, with a clear message.
 */
#ifndef LUXLOC_PLUGIN_H
#define LUXLOC_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LUXLOC_PLUGIN_ABI_VERSION 1u

typedef struct luxloc_imu_sample {
  int64_t t_ns;
  double acc[3];  /* specific force, m/s^2, body frame (+9.81 on z at rest) */
  double gyro[3]; /* rad/s */
  double mag[3];  /* microtesla, when has_mag */
  int has_mag;
} luxloc_imu_sample;

typedef struct luxloc_frame_sample {
  int64_t t_ns; /* start of exposure of row 0 */
  int width, height;
  int stride;            /* bytes per row */
  const uint8_t* gray;   /* 8-bit gray, rows in rolling-shutter readout order */
} luxloc_frame_sample;

typedef struct luxloc_fix_sample {
  int64_t t_ns;
  double x, y;    /* world, m */
  double sigma_m; /* 1 sigma; <= 0 or NaN: unknown */
} luxloc_fix_sample;

typedef struct luxloc_uwb_sample {
  int64_t t_ns;
  int anchor;
  double range_m;
  double aoa_rad; /* NaN when absent */
} luxloc_uwb_sample;

/* What the host gives the plugin. Each push returns 0 when the sample was taken, nonzero
 * when it was refused (non-finite values: counted by the host). */
typedef struct luxloc_host {
  uint32_t abi_version;
  void* ctx;
  int (*push_imu)(void* ctx, const luxloc_imu_sample* s);
  int (*push_frame)(void* ctx, const luxloc_frame_sample* s);
  int (*push_fix)(void* ctx, const luxloc_fix_sample* s);
  int (*push_uwb)(void* ctx, const luxloc_uwb_sample* s);
  /* Nonzero once the run is stopping (Ctrl-C, end of the other sources): return soon. */
  int (*stop_requested)(void* ctx);
} luxloc_host;

enum { LUXLOC_NEXT_MORE = 1, LUXLOC_NEXT_END = 0, LUXLOC_NEXT_FAILED = -1 };

typedef struct luxloc_source_plugin {
  uint32_t abi_version; /* LUXLOC_PLUGIN_ABI_VERSION the plugin was built with */
  const char* kind;     /* source kind, e.g. "example-fixes" */
  const char* description;
  /* Opens a source. `target` is what follows KIND:, `params` the "key=value,..." rest (may
   * be empty). Returns a handle, or NULL with a message in err (err_len bytes). */
  void* (*open)(const char* target, const char* params, char* err, size_t err_len);
  /* Pushes the next sample(s) through `host`; blocks at most ~200 ms when it has none.
   * Returns LUXLOC_NEXT_MORE, LUXLOC_NEXT_END, or LUXLOC_NEXT_FAILED with a message in err. */
  int (*next)(void* handle, const luxloc_host* host, char* err, size_t err_len);
  void (*close)(void* handle);
} luxloc_source_plugin;

typedef const luxloc_source_plugin* (*luxloc_plugin_entry_fn)(uint32_t host_abi_version);

#ifdef __cplusplus
}
#endif

#endif /* LUXLOC_PLUGIN_H */
