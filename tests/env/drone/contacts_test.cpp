// Contacts: touching pairs from the dispatcher's manifolds, a contact counted once at its start
// while it lasts, again after the bodies part and meet again, and nothing for distant bodies.
#include "env/drone/contacts.h"

#include <gtest/gtest.h>

#include "env/drone/drone_body.h"

namespace rlt::drone {
namespace {

TEST(ContactsTest, PairIsCanonical) {
  btCollisionObject x, y;
  const ContactPair p = make_contact_pair(&x, &y), q = make_contact_pair(&y, &x);
  EXPECT_TRUE(p == q);
  EXPECT_TRUE(p.involves(&x));
  EXPECT_EQ(p.other(&x), &y);
  EXPECT_EQ(p.other(&y), &x);
}

TEST(ContactsTest, PressingIntoAWallStartsOneContactThenPartingAndMeetingAgainAnother) {
  BulletWorld world;
  btRigidBody* wall = world.add_static_box(btVector3(0, 1, 2), btVector3(3, 3, 0.1f), kWall);
  DroneBody drone(world, btVector3(0, 1, 0), 0.0f, kSeeker);  // faces +z, the wall 1.55 m ahead
  ContactTracker tracker;
  int starts = 0, touching_frames = 0;
  auto run = [&](float forward, int frames) {
    for (int f = 0; f < frames; ++f) {
      drone.apply_action(forward, 0, 0, 0);
      world.step_frame();
      tracker.update(world);
      starts += tracker.started(&drone.body(), wall);
      touching_frames += tracker.touching(&drone.body(), wall);
    }
  };
  run(1.0f, 150);  // fly in and keep pushing
  EXPECT_EQ(starts, 1);
  EXPECT_GT(touching_frames, 100);
  run(-1.0f, 50);  // back off
  EXPECT_FALSE(tracker.touching(&drone.body(), wall));
  run(1.0f, 100);  // and again
  EXPECT_EQ(starts, 2);
  tracker.clear();
  EXPECT_TRUE(tracker.touching().empty());
}

TEST(ContactsTest, DistantBodiesDoNotTouch) {
  BulletWorld world;
  DroneBody a(world, btVector3(0, 1, 0), 0.0f, kSeeker);
  DroneBody b(world, btVector3(0, 1, 0.75f), 0.0f, kSeeker);  // 0.05 m gap
  for (int f = 0; f < 10; ++f) {
    world.step_frame();
    EXPECT_TRUE(touching_pairs(world).empty());
  }
}

}  // namespace
}  // namespace rlt::drone
