#include "env/drone/drone_steering.h"

#include <algorithm>
#include <cmath>

namespace rlt::drone {

namespace {
constexpr float kPi = 3.14159265358979f;
float clip1(float x) { return std::clamp(x, -1.0f, 1.0f); }
}  // namespace

float heading_error(const DroneBody& drone, const btVector3& face) {
  const btVector3 to = face - drone.position();
  if (to.x() * to.x() + to.z() * to.z() < 0.05f * 0.05f) return 0.0f;
  float e = std::atan2(to.x(), to.z()) - drone.yaw();
  while (e > kPi) e -= 2 * kPi;
  while (e <= -kPi) e += 2 * kPi;
  return e;
}

std::array<float, 4> steer(const DroneBody& drone, const btVector3& target, const btVector3& face,
                           const SteeringGains& gains) {
  const DroneParams& p = drone.params();
  const btVector3 to = target - drone.position();
  const float distance = to.length();
  btVector3 desired(0, 0, 0);
  if (distance > 1e-4f) {
    const float speed = std::min({gains.speed, p.max_speed, gains.arrive_gain * distance});
    desired = to * (speed / distance);
  }
  // force for the velocity error, in units of max_force
  const btVector3 force = (desired - drone.velocity()) * (gains.velocity_gain * p.mass / p.max_force);
  return {clip1(force.dot(drone.forward())), clip1(force.dot(drone.right())), clip1(force.y()),
          clip1(gains.yaw_gain * heading_error(drone, face))};
}

}  // namespace rlt::drone
