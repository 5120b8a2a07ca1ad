#include "env/drone/ray_sensor.h"

#include <cmath>
#include <stdexcept>

#include "env/drone/sphere_cast.h"

namespace rlt::drone {

namespace {

constexpr float kDegrees = 3.14159265358979f / 180.0f;

// closest hit of a sweep, ignoring the casting body
struct NotSelfCallback : btCollisionWorld::ClosestConvexResultCallback {
  NotSelfCallback(const btCollisionObject* self, const btVector3& from, const btVector3& to)
      : ClosestConvexResultCallback(from, to), self(self) {}
  bool needsCollision(btBroadphaseProxy* proxy) const override {
    if (proxy->m_clientObject == self) return false;
    return ClosestConvexResultCallback::needsCollision(proxy);
  }
  const btCollisionObject* self;
};

}  // namespace

RaySensor::RaySensor(const RaySensorParams& params)
    : params_(params), sphere_(params.sphere_radius > 0 ? params.sphere_radius : 1e-4f) {
  if (params_.rays_per_direction < 0 || params_.rays_per_direction > 32)
    throw std::invalid_argument("RaySensor: rays_per_direction must be in [0, 32]");
  if (!(params_.max_ray_degrees > 0 && params_.max_ray_degrees <= 180))
    throw std::invalid_argument("RaySensor: max_ray_degrees must be in (0, 180]");
  if (!(params_.ray_length > 0)) throw std::invalid_argument("RaySensor: ray_length must be > 0");
  // ML-Agents RayPerceptionSensorComponentBase.GetRayAngles
  const float delta = params_.max_ray_degrees / std::max(params_.rays_per_direction, 1);
  angles_.push_back(90.0f);
  for (int k = 0; k < params_.rays_per_direction; ++k) {
    angles_.push_back(90.0f - (k + 1) * delta);
    angles_.push_back(90.0f + (k + 1) * delta);
  }
  for (float degrees : angles_) {
    cos_.push_back(std::cos(degrees * kDegrees));
    sin_.push_back(std::sin(degrees * kDegrees));
  }
}

btVector3 RaySensor::direction(const btTransform& pose, int i) const {
  btVector3 forward = pose.getBasis() * btVector3(0, 0, 1);
  forward.setY(0);
  forward.normalize();
  const btVector3 right = forward.cross(btVector3(0, 1, 0));
  return cos_[i] * right + sin_[i] * forward;
}

void RaySensor::observe(const ShapeSnapshot& scene, const btCollisionObject& self,
                        float* out) const {
  const btTransform& pose = self.getWorldTransform();
  const btVector3 origin = pose.getOrigin();
  btVector3 forward = pose.getBasis() * btVector3(0, 0, 1);
  forward.setY(0);
  forward.normalize();
  const btVector3 right = forward.cross(btVector3(0, 1, 0));
  btVector3 directions[kMaxFanRays];
  for (int i = 0; i < num_rays(); ++i) directions[i] = cos_[i] * right + sin_[i] * forward;
  CastHit hits[kMaxFanRays];
  first_hits(scene, origin, directions, num_rays(), params_.ray_length, params_.sphere_radius,
             &self, hits);
  for (int i = 0; i < num_rays(); ++i) {
    float* ray = out + i * kFloatsPerRay;
    const CastHit& hit = hits[i];
    for (int t = 0; t < kFloatsPerRay; ++t) ray[t] = 0.0f;
    if (hit.hit()) {
      if (hit.tag >= 0 && hit.tag < kNumTags) ray[hit.tag] = 1.0f;
      ray[kNumTags + 1] = hit.fraction;
    } else {
      ray[kNumTags] = 1.0f;
      ray[kNumTags + 1] = 1.0f;
    }
  }
}

void RaySensor::observe(const btCollisionWorld& world, const btCollisionObject& self,
                        float* out) const {
  thread_local ShapeSnapshot scene;
  scene.capture(world);
  observe(scene, self, out);
}

void RaySensor::observe_with_bullet_sweeps(const btCollisionWorld& world,
                                           const btCollisionObject& self, float* out) const {
  const btTransform& pose = self.getWorldTransform();
  const btVector3 origin = pose.getOrigin();
  for (int i = 0; i < num_rays(); ++i) {
    float* ray = out + i * kFloatsPerRay;
    const btVector3 end = origin + params_.ray_length * direction(pose, i);
    NotSelfCallback hit(&self, origin, end);
    world.convexSweepTest(&sphere_, btTransform(btQuaternion::getIdentity(), origin),
                          btTransform(btQuaternion::getIdentity(), end), hit);
    for (int t = 0; t < kFloatsPerRay; ++t) ray[t] = 0.0f;
    if (hit.hasHit() && hit.m_hitCollisionObject) {
      const int tag = tag_of(*hit.m_hitCollisionObject);
      if (tag >= 0 && tag < kNumTags) ray[tag] = 1.0f;
      ray[kNumTags + 1] = static_cast<float>(hit.m_closestHitFraction);
    } else {
      ray[kNumTags] = 1.0f;
      ray[kNumTags + 1] = 1.0f;
    }
  }
}

}  // namespace rlt::drone
