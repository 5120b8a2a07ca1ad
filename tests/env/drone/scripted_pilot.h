// A scripted pilot for the drone task tests: from a drone's own vector observation (the DroneTask
// common block) and a world-frame offset to a goal, the 4 actions that fly it there.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "env/drone/drone_task.h"

namespace rlt::drone {

// Desired velocity gain * offset (capped at cruise m/s), thrust proportional to the velocity
// error, expressed in the drone's forward/right/up frame; yaw turns towards the goal when `turn`.
inline std::array<float, 4> pilot_actions(const float* obs, float dx, float dy, float dz,
                                          float max_speed, float cruise = 4.f, float gain = 2.f,
                                          bool turn = false) {
  const float v[3] = {obs[3] * max_speed, obs[4] * max_speed, obs[5] * max_speed};
  const float fx = obs[6], fz = obs[8];
  const float rx = -fz, rz = fx;  // right = forward x up
  float des[3] = {gain * dx, gain * dy, gain * dz};
  const float len = std::sqrt(des[0] * des[0] + des[1] * des[1] + des[2] * des[2]);
  if (len > cruise)
    for (float& c : des) c *= cruise / len;
  const float F[3] = {des[0] - v[0], des[1] - v[1], des[2] - v[2]};
  auto clip = [](float x) { return std::clamp(x, -1.f, 1.f); };
  float yaw = 0.f;
  if (turn) {
    // signed angle from forward to the goal's horizontal direction; positive yaw turns +z to +x
    const float cross = fz * dx - fx * dz;
    const float dot = fx * dx + fz * dz;
    yaw = clip(2.f * std::atan2(cross, dot));
  }
  return {clip(F[0] * fx + F[2] * fz), clip(F[0] * rx + F[2] * rz), clip(F[1]), yaw};
}

// the world-frame offset encoded by DroneTask::write_relative
inline std::array<float, 3> decode_relative(const float* rel, const DroneTaskSettings& s) {
  return {rel[0] * 2.f * s.arena.half_size, rel[1] * s.arena.height,
          rel[2] * 2.f * s.arena.half_size};
}

}  // namespace rlt::drone
