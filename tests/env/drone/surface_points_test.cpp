// SurfacePoints: boxes and spheres sampled on their surfaces at the resolution, dynamic points that
// follow their body, slabs and buried or outside static points dropped, rebuilds after a reset,
// and the point counts of a hide-and-seek scene.
#include "env/drone/surface_points.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "env/drone/arena.h"
#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"
#include "env/drone/prop.h"

namespace rlt::drone {
namespace {

btVector3 point(const SurfacePoints& points, int i) {
  return btVector3(points.x()[i], points.y()[i], points.z()[i]);
}

TEST(SurfacePointsTest, BoxFacesGetCellCentresAtTheResolution) {
  BulletWorld world;
  DynamicBodyDesc desc;
  desc.position = btVector3(1, 2, 3);
  desc.tag = kObstacle;
  btRigidBody* box =
      world.add_dynamic_body(std::make_unique<btBoxShape>(btVector3(1.0f, 0.5f, 0.25f)), desc);
  SurfacePointsParams params;
  params.dynamic_resolution = 0.5f;
  SurfacePoints points(params);
  points.update(world);
  // +-x faces 2 x 1, +-y faces 1 x 4, +-z faces 4 x 2 cells
  ASSERT_EQ(points.size(), 2 * 2 + 2 * 4 + 2 * 8);
  EXPECT_EQ(points.num_static_points(), 0);
  EXPECT_EQ(points.num_dynamic_points(), 28);
  ASSERT_EQ(points.num_bodies(), 1);
  EXPECT_EQ(points.body_index(*box), 0);
  const btVector3 half(1.0f, 0.5f, 0.25f);
  for (int i = 0; i < points.size(); ++i) {
    EXPECT_EQ(points.tag()[i], kObstacle);
    const btVector3 local = point(points, i) - desc.position;
    // on exactly one face, strictly inside the others
    int on_faces = 0;
    for (int a = 0; a < 3; ++a) {
      const float ratio = std::fabs(local[a]) / half[a];
      EXPECT_LE(ratio, 1.0f + 1e-5f);
      on_faces += ratio > 1.0f - 1e-5f;
    }
    EXPECT_EQ(on_faces, 1) << i;
  }
}

TEST(SurfacePointsTest, SphereIsSampledOnItsSurfaceAllAround) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 1, 0), 0.0f, kHider);
  SurfacePoints points;  // 0.3 m on dynamic bodies
  points.update(world);
  // ceil(4 pi 0.35^2 / 0.3^2) = 18
  ASSERT_EQ(points.size(), 18);
  for (int i = 0; i < points.size(); ++i) {
    EXPECT_NEAR((point(points, i) - drone.position()).length(), 0.35f, 1e-5f);
    EXPECT_EQ(points.tag()[i], kHider);
  }
  // every one of the six axis directions has a point within 50 degrees
  for (int a = 0; a < 6; ++a) {
    btVector3 axis(0, 0, 0);
    axis[a / 2] = a % 2 ? -1.0f : 1.0f;
    float best = -1.0f;
    for (int i = 0; i < points.size(); ++i) {
      best = std::max(best, (point(points, i) - drone.position()).normalized().dot(axis));
    }
    EXPECT_GT(best, std::cos(50.0f * 3.14159265f / 180.0f)) << a;
  }
}

TEST(SurfacePointsTest, DynamicPointsFollowTheirBodyAndStaticPointsStay) {
  BulletWorld world;
  world.add_static_box(btVector3(0, 2, 10), btVector3(2, 2, 0.1f), kWall);
  DroneBody drone(world, btVector3(0, 1, 0), 0.0f, kSeeker);
  SurfacePoints points;
  points.update(world);
  const int n = points.size();
  ASSERT_GT(points.num_static_points(), 0);
  std::vector<btVector3> before;
  for (int i = 0; i < n; ++i) before.push_back(point(points, i));

  // move and turn the drone by hand; update re-transforms the cached local points
  btTransform pose = drone.body().getWorldTransform();
  const btVector3 shift(3, 0.5f, -2);
  pose.setOrigin(pose.getOrigin() + shift);
  pose.setRotation(btQuaternion(btVector3(0, 1, 0), 1.0f));
  drone.body().setWorldTransform(pose);
  points.update(world);
  ASSERT_EQ(points.size(), n);
  for (int i = 0; i < points.num_static_points(); ++i) {
    EXPECT_EQ(point(points, i), before[i]);
  }
  const SurfaceBody& body = points.body(points.body_index(drone.body()));
  EXPECT_TRUE(body.dynamic);
  for (int i = body.begin; i < body.end; ++i) {
    const btVector3 expected = pose * (before[i] - btVector3(0, 1, 0));  // local, then posed
    EXPECT_NEAR((point(points, i) - expected).length(), 0.0f, 1e-5f);
  }
}

