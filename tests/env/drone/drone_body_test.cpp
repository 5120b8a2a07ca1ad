// DroneBody physics invariants: no tunnelling through the thinnest wall with CCD (and tunnelling
// without it, so the test can fail), no gravity, upright after collisions, the speed cap, and the
// action frame.
#include "env/drone/drone_body.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "env/drone/bullet_world.h"

namespace rlt::drone {
namespace {

constexpr float kWallHalf = 0.05f;  // the thinnest wall: 0.1 m

// fires a drone along +z at `speed` from z = start at a 0.1 m wall at z = 0 for 100 frames with no
// action (so no speed cap); returns the largest z the centre reached
float fire_at_thin_wall(float speed, float start, bool ccd) {
  BulletWorld world;
  world.add_static_box(btVector3(0, 1, 0), btVector3(5, 5, kWallHalf), kWall);
  DroneParams params;
  params.ccd = ccd;
  DroneBody drone(world, btVector3(0, 1, start), 0.0f, kHider, params);
  drone.body().setLinearVelocity(btVector3(0, 0, speed));
  float max_z = start;
  for (int f = 0; f < 100; ++f) {
    world.step_frame();
    max_z = std::max(max_z, static_cast<float>(drone.position().z()));
  }
  return max_z;
}

TEST(DroneBodyTest, CcdStopsTenTimesTopSpeedAtTheThinnestWall) {
  const float top = DroneParams{}.max_speed;
  for (float factor : {10.0f, 20.0f, 40.0f}) {
    int passed_with_ccd = 0, passed_without = 0;
    const int shots = 20;
    for (int k = 0; k < shots; ++k) {
      // starting phases spread over one frame of travel so that some frames straddle the wall
      const float start = -3.0f - k * (factor * top / 50.0f) / shots;
      const float with_ccd = fire_at_thin_wall(factor * top, start, true);
      const float without = fire_at_thin_wall(factor * top, start, false);
      // never past the wall's near face
      EXPECT_LT(with_ccd, -kWallHalf) << factor << "x top speed from z = " << start;
      passed_with_ccd += with_ccd > 0;
      passed_without += without > 0;
    }
    std::printf(
        "%.0fx top speed (%.0f m/s) at a 0.1 m wall: %d of %d shots passed with CCD, %d "
        "without\n",
        factor, factor * top, passed_with_ccd, shots, passed_without);
    EXPECT_EQ(passed_with_ccd, 0) << factor << "x";
    // the negative control: without CCD the same shots go through (11, 16, 18 of 20 measured)
    EXPECT_GE(passed_without, shots / 4) << factor << "x";
  }
}

TEST(DroneBodyTest, NoGravityButOtherBodiesFall) {
  WorldParams wp;
  wp.gravity = btVector3(0, -9.81f, 0);
  BulletWorld world(wp);
  DroneBody drone(world, btVector3(0, 3, 0), 0.0f, kSeeker);
  DynamicBodyDesc box;
  box.position = btVector3(5, 3, 0);
  btRigidBody* obstacle =
      world.add_dynamic_body(std::make_unique<btBoxShape>(btVector3(0.5f, 0.5f, 0.5f)), box);
  for (int f = 0; f < 100; ++f) {
    drone.apply_action(0, 0, 0, 0);
    world.step_frame();
  }
  EXPECT_EQ(drone.position().y(), 3.0f);
  EXPECT_EQ(drone.velocity().length(), 0.0f);
  EXPECT_LT(obstacle->getWorldTransform().getOrigin().y(), 3.0f - 4.0f);  // about 4.9 m in 1 s
}

TEST(DroneBodyTest, StaysUprightAfterCollisions) {
  BulletWorld world;
  world.add_static_box(btVector3(0, -0.5f, 0), btVector3(10, 0.5f, 10), kWall);  // floor
  world.add_static_box(btVector3(0, 3, 4), btVector3(10, 3, 0.05f), kWall);      // thin wall
  DroneBody a(world, btVector3(0, 1, 0), 0.4f, kHider);
  DroneBody b(world, btVector3(0.3f, 1.2f, 2), 2.5f, kSeeker);
  a.body().setLinearVelocity(btVector3(2, -3, 50));  // off-centre, into the floor and the wall
  for (int f = 0; f < 300; ++f) {
    a.apply_action(1, 0.7f, -1, 0.5f);
    b.apply_action(-1, -0.5f, -0.8f, -1);
    world.step_frame();
    for (const DroneBody* d : {&a, &b}) {
      const btVector3 up = d->body().getWorldTransform().getBasis() * btVector3(0, 1, 0);
      ASSERT_NEAR(up.y(), 1.0f, 1e-5f) << "frame " << f;
      ASSERT_EQ(d->body().getAngularVelocity().x(), 0.0f);
      ASSERT_EQ(d->body().getAngularVelocity().z(), 0.0f);
      ASSERT_LT(d->position().z(), 4.0f);
    }
  }
}

TEST(DroneBodyTest, SpeedIsCappedUnderFullThrust) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 5, 0), 0.0f, kHider);
  float fastest = 0;
  for (int f = 0; f < 200; ++f) {
    drone.apply_action(1, 1, 1, 0);
    world.step_frame();
    fastest = std::max(fastest, static_cast<float>(drone.velocity().length()));
  }
  EXPECT_LE(fastest, drone.params().max_speed + 1e-4f);
  // the frame's damping takes off a factor 0.5^0.02 = 0.986 after the capped integration
  EXPECT_GT(fastest, 0.98f * drone.params().max_speed);
  // a pushed drone is brought back to the cap on its next action
  drone.body().setLinearVelocity(btVector3(30, 0, 0));
  drone.apply_action(0, 0, 0, 0);
  world.step_frame();
  EXPECT_LE(drone.velocity().length(), drone.params().max_speed + 1e-4f);
}

TEST(DroneBodyTest, ActionsActInTheDroneFrame) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 5, 0), 0.0f, kHider);
  for (int f = 0; f < 10; ++f) {
    drone.apply_action(1, 0, 0, 0);
    world.step_frame();
  }
  EXPECT_GT(drone.velocity().z(), 1.0f);  // forward is +z at yaw 0
  EXPECT_NEAR(drone.velocity().x(), 0.0f, 1e-6f);

  BulletWorld world2;
  DroneBody turned(world2, btVector3(0, 5, 0), 3.14159265f / 2, kHider);  // facing +x
  for (int f = 0; f < 10; ++f) {
    turned.apply_action(0, 1, 1, 0);
    world2.step_frame();
  }
  EXPECT_GT(turned.velocity().z(), 0.5f);  // right = forward x up = +z
  EXPECT_GT(turned.velocity().y(), 0.5f);
  EXPECT_NEAR(turned.velocity().x(), 0.0f, 1e-5f);

  const float yaw0 = drone.yaw();
  for (int f = 0; f < 10; ++f) {
    drone.apply_action(0, 0, 0, 1);
    world.step_frame();
  }
  EXPECT_GT(drone.yaw() - yaw0, 0.4f);  // about 3 rad/s for 0.2 s, less the damping
  EXPECT_LT(drone.yaw() - yaw0, 0.61f);
}

}  // namespace
}  // namespace rlt::drone
