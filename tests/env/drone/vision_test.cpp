// Vision: a hider in the cone and in range is seen; behind a wall, behind the seeker, outside the
// cone or beyond range it is not; the same through the arena's open and closed doorways; the
// assault-horizon signal on hand-built cases.
#include "env/drone/vision.h"

#include <gtest/gtest.h>

#include <cmath>

#include "env/drone/arena.h"
#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"

namespace rlt::drone {
namespace {

constexpr float kPi = 3.14159265f;

// whether a seeker at the origin (1 m up) facing +z sees a hider at `hider`, with an optional wall
bool seen(const btVector3& hider, bool wall = false, float range = kDefaultVisionRange) {
  BulletWorld world;
  if (wall) world.add_static_box(btVector3(0, 1, 2.5f), btVector3(3, 3, 0.1f), kWall);
  DroneBody seeker(world, btVector3(0, 1, 0), 0.0f, kSeeker);
  DroneBody target(world, hider, 0.0f, kHider);
  return sees(world, seeker.body(), target.body(), kDefaultConeDegrees, range);
}

// a hider at distance d and horizontal angle `degrees` from the seeker's forward (+z)
btVector3 at_angle(float d, float degrees) {
  const float a = degrees * kPi / 180.0f;
  return btVector3(d * std::sin(a), 1, d * std::cos(a));
}

TEST(VisionTest, InConeAndRangeIsSeen) {
  EXPECT_TRUE(seen(btVector3(0, 1, 5)));
  EXPECT_TRUE(seen(at_angle(10, 60)));
  EXPECT_TRUE(seen(at_angle(10, -60)));
  EXPECT_TRUE(seen(at_angle(19.5f, 0)));
}

TEST(VisionTest, BehindAWallIsNotSeen) {
  EXPECT_FALSE(seen(btVector3(0, 1, 5), true));
  // the wall is 6 m wide: a hider beside it is seen again
  EXPECT_TRUE(seen(btVector3(8, 1, 5), true));
}

TEST(VisionTest, OutsideTheConeIsNotSeen) {
  EXPECT_FALSE(seen(btVector3(0, 1, -5)));  // behind
  EXPECT_FALSE(seen(at_angle(10, 75)));     // half-angle is 67.5
  EXPECT_FALSE(seen(at_angle(10, -75)));
  EXPECT_FALSE(seen(at_angle(10, 90)));
}

TEST(VisionTest, BeyondRangeIsNotSeen) {
  EXPECT_FALSE(seen(btVector3(0, 1, 20.5f)));
  EXPECT_FALSE(seen(btVector3(0, 1, 10), false, 8.0f));
  EXPECT_TRUE(seen(btVector3(0, 1, 10), false, 12.0f));
}

TEST(VisionTest, ConeFollowsTheSeekersYaw) {
  BulletWorld world;
  DroneBody seeker(world, btVector3(0, 1, 0), kPi / 2, kSeeker);  // faces +x
  DroneBody ahead(world, btVector3(5, 1, 0), 0.0f, kHider);
  DroneBody old_ahead(world, btVector3(0, 1, 7), 0.0f, kHider);
  EXPECT_TRUE(sees(world, seeker.body(), ahead.body()));
  EXPECT_FALSE(sees(world, seeker.body(), old_ahead.body()));
  EXPECT_NEAR(body_forward(seeker.body()).x(), 1.0f, 1e-5);
}

TEST(VisionTest, ThroughTheArenasDoorways) {
  // level 1: the -z doorway is open, the +z one closed
  BulletWorld world;
  ArenaParams params;
  params.level = 1;
  Arena arena(world, params);
  const float y = arena.openings()[0].centre.y();
  DroneBody hider(world, btVector3(0, y, 0), 0.0f, kHider);
  DroneBody south(world, btVector3(0, y, -9), 0.0f, kSeeker);    // faces +z, the open doorway
  DroneBody north(world, btVector3(0, y, 9), kPi, kSeeker);      // faces -z, the closed one
  DroneBody east(world, btVector3(9, y, 0), -kPi / 2, kSeeker);  // faces -x, a full wall
  EXPECT_TRUE(sees(world, south.body(), hider.body()));
  EXPECT_FALSE(sees(world, north.body(), hider.body()));
  EXPECT_FALSE(sees(world, east.body(), hider.body()));
}

TEST(VisionTest, AssaultHorizon) {
  const btVector3 f(0, 0, 1), o(0, 0, 0);
  EXPECT_FLOAT_EQ(assault_horizon(f, o, btVector3(0, 0, 2)), 0.5f);         // ahead at 2 m: 1/2
  EXPECT_FLOAT_EQ(assault_horizon(f, o, btVector3(0, 0, 4)), 0.25f);        // farther: smaller
  EXPECT_FLOAT_EQ(assault_horizon(f, o, btVector3(2, 0, 0)), 0.0f);         // beside: 0
  EXPECT_FLOAT_EQ(assault_horizon(f, o, btVector3(0, 0, -4)), -0.25f);      // behind: negative
  EXPECT_FLOAT_EQ(assault_horizon(f, o, btVector3(3, 0, 4)), 0.8f / 5.0f);  // cos 0.8 over 5 m
  // an unnormalised forward and an offset seeker give the same value
  EXPECT_FLOAT_EQ(assault_horizon(btVector3(0, 0, 3), btVector3(1, 2, 3), btVector3(4, 2, 7)),
                  0.8f / 5.0f);
  EXPECT_FLOAT_EQ(assault_horizon(f, o, o), 0.0f);
}

}  // namespace
}  // namespace rlt::drone