// a body without a sensor tag (added to Bullet's world directly, user index -1) is not sampled, so
// every point's tag indexes a grid channel
TEST(SurfacePointsTest, UntaggedBodiesAreNotSampled) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 1, 0), 0.0f, kHider);
  btSphereShape shape(0.5f);
  btRigidBody::btRigidBodyConstructionInfo info(1.0f, nullptr, &shape);
  btRigidBody untagged(info);
  untagged.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(3, 1, 0)));
  ASSERT_EQ(untagged.getUserIndex(), -1);
  world.world().addRigidBody(&untagged);
  SurfacePoints points;
  points.update(world);
  EXPECT_EQ(points.body_index(untagged), -1);
  EXPECT_GE(points.body_index(drone.body()), 0);
  for (int i = 0; i < points.size(); ++i) {
    EXPECT_GE(points.tag()[i], 0);
    EXPECT_LT(points.tag()[i], kNumTags);
  }
  world.world().removeRigidBody(&untagged);
}

TEST(SurfacePointsTest, SlabsAreNotDetectableUnlessAskedFor) {
  BulletWorld world;
  btRigidBody* floor = world.add_static_box(btVector3(0, -0.1f, 0), btVector3(12, 0.1f, 12));
  btRigidBody* wall = world.add_static_box(btVector3(0, 3, 5), btVector3(3, 3, 0.1f));
  SurfacePoints points;
  points.update(world);
  EXPECT_EQ(points.body_index(*floor), -1);
  EXPECT_GE(points.body_index(*wall), 0);
  // the wall's bottom face rests on the floor: buried, although the floor itself is not sampled
  for (int i = 0; i < points.size(); ++i) EXPECT_GT(points.y()[i], 0.01f);

  SurfacePointsParams params;
  params.detect_slabs = true;
  SurfacePoints with_slabs(params);
  with_slabs.update(world);
  EXPECT_GE(with_slabs.body_index(*floor), 0);
  EXPECT_GT(with_slabs.size(), points.size());
}

TEST(SurfacePointsTest, BuriedAndOutsideStaticPointsAreDropped) {
  BulletWorld world;
  // two 2 m cubes side by side: the faces at x = 0 touch each other
  world.add_static_box(btVector3(-1, 1, 0), btVector3(1, 1, 1));
  world.add_static_box(btVector3(1, 1, 0), btVector3(1, 1, 1));
  SurfacePointsParams params;
  params.static_resolution = 1.0f;
  SurfacePoints points(params);
  points.update(world);
  // 6 faces x 4 points x 2 cubes, minus 2 x 4 on the shared face
  EXPECT_EQ(points.size(), 2 * 6 * 4 - 8);
  for (int i = 0; i < points.size(); ++i) EXPECT_GT(std::fabs(points.x()[i]), 0.01f);

  // keep only x <= 1.5: the far face of the right cube (x = 2) goes
  params.static_keep_max = btVector3(1.5f, 100, 100);
  SurfacePoints kept(params);
  kept.update(world);
  EXPECT_EQ(kept.size(), 2 * 6 * 4 - 8 - 4);
}

TEST(SurfacePointsTest, ResetRebuildsTheCloud) {
  BulletWorld world;
  DroneBody first(world, btVector3(0, 1, 0), 0.0f, kSeeker);
  SurfacePoints points;
  points.update(world);
  EXPECT_EQ(points.num_bodies(), 1);
  world.reset();
  DroneBody a(world, btVector3(0, 1, 0), 0.0f, kHider);
  DroneBody b(world, btVector3(3, 1, 0), 0.0f, kSeeker);
  points.update(world);
  ASSERT_EQ(points.num_bodies(), 2);
  EXPECT_EQ(points.body(0).object, &a.body());
  EXPECT_EQ(points.body(1).object, &b.body());
  EXPECT_EQ(points.tag()[points.body(1).begin], kSeeker);
}

TEST(SurfacePointsTest, HideAndSeekSceneCounts) {
  BulletWorld world;
  Arena arena(world);  // level 4
  const ArenaParams& a = arena.params();
  PropSet props(world);
  for (int i = 0; i < 4; ++i) props.add(btVector3(-2.0f + 1.3f * i, 1.0f, 1.5f), 0.3f * i);
  for (int i = 0; i < 5; ++i) add_obstacle(world, btVector3(-9.0f + 4 * i, 0.4f, 8.0f));
  for (int i = 0; i < 4; ++i) {
    DroneBody(world, btVector3(-6.0f + 4 * i, 1.5f, -7), 0.5f * i, i < 2 ? kHider : kSeeker);
  }
  SurfacePoints all;
  all.update(world);
  SurfacePointsParams params;
  const float eps = 0.01f;
  params.static_keep_min = btVector3(-a.half_size - eps, -eps, -a.half_size - eps);
  params.static_keep_max = btVector3(a.half_size + eps, a.height + eps, a.half_size + eps);
  SurfacePoints inner(params);
  inner.update(world);
  std::printf("hide-and-seek scene: %d static points (%d without the keep box), %d dynamic\n",
              inner.num_static_points(), all.num_static_points(), inner.num_dynamic_points());
  EXPECT_EQ(inner.num_unsupported(), 0);
  EXPECT_LT(inner.num_static_points(), all.num_static_points());
  EXPECT_EQ(inner.num_dynamic_points(), all.num_dynamic_points());
  for (int i = 0; i < inner.num_static_points(); ++i) {
    EXPECT_TRUE(arena.inside_arena(point(inner, i)) ||
                std::fabs(std::fabs(inner.x()[i]) - a.half_size) < 2 * eps ||
                std::fabs(std::fabs(inner.z()[i]) - a.half_size) < 2 * eps)
        << i;
  }
}

}  // namespace
}  // namespace rlt::drone
