// RaySensor: hand-built scenes with known answers (a wall at a known distance, a drone to the
// right, an empty world), the ML-Agents ray order, and rays that ignore the casting drone.
#include "env/drone/ray_sensor.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"

namespace rlt::drone {
namespace {

constexpr int kTagged = RaySensor::kFloatsPerRay;
constexpr float kPi = 3.14159265358979f;

struct Ray {
  const float* p;
  bool miss() const { return p[kNumTags] == 1.0f; }
  float fraction() const { return p[kNumTags + 1]; }
  int tag() const {
    int found = -1;
    for (int t = 0; t < kNumTags; ++t) {
      if (p[t] == 1.0f) found = t;
    }
    return found;
  }
};

std::vector<float> observe(const RaySensor& sensor, BulletWorld& world,
                           const btCollisionObject& self) {
  // ray tests read broadphase aabbs, which a world updates on a step or on request
  world.world().updateAabbs();
  std::vector<float> out(sensor.size(), -7.0f);
  sensor.observe(world.world(), self, out.data());
  return out;
}

TEST(RaySensorTest, LayoutFollowsMlAgents) {
  RaySensor sensor;
  EXPECT_EQ(sensor.num_rays(), 17);
  EXPECT_EQ(sensor.size(), 17 * 7);
  // forward, then right/left pairs fanning out by 22.5 degrees; the last pair both point back
  EXPECT_FLOAT_EQ(sensor.angle(0), 90.0f);
  EXPECT_FLOAT_EQ(sensor.angle(1), 67.5f);
  EXPECT_FLOAT_EQ(sensor.angle(2), 112.5f);
  EXPECT_FLOAT_EQ(sensor.angle(15), -90.0f);
  EXPECT_FLOAT_EQ(sensor.angle(16), 270.0f);
  // yaw 0 faces +z; right is forward x up = -x
  btTransform pose;
  pose.setIdentity();
  EXPECT_NEAR(sensor.direction(pose, 0).z(), 1.0f, 1e-6f);
  EXPECT_NEAR(sensor.direction(pose, 7).x(), -1.0f, 1e-6f);  // theta = 0: straight right
  EXPECT_NEAR(sensor.direction(pose, 8).x(), 1.0f, 1e-6f);   // theta = 180: straight left
  EXPECT_NEAR(sensor.direction(pose, 15).z(), -1.0f, 1e-6f);
  EXPECT_NEAR(sensor.direction(pose, 16).z(), -1.0f, 1e-6f);
}

TEST(RaySensorTest, WallAtKnownDistanceAndFreeDirectionsMiss) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 1, 0), 0.0f, kSeeker);
  // a 2 m wide wall whose near face is 5 m ahead
  world.add_static_box(btVector3(0, 1, 5.5f), btVector3(1, 2, 0.5f), kWall);
  RaySensor sensor;
  const std::vector<float> out = observe(sensor, world, drone.body());
  for (float x : out) ASSERT_TRUE(x == 0.0f || x == 1.0f || (x > 0.0f && x < 1.0f)) << x;

  // forward: the 0.3 m sphere touches the face when its centre is 4.7 m out
  const Ray forward{out.data()};
  EXPECT_FALSE(forward.miss());
  EXPECT_EQ(forward.tag(), kWall);
  EXPECT_NEAR(forward.fraction(), (5.0f - 0.3f) / 20.0f, 1e-3f);
  // every other ray passes the wall's edges (22.5 degrees off reaches x = 2.07 m at z = 5)
  for (int i = 1; i < sensor.num_rays(); ++i) {
    const Ray ray{out.data() + i * kTagged};
    EXPECT_TRUE(ray.miss()) << "ray " << i;
    EXPECT_EQ(ray.tag(), -1) << "ray " << i;
    EXPECT_EQ(ray.fraction(), 1.0f) << "ray " << i;
  }
}

TEST(RaySensorTest, RaysTurnWithTheDrone) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 1, 0), kPi / 2, kHider);  // facing +x
  world.add_static_box(btVector3(3.5f, 1, 0), btVector3(0.5f, 2, 1), kWall);
  RaySensor sensor;
  const std::vector<float> out = observe(sensor, world, drone.body());
  EXPECT_EQ(Ray{out.data()}.tag(), kWall);
  EXPECT_NEAR(Ray{out.data()}.fraction(), (3.0f - 0.3f) / 20.0f, 1e-3f);
}

