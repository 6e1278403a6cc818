#pragma once
// The particles as a structure of arrays in single precision, 32-byte aligned so every
// 256-particle block is an aligned AVX2 stream (and Eigen's block reductions sum in the
// same order whatever the allocation: results stay bit-identical across runs and
// thread counts). Floats halve the memory traffic, which bounds a 1M-particle step;
// positions are kept relative to an origin (ParticleFilter::origin()) so single
// precision stays at micrometres even on a map in projected coordinates.
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <tbb/parallel_for.h>
#include <vector>

namespace luxloc {

using FloatVector = std::vector<float, Eigen::aligned_allocator<float>>;

struct ParticleSet {
  FloatVector x, y;    // m, relative to the filter's origin
  FloatVector vx, vy;  // m/s, world frame
  // Gait calibration of the pedestrian motion model (core/filter/motion_model.hpp): step-
  // length scale, heading offset (rad) and the walker's slowdown in turns (m/rad: metres lost
  // per radian turned). Empty unless `gait` (other models do not pay for them in the
  // resampling gather).
  FloatVector ks, dpsi, kturn;
  bool gait = false;
  // Yaw offset of the attitude filter (rad; core/filter/heading_noise.hpp): true device
  // yaw = AHRS yaw + yaw[i]. Empty unless `heading`.
  FloatVector yaw;
  bool heading = false;
  std::size_t size() const { return x.size(); }
  void resize(std::size_t n) {
    x.resize(n);
    y.resize(n);
    vx.resize(n);
    vy.resize(n);
    ks.resize(gait ? n : 0);
    dpsi.resize(gait ? n : 0);
    kturn.resize(gait ? n : 0);
    yaw.resize(heading ? n : 0);
  }
};

// Work is split into fixed chunks, each with its own random stream keyed by
// (seed, step, chunk): the numbers a particle gets do not depend on the thread count.
inline constexpr std::size_t kParticleChunk = 4096;
inline std::size_t particle_chunks(std::size_t n) { return (n + kParticleChunk - 1) / kParticleChunk; }

// f(chunk, begin, end) for every chunk of [0, n), in parallel when there are several.
template <typename F>
void for_each_particle_chunk(std::size_t n, F&& f) {
  const std::size_t chunks = particle_chunks(n);
  if (chunks <= 1) {
    if (n) f(std::size_t{0}, std::size_t{0}, n);
    return;
  }
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    f(c, c * kParticleChunk, std::min(n, (c + 1) * kParticleChunk));
  });
}

}  // namespace luxloc
