// Line-of-sight vision with a cone (SPEC.md section 6, "Seeing") and the assault-horizon signal.
//
// sees(): the target is seen by the seeker when its centre is within `range` of the seeker's
// centre, inside the cone of `cone_degrees` (full angle) around the seeker's forward vector, and a
// ray cast from the seeker's centre to the target's centre (btCollisionWorld::rayTest, closest hit,
// the seeker itself ignored) hits the target before anything else. The seeker's forward vector is
// its body's local +z axis in world coordinates (DroneBody's frame). assault_horizon(): S = (f .
// a/|a|) / |a| with f the seeker's unit forward and a the vector from seeker to hider: in [-1/|a|,
// 1/|a|], largest for a close hider straight ahead; 0 when |a| = 0.
#ifndef RLT_ENV_DRONE_VISION_H_
#define RLT_ENV_DRONE_VISION_H_

#include <btBulletDynamicsCommon.h>

#include "env/drone/bullet_world.h"

namespace rlt::drone {

inline constexpr float kDefaultConeDegrees = 135.0f;  // full cone angle (half-angle 67.5)
inline constexpr float kDefaultVisionRange = 20.0f;   // m

// the unit forward vector of a body (its local +z axis)
btVector3 body_forward(const btCollisionObject& body);

bool sees(const BulletWorld& world, const btCollisionObject& seeker,
          const btCollisionObject& target, float cone_degrees = kDefaultConeDegrees,
          float range = kDefaultVisionRange);

float assault_horizon(const btVector3& forward, const btVector3& seeker_position,
                      const btVector3& target_position);

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_VISION_H_
