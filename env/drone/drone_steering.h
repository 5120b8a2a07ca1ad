// Steering for scripted drones: the four continuous actions (forward, strafe, vertical, yaw rate,
// each in [-1, 1]; DroneBody's convention) that fly a drone to a point while it faces another.
//
// Motion: a desired velocity towards `target` of min(speed, gain * distance) (so the drone slows
// down as it arrives), and thrust proportional to the velocity error, expressed in the drone's
// forward / right / up axes. Heading: yaw rate proportional to the heading error towards `face`
// (ignored when `face` is within 5 cm of the drone horizontally).
#pragma once

#include <array>

#include "env/drone/drone_body.h"

namespace rlt::drone {

struct SteeringGains {
  float speed = 4.0f;        // cruising speed (m/s), at most the drone's max_speed
  float arrive_gain = 1.5f;  // desired speed per metre of distance left (1/s)
  float velocity_gain = 4.0f;  // acceleration per m/s of velocity error (1/s)
  float yaw_gain = 2.5f;     // yaw-rate action per radian of heading error
};

// actions {forward, strafe, vertical, yaw_rate} in [-1, 1]
std::array<float, 4> steer(const DroneBody& drone, const btVector3& target, const btVector3& face,
                           const SteeringGains& gains = {});

// heading error in (-pi, pi] from the drone's forward to the horizontal direction of `face`
float heading_error(const DroneBody& drone, const btVector3& face);

}  // namespace rlt::drone
