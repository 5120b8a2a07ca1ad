// RaySensor: sphere casts in the layout of Unity ML-Agents' RayPerceptionSensor3D
// (com.unity.ml-agents/Runtime/Sensors/RayPerceptionSensor.cs), SPEC.md section 6 "rays".
//
// Rays: 2 * rays_per_direction + 1 (17 by default), horizontal, from the centre of `self`.
// Ray i has the ML-Agents angle theta_i (degrees, 90 = straight ahead), delta =
// max_ray_degrees / rays_per_direction:
//   theta_0 = 90; theta_{2k+1} = 90 - (k+1) delta (towards `right`); theta_{2k+2} = 90 + (k+1)
//   delta
// for k = 0 .. rays_per_direction - 1, and direction_i = cos(theta_i) right + sin(theta_i) forward,
// with forward and right the horizontal axes of DroneBody (forward = basis * +z, right = forward x
// up). So the order is forward, then right/left pairs fanning out. With the default 180 degrees
// and 8 per direction (delta 22.5) the rays cover 360 degrees and, as in ML-Agents, the last pair
// both point straight back.
// Each ray sweeps a sphere of radius sphere_radius from the centre over ray_length metres and keeps
// the closest hit, ignoring `self`. A body that already touches the sphere at the start is reported
// at fraction 0 if the ray points into it and missed otherwise (Bullet's
// btContinuousConvexCollision rule, see sphere_cast.h); around a drone of radius 0.35 m nothing
// touches a 0.3 m sphere unless bodies interpenetrate. Two implementations with the same output:
//   observe(ShapeSnapshot, ...): analytic casts against a snapshot of the world (shape_snapshot.h,
//     sphere_cast.h); boxes are Bullet's boxes, edges rounded by their collision margin as Bullet's
//     GJK sees them (0.04 m; a tenth of the smallest half extent for thinner boxes, 0.01 m for the
//     0.2 m walls). observe(btCollisionWorld, ...) captures a snapshot and does the same.
//   observe_with_bullet_sweeps(): one btCollisionWorld::convexSweepTest per ray, the reference.
//     It reads the broadphase AABBs (updated by a step or updateAabbs()); it also accepts shapes
//     the snapshot does not know. Its fractions are those of conservative advancement, which stops
//     within 1 mm of contact: a cast passing within 1 mm of a shape is a hit for Bullet only, and
//     along a grazing cast its fraction can be centimetres short.
//   Differences (ray_sensor_test, agreement on random scenes): the snapshot misses those 1 mm
//   grazes, and a sphere starting in contact with a body and moving along the contact plane is a
//   miss for the snapshot, a hit at 0 or a miss for Bullet by GJK/EPA round-off.
// Cost (tests/env/drone/ray_sensor_timing.cpp, Release, -march=native, one core of a shared
// 2-core machine): the level-4 Arena, 4 drones, 4 props, 5 obstacles (29 boxes, 4 spheres), 17
// rays: Bullet sweeps 35-39 us per observation; snapshot 1.7-1.9 us per observation (1.65-1.85 us
// casting + 0.4 us per frame for the capture, shared by the 4 drones). Rays disagreeing: 9 in
// 68000, all 1 mm grazes (obstacle tops at the height of a hovering drone's sphere, room corners).
// Output per ray, kNumTags + 2 = 7 floats, rays in the order above (119 floats by default):
//   [0, kNumTags): one-hot of the hit body's Tag (kWall, kProp, kObstacle, kHider, kSeeker), zeros
//                  on a miss;
//   kNumTags:      1 on a miss, else 0;
//   kNumTags + 1:  hit fraction in [0, 1], the fraction of ray_length the sphere's centre travelled
//                  before touching (1 on a miss). A plane facing the ray at distance d from the
//                  centre gives (d - sphere_radius) / ray_length.
#ifndef RLT_ENV_DRONE_RAY_SENSOR_H_
#define RLT_ENV_DRONE_RAY_SENSOR_H_

#include <btBulletDynamicsCommon.h>

#include <vector>

#include "env/drone/bullet_world.h"
#include "env/drone/shape_snapshot.h"

namespace rlt::drone {

struct RaySensorParams {
  int rays_per_direction = 8;      // rays on each side of forward (0-32)
  float max_ray_degrees = 180.0f;  // angle of the outermost pair from forward (degrees, (0, 180])
  float ray_length = 20.0f;        // sweep length (m)
  float sphere_radius = 0.3f;      // radius of the swept sphere (m); 0 for thin rays
};

class RaySensor {
 public:
  static constexpr int kFloatsPerRay = kNumTags + 2;

  explicit RaySensor(const RaySensorParams& params = {});

  int num_rays() const { return static_cast<int>(angles_.size()); }
  int size() const { return num_rays() * kFloatsPerRay; }  // floats written by observe()
  // the ML-Agents angle of ray i (degrees, 90 = forward)
  float angle(int i) const { return angles_[i]; }
  // world direction of ray i for a body with this pose (unit, horizontal)
  btVector3 direction(const btTransform& pose, int i) const;

  // casts every ray from `self` against `scene` (a snapshot of self's world, self included) and
  // writes size() floats to `out`
  void observe(const ShapeSnapshot& scene, const btCollisionObject& self, float* out) const;
  // the same for `world`, through a snapshot of it taken now (one per thread, reused); for several
  // drones of one frame, capture a ShapeSnapshot once and use the overload above. Throws
  // std::invalid_argument on shapes other than boxes and spheres.
  void observe(const btCollisionWorld& world, const btCollisionObject& self, float* out) const;
  // the reference: one Bullet convexSweepTest per ray (see the header comment)
  void observe_with_bullet_sweeps(const btCollisionWorld& world, const btCollisionObject& self,
                                  float* out) const;

 private:
  RaySensorParams params_;
  std::vector<float> angles_;     // [num_rays] degrees
  std::vector<float> cos_, sin_;  // [num_rays] cos and sin of the angles
  btSphereShape sphere_;
};

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_RAY_SENSOR_H_
