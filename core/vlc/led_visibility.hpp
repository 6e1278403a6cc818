#pragma once
// How far apart two ceiling LEDs can be and still appear in one camera frame: the rule
// behind frequency reuse (SPEC.md "LED map": two LEDs of one class must never be in view
// together). The camera looks up at a ceiling dz above it; a tilt of up to max_tilt_rad
// stretches its footprint on the far side more than it shrinks it on the near one.
#include <string>

#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"

namespace luxloc {

// Half-angle of the image diagonal (from the undistorted bearings of the image corners).
double half_diagonal_fov_rad(const CameraModel& camera);
// Largest horizontal distance between two points of the ceiling plane dz above the camera
// that can both be in one image, for a camera within max_tilt_rad of looking straight up:
// dz (tan(a + tilt) + tan(a - tilt)) with a the half-diagonal (a + tilt capped at 80 deg).
double co_visibility_distance_m(const CameraModel& camera, double dz_m, double max_tilt_rad);

// SPEC.md: rejects (InputError naming `origin`, the two LEDs and freq_hz) a map in which two
// LEDs of one frequency class are closer than the co-visibility distance of a level camera
// at the given device height (the loosest reading: a map that fails it is ambiguous in
// plain view). No-op for a map without reuse.
void check_frequency_reuse(const LedMap& map, const CameraModel& camera, double device_height_m,
                           const std::string& origin);

}  // namespace luxloc
