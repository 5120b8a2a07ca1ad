#include "env/drone/vision.h"

#include <cmath>

namespace rlt::drone {
namespace {

// the closest hit along a ray, skipping one object (the seeker, whose centre the ray starts in)
struct ClosestExcept : btCollisionWorld::ClosestRayResultCallback {
  ClosestExcept(const btVector3& from, const btVector3& to, const btCollisionObject* skip)
      : ClosestRayResultCallback(from, to), skip_(skip) {}
  bool needsCollision(btBroadphaseProxy* proxy) const override {
    if (static_cast<const btCollisionObject*>(proxy->m_clientObject) == skip_) return false;
    return ClosestRayResultCallback::needsCollision(proxy);
  }
  const btCollisionObject* skip_;
};

}  // namespace

btVector3 body_forward(const btCollisionObject& body) {
  return body.getWorldTransform().getBasis() * btVector3(0, 0, 1);
}

bool sees(const BulletWorld& world, const btCollisionObject& seeker,
          const btCollisionObject& target, float cone_degrees, float range) {
  const btVector3 from = seeker.getWorldTransform().getOrigin();
  const btVector3 to = target.getWorldTransform().getOrigin();
  const btVector3 a = to - from;
  const btScalar distance = a.length();
  if (distance > range) return false;
  if (distance > 0) {
    const float half_angle = 0.5f * cone_degrees * static_cast<float>(M_PI) / 180.0f;
    const btScalar cos_angle = body_forward(seeker).dot(a) / distance;
    if (cos_angle < std::cos(half_angle)) return false;
  }
  ClosestExcept ray(from, to, &seeker);
  world.world().rayTest(from, to, ray);
  // the ray ends at the target's centre, so it hits the target's surface unless blocked first
  return !ray.hasHit() || ray.m_collisionObject == &target;
}

float assault_horizon(const btVector3& forward, const btVector3& seeker_position,
                      const btVector3& target_position) {
  const btVector3 a = target_position - seeker_position;
  const btScalar d2 = a.length2();
  if (d2 <= 0) return 0.0f;
  return static_cast<float>(forward.normalized().dot(a) / d2);
}

}  // namespace rlt::drone
