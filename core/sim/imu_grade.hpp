#pragma once
// IMU grades for the simulator (docs/SIMULATOR.md "IMU grades"): named ImuNoise sets from an
// ideal sensor to a poor MEMS part, selectable per scenario and with `luxloc sim --imu-grade`.
// "default" is the simulator's historic IMU (its sessions stay bit-identical).
#include <string>
#include <vector>

#include "core/sim/imu_synth.hpp"

namespace luxloc::sim {

// "default", "ideal", "tactical", "consumer", "poor".
std::vector<std::string> imu_grade_names();
// Throws std::invalid_argument naming the grades for an unknown name.
ImuNoise imu_grade(const std::string& name);

}  // namespace luxloc::sim