TEST(RaySensorTest, OtherDroneToTheRightGivesItsTag) {
  BulletWorld world;
  DroneBody seeker(world, btVector3(0, 1, 0), 0.0f, kSeeker);
  DroneBody hider(world, btVector3(-4, 1, 0), 0.0f, kHider);  // straight right of the seeker
  RaySensor sensor;
  const std::vector<float> out = observe(sensor, world, seeker.body());
  const Ray right{out.data() + 7 * kTagged};
  EXPECT_EQ(right.tag(), kHider);
  // centres 4 m apart, radii 0.35 (drone) + 0.3 (sphere)
  EXPECT_NEAR(right.fraction(), (4.0f - 0.65f) / 20.0f, 1e-3f);
  for (int i = 0; i < sensor.num_rays(); ++i) {
    if (i == 7) continue;
    EXPECT_TRUE(Ray{out.data() + i * kTagged}.miss()) << "ray " << i;
  }
  // and the hider sees the seeker on its left (ray 8), not itself
  const std::vector<float> back = observe(sensor, world, hider.body());
  EXPECT_EQ(Ray{back.data() + 8 * kTagged}.tag(), kSeeker);
  EXPECT_TRUE(Ray{back.data() + 7 * kTagged}.miss());
}

TEST(RaySensorTest, RaysIgnoreTheCastingDrone) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 1, 0), 0.3f, kSeeker);
  RaySensor sensor;
  const std::vector<float> out = observe(sensor, world, drone.body());
  for (int i = 0; i < sensor.num_rays(); ++i) {
    EXPECT_TRUE(Ray{out.data() + i * kTagged}.miss()) << "ray " << i;
  }
  // control: the same sweep cast 1 m behind the drone on behalf of another object hits it
  btCollisionObject other;
  btTransform behind = drone.body().getWorldTransform();
  behind.setOrigin(behind.getOrigin() - drone.forward());
  other.setWorldTransform(behind);
  const std::vector<float> control = observe(sensor, world, other);
  EXPECT_EQ(Ray{control.data()}.tag(), kSeeker);
  EXPECT_NEAR(Ray{control.data()}.fraction(), (1.0f - 0.65f) / 20.0f, 1e-3f);
}

TEST(RaySensorTest, CostInAWalledArena) {
  // a 24 x 24 m arena with floor, ceiling, four walls, a few boxes and four drones
  BulletWorld world;
  world.add_static_box(btVector3(0, -0.5f, 0), btVector3(12, 0.5f, 12), kWall);
  world.add_static_box(btVector3(0, 6.5f, 0), btVector3(12, 0.5f, 12), kWall);
  world.add_static_box(btVector3(12.5f, 3, 0), btVector3(0.5f, 3, 12), kWall);
  world.add_static_box(btVector3(-12.5f, 3, 0), btVector3(0.5f, 3, 12), kWall);
  world.add_static_box(btVector3(0, 3, 12.5f), btVector3(12, 3, 0.5f), kWall);
  world.add_static_box(btVector3(0, 3, -12.5f), btVector3(12, 3, 0.5f), kWall);
  for (int i = 0; i < 5; ++i) {
    world.add_static_box(btVector3(-8.0f + 4 * i, 1, 3), btVector3(0.5f, 1, 0.5f), kObstacle);
  }
  std::vector<DroneBody> drones;
  for (int i = 0; i < 4; ++i) {
    drones.emplace_back(world, btVector3(-6.0f + 4 * i, 1.5f, -4), 0.7f * i,
                        i < 2 ? kHider : kSeeker);
  }
  RaySensor sensor;
  world.world().updateAabbs();
  std::vector<float> out(sensor.size());
  const int reps = 500;
  const auto t0 = std::chrono::steady_clock::now();
  int hits = 0;
  for (int r = 0; r < reps; ++r) {
    for (const DroneBody& d : drones) {
      sensor.observe(world.world(), d.body(), out.data());
      hits += out[kNumTags] == 0.0f;
    }
  }
  const double us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() /
      (reps * drones.size());
  std::printf("ray sensor: %.1f us per observation of %d sphere casts\n", us, sensor.num_rays());
  EXPECT_GT(hits, 0);
}

}  // namespace
}  // namespace rlt::drone
