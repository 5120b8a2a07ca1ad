// BulletWorld: the fixed step, ownership through reset, and bit-identical trajectories after a
// reset.
#include "env/drone/bullet_world.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "env/drone/drone_body.h"

namespace rlt::drone {
namespace {

// a small scene: a closed box of walls, two drones and a loose obstacle under weak gravity
std::vector<DroneBody> build_scene(BulletWorld& world) {
  world.add_static_box(btVector3(0, -0.5f, 0), btVector3(6, 0.5f, 6), kWall);
  world.add_static_box(btVector3(0, 4.5f, 0), btVector3(6, 0.5f, 6), kWall);
  world.add_static_box(btVector3(5.5f, 2, 0), btVector3(0.5f, 2, 6), kWall);
  world.add_static_box(btVector3(-5.5f, 2, 0), btVector3(0.5f, 2, 6), kWall);
  world.add_static_box(btVector3(0, 2, 5.5f), btVector3(6, 2, 0.5f), kWall);
  world.add_static_box(btVector3(0, 2, -5.5f), btVector3(6, 2, 0.5f), kWall);
  DynamicBodyDesc box;
  box.position = btVector3(1, 0.5f, 1);
  box.mass = 0.5f;
  btRigidBody* obstacle =
      world.add_dynamic_body(std::make_unique<btBoxShape>(btVector3(0.4f, 0.4f, 0.4f)), box);
  obstacle->setGravity(btVector3(0, -1, 0));
  std::vector<DroneBody> drones;
  drones.emplace_back(world, btVector3(-2, 1, -2), 0.3f, kHider);
  drones.emplace_back(world, btVector3(2, 1, 2), -2.0f, kSeeker);
  return drones;
}

// runs the scene for `frames` with the given actions and returns every body's pose bits per frame
std::vector<float> run(BulletWorld& world, const std::vector<float>& actions, int frames) {
  std::vector<DroneBody> drones = build_scene(world);
  std::vector<float> trace;
  for (int f = 0; f < frames; ++f) {
    for (size_t d = 0; d < drones.size(); ++d) {
      const float* a = actions.data() + (f * drones.size() + d) * 4;
      drones[d].apply_action(a[0], a[1], a[2], a[3]);
    }
    world.step_frame();
    const auto& objects = world.world().getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) {
      const btTransform& t = objects[i]->getWorldTransform();
      for (int k = 0; k < 3; ++k) trace.push_back(t.getOrigin()[k]);
      const btQuaternion q = t.getRotation();
      for (int k = 0; k < 4; ++k) trace.push_back(q[k]);
    }
  }
  return trace;
}

std::vector<float> random_actions(unsigned seed, int frames) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> actions(frames * 2 * 4);
  for (float& a : actions) a = u(rng);
  return actions;
}

TEST(BulletWorldTest, FixedFiftyHertzStep) {
  BulletWorld world;
  EXPECT_FLOAT_EQ(world.dt(), 0.02f);
  DynamicBodyDesc desc;
  btRigidBody* body = world.add_dynamic_body(std::make_unique<btSphereShape>(0.2f), desc);
  body->setLinearVelocity(btVector3(1, 0, 0));
  for (int f = 0; f < 50; ++f) world.step_frame();
  EXPECT_EQ(world.frame(), 50);
  EXPECT_NEAR(body->getWorldTransform().getOrigin().x(), 1.0f, 1e-5f);  // 50 frames = 1 s
}

TEST(BulletWorldTest, ResetGivesBitIdenticalTrajectories) {
  const int frames = 500;
  const std::vector<float> actions = random_actions(7, frames);
  BulletWorld world;
  const std::vector<float> first = run(world, actions, frames);
  world.reset();
  EXPECT_EQ(world.num_bodies(), 0);
  EXPECT_EQ(world.world().getNumCollisionObjects(), 0);
  const std::vector<float> second = run(world, actions, frames);
  ASSERT_EQ(first.size(), second.size());
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0);
  // a fresh world agrees too
  BulletWorld fresh;
  EXPECT_EQ(run(fresh, actions, frames), first);
  // and other actions do give another trajectory (the comparison can fail)
  world.reset();
  EXPECT_NE(run(world, random_actions(8, frames), frames), first);
}

TEST(BulletWorldTest, RemoveBodyAndTags) {
  BulletWorld world;
  btRigidBody* wall = world.add_static_box(btVector3(0, 0, 0), btVector3(1, 1, 1), kWall);
  DynamicBodyDesc desc;
  desc.tag = kProp;
  btRigidBody* prop = world.add_dynamic_body(std::make_unique<btSphereShape>(0.2f), desc);
  EXPECT_EQ(tag_of(*wall), kWall);
  EXPECT_EQ(tag_of(*prop), kProp);
  EXPECT_TRUE(wall->isStaticObject());
  world.remove_body(wall);
  EXPECT_EQ(world.num_bodies(), 1);
  EXPECT_EQ(world.world().getNumCollisionObjects(), 1);
  EXPECT_THROW(world.remove_body(wall), std::invalid_argument);
}

}  // namespace
}  // namespace rlt::drone
