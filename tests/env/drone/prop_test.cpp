// Props and obstacles: grab drags a prop and release leaves it, a square hold swings the panel
// face-on, grab needs reach and the front cone, a locked prop does not move when rammed, only the
// locking team unlocks, a locked prop cannot be grabbed, obstacles glide under weak gravity, and a
// reset with props stays bit-identical.
#include "env/drone/prop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"

namespace rlt::drone {
namespace {

constexpr int kHiders = 0;
constexpr int kSeekers = 1;
constexpr float kPi = 3.14159265f;

// flies the drone with a constant action for `frames`
void fly(BulletWorld& world, DroneBody& drone, int frames, float forward, float strafe = 0,
         float vertical = 0, float yaw_rate = 0) {
  for (int f = 0; f < frames; ++f) {
    drone.apply_action(forward, strafe, vertical, yaw_rate);
    world.step_frame();
  }
}

TEST(PropTest, GrabbedPropFollowsAndStaysAfterRelease) {
  BulletWorld world;
  PropSet props(world);
  // a drone at z = 0 facing +z, a panel 1.3 m ahead (gap 1.3 - 0.1 - 0.35 = 0.85 m)
  DroneBody drone(world, btVector3(0, 2, 0), 0.0f, kHider);
  const int p = props.add(btVector3(0, 2, 1.3f));
  EXPECT_NEAR(props.gap(drone, p), 0.85f, 1e-5f);
  ASSERT_EQ(props.grab(drone), p);
  EXPECT_EQ(props.held_by(drone), p);
  EXPECT_EQ(world.num_constraints(), 1);
  const float d0 = (props[p].position() - drone.position()).length();
  // turn around and fly away for 3 s, then strafe and climb
  float largest = 0;
  for (int f = 0; f < 250; ++f) {
    if (f < 50) {
      drone.apply_action(0, 0, 0, 1);
    } else if (f < 200) {
      drone.apply_action(1, 0, 0, 0);
    } else {
      drone.apply_action(0, 1, 1, 0);
    }
    world.step_frame();
    largest = std::max(
        largest,
        static_cast<float>(std::abs((props[p].position() - drone.position()).length() - d0)));
  }
  const btVector3 start(0, 2, 1.3f);
  const float travelled = (props[p].position() - start).length();
  std::printf("dragged prop: travelled %.2f m, centre distance %.3f m, largest change %.4f m\n",
              travelled, d0, largest);
  EXPECT_GT(travelled, 5.0f);
  EXPECT_LT(largest, 0.1f);  // the pivot keeps the distance

  ASSERT_EQ(props.release(drone), p);
  EXPECT_EQ(props.held_by(drone), -1);
  EXPECT_EQ(world.num_constraints(), 0);
  EXPECT_EQ(props.release(drone), -1);
  const btVector3 left_at = props[p].position();
  const btVector3 drone_at = drone.position();
  const float speed_at_release = props[p].body->getLinearVelocity().length();
  fly(world, drone, 150, 1);  // 3 s away from it
  const float drift = (props[p].position() - left_at).length();
  const float flown = (drone.position() - drone_at).length();
  const float speed_after = props[p].body->getLinearVelocity().length();
  std::printf(
      "released at %.2f m/s: the prop drifted %.2f m (%.2f m/s after 3 s) while the drone flew "
      "%.2f m\n",
      speed_at_release, drift, speed_after, flown);
  // no more pull: its velocity at release, damped by 0.5^3
  EXPECT_LT(speed_after, 0.2f * speed_at_release);
  EXPECT_LT(drift, 0.7f * flown);
  EXPECT_GT((drone.position() - props[p].position()).length(), d0 + 8.0f);
}

// yaw of the prop's panel normal (its local z) in the drone's frame, in (-pi, pi]
float yaw_in_drone(const DroneBody& drone, const Prop& prop) {
  const btTransform rel = drone.body().getWorldTransform().inverse() *
                          prop.body->getWorldTransform();
  const btVector3 normal = rel.getBasis().getColumn(2);
  return std::atan2(normal.x(), normal.z());
}

TEST(PropTest, SquareHoldSwingsThePanelFaceOn) {
  // a panel turned 50 degrees to a drone facing +z, 1.2 m ahead; held for 1 s without moving
  for (const bool square : {false, true}) {
    BulletWorld world;
    PropParams params;
    params.square_hold = square;
    PropSet props(world, params);
    DroneBody drone(world, btVector3(0, 2, 0), 0.0f, kHider);
    const float turned = 50.0f * kPi / 180.0f;
    const int p = props.add(btVector3(0, 2, 1.2f), turned);
    ASSERT_EQ(props.grab(drone), p);
    EXPECT_NEAR(yaw_in_drone(drone, props[p]), turned, 1e-3f);
    fly(world, drone, 50, 0);
    const float held = yaw_in_drone(drone, props[p]);
    // then carried: turn the drone a quarter turn, the panel turns with it
    fly(world, drone, 60, 0, 0, 0, 1);
    const float after_turn = yaw_in_drone(drone, props[p]);
    const float distance = (props[p].position() - drone.position()).length();
    std::printf("square_hold %d: panel at %.1f deg to the drone after 1 s, %.1f after a turn, "
                "%.2f m away\n",
                square, held * 180 / kPi, after_turn * 180 / kPi, distance);
    if (square) {
      EXPECT_NEAR(held, 0.0f, 2.0f * kPi / 180.0f);
      EXPECT_NEAR(after_turn, 0.0f, 3.0f * kPi / 180.0f);
    } else {
      EXPECT_NEAR(held, turned, 2.0f * kPi / 180.0f);
      EXPECT_NEAR(after_turn, turned, 3.0f * kPi / 180.0f);
    }
    EXPECT_GT(distance, drone.params().radius + props[p].half.z());
  }
  // a panel edge-on to the drone (90 degrees) swings to face it and keeps clear of it
  BulletWorld world;
  PropParams params;
  params.square_hold = true;
  PropSet props(world, params);
  DroneBody drone(world, btVector3(0, 2, 0), 0.0f, kHider);
  const int p = props.add(btVector3(0, 2, 1.2f), 0.5f * kPi);
  ASSERT_EQ(props.grab(drone), p);
  fly(world, drone, 50, 0);
  const float yaw = yaw_in_drone(drone, props[p]);
  EXPECT_LT(std::min(std::abs(yaw), std::abs(std::abs(yaw) - kPi)), 2.0f * kPi / 180.0f);
  const btVector3 local = drone.body().getWorldTransform().invXform(props[p].position());
  EXPECT_GT(local.z(), drone.params().radius + props[p].half.z());
}

TEST(PropTest, GrabNeedsReachAndFront) {
  BulletWorld world;
  PropSet props(world);
  DroneBody drone(world, btVector3(0, 2, 0), 0.0f, kHider);
  // out of reach: gap 2.0 - 0.1 - 0.35 = 1.55 m > 1.5 m
  const int far = props.add(btVector3(0, 2, 2.0f));
  EXPECT_GT(props.gap(drone, far), props.params().reach);
  EXPECT_EQ(props.grab(drone), -1);
  // behind the drone, within reach
  const int behind = props.add(btVector3(0, 2, -1.0f));
  EXPECT_LT(props.gap(drone, behind), props.params().reach);
  EXPECT_FALSE(props.in_front(drone, behind));
  EXPECT_EQ(props.grab(drone), -1);
  // beside it (90 degrees): outside the 60 degree cone
  const int side = props.add(btVector3(1.2f, 2, 0), kPi / 2);
  EXPECT_FALSE(props.in_front(drone, side));
  EXPECT_EQ(props.grab(drone), -1);
  EXPECT_EQ(world.num_constraints(), 0);
  // turning to face the one behind makes it grabbable
  DroneBody turned(world, btVector3(3, 2, 0), 0.0f, kHider);
  EXPECT_EQ(props.grab(turned), -1);
  const int near = props.add(btVector3(3, 2, 1.0f));
  EXPECT_EQ(props.grab(turned), near);
  // a second drone cannot take a held prop
  DroneBody other(world, btVector3(3, 2, 2.0f), kPi, kHider);
  EXPECT_EQ(props.grab(other), -1);
}

// an `allowed` mask passes over the props it leaves out, nearest or not
TEST(PropTest, AllowedMaskPassesOverOtherProps) {
  BulletWorld world;
  PropSet props(world);
  DroneBody drone(world, btVector3(0, 2, 0), 0.0f, kHider);
  const int near = props.add(btVector3(0, 2, 1.0f));
  const int further = props.add(btVector3(0.4f, 2, 1.6f));
  EXPECT_EQ(props.grabbable(drone), near);
  EXPECT_EQ(props.grabbable(drone, 1u << further), further);
  EXPECT_EQ(props.grabbable(drone, 0u), -1);
  EXPECT_EQ(props.grab(drone, 0u), -1);
  EXPECT_EQ(props.lock(drone, kHiders, 1u << further), further);
  EXPECT_EQ(props.unlockable(drone, kHiders, 1u << near), -1);
  EXPECT_EQ(props.unlock(drone, kHiders, 1u << near), -1);
  EXPECT_TRUE(props[further].locked());
  EXPECT_EQ(props.grab(drone, 1u << near), near);
  EXPECT_EQ(props.unlock(drone, kHiders), further);
}

// a mask names the first 32 props: one that narrows them leaves the rest out, kAllProps not
TEST(PropTest, PropsPastTheMasksBitsNeedAllProps) {
  BulletWorld world;
  PropSet props(world);
  DroneBody drone(world, btVector3(0, 2, 0), 0.0f, kHider);
  for (int i = 0; i < 32; ++i) props.add(btVector3(20.0f + 3.0f * i, 2, 20.0f));  // out of reach
  const int last = props.add(btVector3(0, 2, 1.0f));
  ASSERT_EQ(last, 32);
  EXPECT_EQ(props.grabbable(drone), last);
  EXPECT_EQ(props.grabbable(drone, ~1u), -1);
}

// rams the prop at top speed for 2 s from 3 m; returns how far the prop's centre moved
float ram(BulletWorld& world, DroneBody& drone, const PropSet& props, int p) {
  const btVector3 before = props[p].position();
  fly(world, drone, 100, 1);
  return (props[p].position() - before).length();
}

TEST(PropTest, LockedPropDoesNotMoveAndOnlyItsTeamUnlocks) {
  BulletWorld world;
  PropSet props(world);
  const int p = props.add(btVector3(0, 2, 1.3f));
  DroneBody hider(world, btVector3(0, 2, 0), 0.0f, kHider);
  ASSERT_EQ(props.grab(hider), p);
  ASSERT_EQ(props.lock(hider, kHiders), p);  // locking releases the grab
  EXPECT_TRUE(props[p].locked());
  EXPECT_EQ(props[p].locked_by, kHiders);
  EXPECT_EQ(props.held_by(hider), -1);
  EXPECT_EQ(world.num_constraints(), 0);
  EXPECT_EQ(props.lock(hider, kSeekers), -1);  // already locked
  fly(world, hider, 50, -1);                   // back off

  // a seeker rams it at top speed for 2 s from the other side
  DroneBody seeker(world, btVector3(0.2f, 2.3f, 4.3f), kPi, kSeeker);
  const btVector3 before = props[p].position();
  float fastest = 0;
  for (int f = 0; f < 100; ++f) {
    seeker.apply_action(1, 0, 0, 0);
    world.step_frame();
    fastest = std::max(fastest, static_cast<float>(seeker.velocity().length()));
    ASSERT_LT((props[p].position() - before).length(), 1e-6f) << "frame " << f;
  }
  std::printf("locked prop rammed at up to %.2f m/s for 2 s: moved %.3g m\n", fastest,
              (props[p].position() - before).length());
  EXPECT_GT(fastest, 0.95f * seeker.params().max_speed);
  EXPECT_EQ(props[p].body->getLinearVelocity().length(), 0.0f);
  // a locked prop cannot be grabbed, and the failed grab releases nothing
  EXPECT_EQ(props.grab(seeker), -1);

  // the seeker (other team) cannot unlock, the hiders can
  EXPECT_EQ(props.unlock(seeker, kSeekers), -1);
  EXPECT_TRUE(props[p].locked());
  fly(world, seeker, 50, -1);
  EXPECT_GT(props.gap(seeker, p), 0.0f);
  DroneBody hider2(world, btVector3(0, 2, 0), 0.0f, kHider);
  EXPECT_EQ(props.unlock(hider2, kSeekers), -1);
  EXPECT_EQ(props.unlock(hider2, kHiders), p);
  EXPECT_FALSE(props[p].locked());
  EXPECT_EQ(props.unlock(hider2, kHiders), -1);  // nothing locked any more
  fly(world, hider2, 50, -1);

  // now the same ram moves it (so the locked test can fail)
  DroneBody seeker2(world, btVector3(0.2f, 2.3f, 4.3f), kPi, kSeeker);
  const float moved = ram(world, seeker2, props, p);
  std::printf("unlocked prop rammed for 2 s: moved %.2f m\n", moved);
  EXPECT_GT(moved, 0.5f);
}

// fires a panel flat-on (along its thin axis) at `speed` at a 0.1 m wall at z = 0; returns the
// largest z its centre reached
float fire_prop_at_thin_wall(float speed, float start, bool ccd) {
  BulletWorld world;
  world.add_static_box(btVector3(0, 2, 0), btVector3(5, 5, 0.05f), kWall);
  PropParams params;
  params.ccd = ccd;
  PropSet props(world, params);
  const int p = props.add(btVector3(0, 2, start));
  props[p].body->setLinearVelocity(btVector3(0, 0, speed));
  float max_z = start;
  for (int f = 0; f < 100; ++f) {
    world.step_frame();
    max_z = std::max(max_z, static_cast<float>(props[p].position().z()));
  }
  return max_z;
}

TEST(PropTest, CcdStopsAPropFiredAtTenTimesTopSpeed) {
  const float speed = 10 * DroneParams{}.max_speed;
  const int shots = 20;
  int passed_with = 0, passed_without = 0;
  for (int k = 0; k < shots; ++k) {
    const float start = -3.0f - k * (speed / 50.0f) / shots;
    const float with_ccd = fire_prop_at_thin_wall(speed, start, true);
    EXPECT_LT(with_ccd, -0.05f) << "from z = " << start;
    passed_with += with_ccd > 0;
    passed_without += fire_prop_at_thin_wall(speed, start, false) > 0;
  }
  std::printf("prop at %.0f m/s at a 0.1 m wall: %d of %d passed with CCD, %d without\n", speed,
              passed_with, shots, passed_without);
  EXPECT_EQ(passed_with, 0);
  EXPECT_GE(passed_without, shots / 4);  // the negative control
}

TEST(PropTest, LockingAHeldPropReleasesItAndRemovingAPropDropsItsGrab) {
  BulletWorld world;
  PropSet props(world);
  const int a = props.add(btVector3(0, 2, 1.3f));
  const int b = props.add(btVector3(4, 2, 1.3f));
  DroneBody hider(world, btVector3(0, 2, 0), 0.0f, kHider);
  DroneBody other(world, btVector3(0, 2, 2.6f), kPi, kHider);
  ASSERT_EQ(props.grab(hider), a);
  ASSERT_EQ(props.lock(other, kHiders), a);  // a teammate locks the prop the hider holds
  EXPECT_EQ(props.held_by(hider), -1);
  EXPECT_EQ(world.num_constraints(), 0);
  const btQuaternion rotation = props[a].body->getWorldTransform().getRotation();
  fly(world, hider, 50, -1, 0, 0, 1);
  EXPECT_EQ(props[a].body->getWorldTransform().getRotation(), rotation);

  DroneBody third(world, btVector3(4, 2, 0), 0.0f, kHider);
  ASSERT_EQ(props.grab(third), b);
  EXPECT_EQ(world.num_constraints(), 1);
  const int bodies = world.num_bodies();
  world.remove_body(&third.body());  // the drone leaves: its constraint goes first
  EXPECT_EQ(world.num_constraints(), 0);
  EXPECT_EQ(world.num_bodies(), bodies - 1);
  EXPECT_EQ(props.release(third), b);  // clears the record only
  EXPECT_EQ(world.num_constraints(), 0);
  world.step_frame();
}

TEST(PropTest, LockedPropCannotBeGrabbedButAnotherCan) {
  BulletWorld world;
  PropSet props(world);
  DroneBody drone(world, btVector3(0, 2, 0), 0.0f, kHider);
  const int a = props.add(btVector3(0, 2, 1.0f));
  ASSERT_EQ(props.lock(drone, kHiders), a);
  EXPECT_EQ(props.grab(drone), -1);
  const int b = props.add(btVector3(1.6f, 2, 1.6f));  // farther, still in reach and in front
  ASSERT_LE(props.gap(drone, b), props.params().reach);
  ASSERT_TRUE(props.in_front(drone, b));
  EXPECT_EQ(props.grab(drone), b);
  EXPECT_TRUE(props[a].locked());
}

TEST(PropTest, ObstacleGlidesAndSettlesUnderWeakGravity) {
  BulletWorld world;
  world.add_static_box(btVector3(0, -0.5f, 0), btVector3(50, 0.5f, 50), kWall);
  btRigidBody* box = add_obstacle(world, btVector3(0, 0.6f, 0));  // 0.2 m above the floor
  EXPECT_EQ(tag_of(*box), kObstacle);
  EXPECT_NEAR(box->getGravity().y(), -0.981f, 1e-6f);
  // it falls slowly: 1/10 g
  for (int f = 0; f < 50; ++f) world.step_frame();
  const float y1 = box->getWorldTransform().getOrigin().y();
  std::printf("obstacle fell %.3f m in 1 s (free fall would be 4.9 m)\n", 0.6f - y1);
  EXPECT_LT(y1, 0.55f);
  for (int f = 0; f < 100; ++f) world.step_frame();
  EXPECT_NEAR(box->getWorldTransform().getOrigin().y(), 0.4f, 0.02f);  // resting on the floor

  // one push: it glides
  box->activate(true);
  box->setLinearVelocity(btVector3(2, 0, 0));
  const float x0 = box->getWorldTransform().getOrigin().x();
  for (int f = 0; f < 100; ++f) world.step_frame();
  const float x2 = box->getWorldTransform().getOrigin().x() - x0;
  const float v2 = box->getLinearVelocity().length();
  int frames = 100;
  while (box->getLinearVelocity().length() > 0.01f && frames < 3000) {
    world.step_frame();
    ++frames;
  }
  const float total = box->getWorldTransform().getOrigin().x() - x0;
  std::printf(
      "obstacle pushed at 2 m/s: %.2f m and %.2f m/s after 2 s, stops after %.1f s at %.2f m\n", x2,
      v2, frames / 50.0f, total);
  EXPECT_GT(x2, 3.0f);
  EXPECT_GT(v2, 1.0f);
  EXPECT_GT(frames, 250);   // still gliding after 5 s
  EXPECT_LT(frames, 3000);  // but it settles
  EXPECT_GT(total, 6.0f);
  EXPECT_NEAR(box->getWorldTransform().getOrigin().y(), 0.4f, 0.02f);
}

TEST(PropTest, DronePushesObstacleAway) {
  BulletWorld world;
  world.add_static_box(btVector3(0, -0.5f, 0), btVector3(50, 0.5f, 50), kWall);
  btRigidBody* box = add_obstacle(world, btVector3(0, 0.4f, 2));
  DroneBody drone(world, btVector3(0, 0.4f, 0), 0.0f, kSeeker);
  fly(world, drone, 25, 1);  // a short dash into it
  fly(world, drone, 100, 0);
  const float z = box->getWorldTransform().getOrigin().z();
  std::printf("obstacle after a 0.5 s dash and 2 s of drift: z = %.2f m, %.2f m/s\n", z,
              box->getLinearVelocity().length());
  EXPECT_GT(z, 3.0f);
}

// a scene with walls, two drones, two props and an obstacle; grabs, locks and releases on a
// schedule; returns the pose bits of every prop and drone per frame
std::vector<float> run_with_props(BulletWorld& world, int frames, std::vector<int>* events) {
  world.add_static_box(btVector3(0, -0.5f, 0), btVector3(6, 0.5f, 6), kWall);
  world.add_static_box(btVector3(5.5f, 2, 0), btVector3(0.5f, 2, 6), kWall);
  world.add_static_box(btVector3(0, 2, 5.5f), btVector3(6, 2, 0.5f), kWall);
  add_obstacle(world, btVector3(1, 0.5f, -1));
  PropSet props(world);
  props.add(btVector3(0, 1.2f, 1.2f));
  props.add(btVector3(2, 1.2f, -2), 0.7f);
  DroneBody hider(world, btVector3(0, 1.2f, 0), 0.0f, kHider);
  DroneBody seeker(world, btVector3(2, 1.2f, -3.2f), 0.0f, kSeeker);
  std::vector<float> trace;
  for (int f = 0; f < frames; ++f) {
    // the events, recorded so that the test can check they happened
    if (f == 5) events->push_back(props.grab(hider));
    if (f == 10) events->push_back(props.grab(seeker));
    if (f == 60) events->push_back(props.release(hider));
    if (f == 120) events->push_back(props.lock(seeker, kSeekers));
    const float t = 0.05f * f;
    hider.apply_action(std::sin(t), std::cos(0.7f * t), 0.3f * std::sin(1.3f * t), 0.5f);
    seeker.apply_action(0.2f + 0.1f * std::cos(t), 0, 0, f < 10 ? 0.0f : -0.3f);
    world.step_frame();
    for (int i = 0; i < props.size(); ++i) {
      const btTransform& pose = props[i].body->getWorldTransform();
      for (int k = 0; k < 3; ++k) trace.push_back(pose.getOrigin()[k]);
      const btQuaternion q = pose.getRotation();
      for (int k = 0; k < 4; ++k) trace.push_back(q[k]);
    }
    for (const DroneBody* d : {&hider, &seeker}) {
      for (int k = 0; k < 3; ++k) trace.push_back(d->position()[k]);
    }
  }
  return trace;
}

TEST(PropTest, ResetWithPropsIsBitIdentical) {
  BulletWorld world;
  std::vector<int> events, again;
  const std::vector<float> first = run_with_props(world, 200, &events);
  world.reset();
  const std::vector<float> second = run_with_props(world, 200, &again);
  world.reset();
  const std::vector<float> third = run_with_props(world, 200, &again);
  BulletWorld fresh;
  const std::vector<float> fourth = run_with_props(fresh, 200, &again);
  // grab, grab, release and lock all happened
  EXPECT_EQ(events, (std::vector<int>{0, 1, 0, 1}));
  ASSERT_EQ(first.size(), second.size());
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(first.data(), third.data(), first.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(first.data(), fourth.data(), first.size() * sizeof(float)), 0);
  // the scenario does something: the first prop moved
  EXPECT_GT(std::abs(first[first.size() - 20] - first[0]), 0.1f);
}

TEST(PropTest, RemovingAHeldPropOrResettingIsSafe) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 2, 0), 0.0f, kHider);
  {
    PropSet props(world);
    props.add(btVector3(0, 2, 1.0f));
    ASSERT_EQ(props.grab(drone), 0);
    EXPECT_EQ(world.num_constraints(), 1);
  }  // the set releases its grabs
  EXPECT_EQ(world.num_constraints(), 0);
  PropSet props(world);
  props.add(btVector3(0, 2, 1.0f));
  ASSERT_EQ(props.grab(drone), 0);
  world.reset();  // constraints go before bodies; the set's destructor then does nothing
  EXPECT_EQ(world.num_constraints(), 0);
  EXPECT_EQ(world.num_bodies(), 0);
}

}  // namespace
}  // namespace rlt::drone
