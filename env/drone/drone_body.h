// DroneBody: an upright drone as a Bullet rigid body (SPEC.md section 6, "Drones").
//
// A sphere (radius 0.35 m, mass 1 kg) that ignores world gravity, with linear and angular damping,
// rotation only about y (it stays upright whatever hits it) and continuous collision detection,
// so that it cannot pass through a wall at any speed.
// Frame: at yaw 0 the drone faces +z; positive yaw turns +z towards +x (right-handed about +y).
// forward = (sin yaw, 0, cos yaw), right = forward x up = (-cos yaw, 0, sin yaw), up = +y.
// Actions, each clipped to [-1, 1], held for the frame they are applied in:
//   forward  -> force forward * max_force along `forward`,
//   strafe   -> force strafe * max_force along `right`,
//   vertical -> force vertical * max_force along +y,
//   yaw_rate -> angular velocity yaw_rate * max_yaw_rate about +y (set, not integrated).
// apply_action() also caps the speed: a faster drone (after a push) is slowed to max_speed and the
// thrust is trimmed so that the frame's integration cannot exceed it (contacts still may).
#ifndef RLT_ENV_DRONE_DRONE_BODY_H_
#define RLT_ENV_DRONE_DRONE_BODY_H_

#include <btBulletDynamicsCommon.h>

#include "env/drone/bullet_world.h"

namespace rlt::drone {

struct DroneParams {
  float radius = 0.35f;         // sphere radius (m)
  float mass = 1.0f;            // kg
  float max_force = 20.0f;      // thrust at action 1 (N)
  float max_speed = 5.0f;       // speed cap (m/s)
  float max_yaw_rate = 3.0f;    // yaw rate at action 1 (rad/s)
  float linear_damping = 0.5f;  // Bullet damping (fraction of velocity lost per second)
  float angular_damping = 0.9f;
  bool ccd = true;  // continuous collision detection (off only to show it matters)
};

class DroneBody {
 public:
  // adds the drone to `world`; the body lives until the world is reset or destroyed
  DroneBody(BulletWorld& world, const btVector3& position, float yaw, Tag tag,
            const DroneParams& params = {});

  // sets thrust and yaw rate for the next frame and caps the speed
  void apply_action(float forward, float strafe, float vertical, float yaw_rate);
  // scales the linear velocity down to max_speed if it is faster
  void cap_speed();

  btVector3 position() const;
  btVector3 velocity() const { return body_->getLinearVelocity(); }
  btVector3 forward() const;  // unit, horizontal
  btVector3 right() const;    // unit, horizontal, forward x up
  float yaw() const;          // radians in (-pi, pi]
  btRigidBody& body() { return *body_; }
  const btRigidBody& body() const { return *body_; }
  const DroneParams& params() const { return params_; }

 private:
  DroneParams params_;
  float dt_;           // frame length of the world (s)
  btRigidBody* body_;  // owned by the world
};

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_DRONE_BODY_H_
