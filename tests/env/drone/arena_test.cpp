// Arena: openings per level, rays and drones through open and closed openings, boundary walls.
#include "env/drone/arena.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"

namespace rlt::drone {
namespace {

ArenaParams at_level(int level) {
  ArenaParams params;
  params.level = level;
  return params;
}

// the first hit of a ray from `from` to `to`; returns its fraction (1 when nothing is hit)
float ray_fraction(const BulletWorld& world, const btVector3& from, const btVector3& to) {
  btCollisionWorld::ClosestRayResultCallback ray(from, to);
  world.world().rayTest(from, to, ray);
  return ray.hasHit() ? ray.m_closestHitFraction : 1.0f;
}

// flies a drone with full forward thrust from `start` towards the room centre at the opening's
// height for `frames` frames; returns the final position and sets `entered` if the drone's centre
// was ever inside the room
btVector3 fly_at(BulletWorld& world, const Arena& arena, const btVector3& start,
                 const btVector3& target, bool* entered, int frames = 400) {
  *entered = false;
  const btVector3 d = target - start;
  const float yaw = std::atan2(d.x(), d.z());
  DroneBody drone(world, start, yaw, kHider);
  for (int f = 0; f < frames; ++f) {
    drone.apply_action(1.0f, 0.0f, 0.0f, 0.0f);
    world.step_frame();
    *entered = *entered || arena.inside_room(drone.position());
  }
  return drone.position();
}

TEST(ArenaTest, OpenOpeningsPerLevel) {
  const int expected[] = {1, 2, 3, 4};
  for (int level = 1; level <= 4; ++level) {
    BulletWorld world;
    Arena arena(world, at_level(level));
    ASSERT_EQ(arena.openings().size(), 4u);
    EXPECT_EQ(arena.num_open(), expected[level - 1]) << "level " << level;
    EXPECT_EQ(open_openings_at_level(level), expected[level - 1]);
    int doorways = 0;
    for (const Opening& o : arena.openings()) doorways += o.kind == Opening::kDoorway && o.open;
    EXPECT_EQ(doorways, level == 1 ? 1 : 2) << "level " << level;
    // floor, ceiling, 4 boundary walls; per side 2 segments, doorway 1 lintel, window sill +
    // lintel, plus one chunk per closed opening
    EXPECT_EQ(arena.num_boxes(), 6 + 4 * 2 + 2 * 1 + 2 * 2 + (4 - expected[level - 1]));
    EXPECT_EQ(world.num_bodies(), arena.num_boxes());
  }
}

TEST(ArenaTest, BadLevelThrows) {
  BulletWorld world;
  EXPECT_THROW(Arena(world, at_level(0)), std::invalid_argument);
  EXPECT_THROW(Arena(world, at_level(5)), std::invalid_argument);
}

TEST(ArenaTest, OpeningGeometry) {
  BulletWorld world;
  Arena arena(world, at_level(4));
  const ArenaParams& p = arena.params();
  for (const Opening& o : arena.openings()) {
    EXPECT_FLOAT_EQ(o.normal.length(), 1.0f);
    EXPECT_FLOAT_EQ(o.normal.y(), 0.0f);
    // the centre lies on the room wall's centre plane, on the normal's axis
    EXPECT_NEAR(o.centre.dot(o.normal), p.room_half, 1e-5);
    if (o.kind == Opening::kDoorway) {
      EXPECT_NEAR(o.centre.y() - 0.5f * o.height, 0.0f, 1e-5) << "a doorway starts at the floor";
    } else {
      EXPECT_NEAR(o.centre.y() - 0.5f * o.height, p.window_sill, 1e-5);
    }
    // inside just behind the opening, outside just in front of it
    EXPECT_TRUE(arena.inside_room(o.centre - o.normal * 0.5f));
    EXPECT_FALSE(arena.inside_room(o.centre + o.normal * 0.5f));
    EXPECT_TRUE(arena.inside_arena(o.centre + o.normal * 0.5f));
  }
  EXPECT_TRUE(arena.inside_room(btVector3(0, 3, 0)));
  EXPECT_FALSE(arena.inside_room(btVector3(0, 7, 0)));
  EXPECT_FALSE(arena.inside_arena(btVector3(13, 3, 0)));
}

TEST(ArenaTest, RaysPassOpenOpeningsAndHitClosedOnes) {
  for (int level = 1; level <= 4; ++level) {
    BulletWorld world;
    Arena arena(world, at_level(level));
    for (const Opening& o : arena.openings()) {
      // from 4 m outside the opening to the room centre at the opening's height
      const btVector3 from = o.centre + o.normal * 4.0f;
      const btVector3 to(0, o.centre.y(), 0);
      const float fraction = ray_fraction(world, from, to);
      const btVector3 hit = from.lerp(to, fraction);
      if (o.open) {
        EXPECT_EQ(fraction, 1.0f) << "level " << level << " open opening blocked";
        EXPECT_TRUE(arena.inside_room(to));
      } else {
        // stopped at the outer face of the closing chunk
        const float outer = arena.params().room_half + 0.5f * arena.params().wall_thickness;
        EXPECT_NEAR(hit.dot(o.normal), outer, 1e-3) << "level " << level;
      }
    }
  }
}

// doorways_swapped: the doorways trade walls and nothing else changes; at level 1 the open doorway
// is then the one in the +z wall, and a ray passes it while the -z wall stops one
TEST(ArenaTest, SwappedDoorwaysTradeWalls) {
  for (int level = 1; level <= 4; ++level) {
    ArenaParams params = at_level(level);
    params.doorways_swapped = true;
    BulletWorld plain_world, swapped_world;
    const Arena plain(plain_world, at_level(level)), swapped(swapped_world, params);
    EXPECT_EQ(swapped.num_boxes(), plain.num_boxes()) << "level " << level;
    for (int i = 0; i < kNumOpenings; ++i) {
      const Opening& a = plain.openings()[i];
      const Opening& b = swapped.openings()[i];
      EXPECT_EQ(b.kind, a.kind);
      EXPECT_EQ(b.open, a.open);
      const float flip = i < 2 ? -1.0f : 1.0f;  // the doorways' z changes sign, the windows stay
      EXPECT_EQ(b.centre, btVector3(a.centre.x(), a.centre.y(), flip * a.centre.z())) << i;
      EXPECT_EQ(b.normal, btVector3(a.normal.x(), a.normal.y(), flip * a.normal.z())) << i;
    }
  }
  ArenaParams params = at_level(1);
  params.doorways_swapped = true;
  BulletWorld world;
  const Arena arena(world, params);
  const float r = arena.params().room_half, y = 0.5f * arena.params().door_height;
  EXPECT_GT(arena.openings()[0].centre.z(), 0.0f);
  EXPECT_EQ(ray_fraction(world, btVector3(0, y, r + 4), btVector3(0, y, 0)), 1.0f);
  EXPECT_LT(ray_fraction(world, btVector3(0, y, -r - 4), btVector3(0, y, 0)), 1.0f);
}

TEST(ArenaTest, DronesPassOpenOpeningsAndAreStoppedByClosedOnes) {
  for (int level : {1, 3}) {
    for (int i = 0; i < kNumOpenings; ++i) {
      BulletWorld world;
      Arena arena(world, at_level(level));
      const Opening& o = arena.openings()[i];
      const btVector3 start = o.centre + o.normal * 5.0f;
      bool entered = false;
      const btVector3 end =
          fly_at(world, arena, start, btVector3(0, o.centre.y(), 0), &entered, 150);
      if (o.open) {
        EXPECT_TRUE(entered) << "level " << level << " opening " << i << " ended at " << end.x()
                             << " " << end.y() << " " << end.z();
      } else {
        EXPECT_FALSE(entered) << "level " << level << " opening " << i;
        EXPECT_GT(end.dot(o.normal), arena.params().room_half) << "level " << level;
      }
    }
  }
}

TEST(ArenaTest, BoundaryWallsStopDrones) {
  const btVector3 directions[] = {btVector3(1, 0, 0), btVector3(-1, 0, 0), btVector3(0, 0, 1),
                                  btVector3(0, 0, -1)};
  for (const btVector3& d : directions) {
    BulletWorld world;
    Arena arena(world, at_level(1));
    // start halfway between the room and the boundary, fly outwards
    const btVector3 start = d * 8.0f + btVector3(0, 3, 0);
    bool entered = false;
    const btVector3 end = fly_at(world, arena, start, start + d * 10.0f, &entered);
    EXPECT_FALSE(entered);
    EXPECT_TRUE(arena.inside_arena(end));
    EXPECT_GT(end.dot(d), 11.0f) << "the drone reached the wall";
    EXPECT_LT(end.dot(d), arena.params().half_size) << "and stayed in front of it";
  }
}

TEST(ArenaTest, CoveredFractionOfAnOpeningByAPanel) {
  BulletWorld world;
  Arena arena(world, at_level(4));
  const Opening& door = arena.openings()[0];      // -z wall, 1.4 x 1.9 m
  const Opening& window = arena.openings()[2];    // +x wall, 1.4 x 1.4 m, sill at 2.2 m
  const btVector3 panel_half(0.75f, 1.0f, 0.1f);  // the default prop panel (1.5 x 2 m)
  const float outside = arena.params().room_half + 0.5f * arena.params().wall_thickness + 0.15f;
  // a panel flush against the doorway's outer face covers all of it
  btRigidBody* full = world.add_static_box(btVector3(0, 1.0f, -outside), panel_half, kProp);
  EXPECT_FLOAT_EQ(covered_fraction(door, *full), 1.0f);
  // the same panel slid 0.7 m sideways covers about half
  btRigidBody* half = world.add_static_box(btVector3(0.7f, 1.0f, -outside), panel_half, kProp);
  EXPECT_NEAR(covered_fraction(door, *half), 0.5f, 0.1f);
  // one far away (or too far from the wall plane) covers none
  btRigidBody* far = world.add_static_box(btVector3(0, 1.0f, -9), panel_half, kProp);
  EXPECT_FLOAT_EQ(covered_fraction(door, *far), 0.0f);
  // a panel turned to face +x, carried up to the window, covers it
  btRigidBody* up = world.add_static_box(btVector3(outside, window.centre.y(), 0),
                                         btVector3(0.1f, 1.0f, 0.75f), kProp);
  EXPECT_FLOAT_EQ(covered_fraction(window, *up), 1.0f);
  // the door panel does not cover the window
  EXPECT_FLOAT_EQ(covered_fraction(window, *full), 0.0f);
}

// cover_shares' graded share (fade_depth > depth): a panel whose face lies between depth and
// fade_depth inside the wall plane counts part way, less the deeper it is; within depth in full
TEST(ArenaTest, GradedCoverFadesWithDepthBehindTheOpening) {
  BulletWorld world;
  Arena arena(world, at_level(2));
  const Opening& door = arena.openings()[0];  // -z wall: inside the room is +z
  const btVector3 panel_half(0.75f, 1.0f, 0.1f);
  // panels parallel to the wall, their faces toward the doorway 0.3, 1.0, 1.25 and 2 m inside
  const auto panel_at = [&](float face) {
    return world.add_static_box(btVector3(0, 1.0f, door.centre.z() + face + 0.1f), panel_half,
                                kProp);
  };
  btRigidBody* near = panel_at(0.3f);
  btRigidBody* mid = panel_at(1.0f);
  btRigidBody* deeper = panel_at(1.25f);
  btRigidBody* beyond = panel_at(2.0f);
  EXPECT_FLOAT_EQ(cover_shares(door, *near, 1.5f).graded, 1.0f);
  EXPECT_NEAR(cover_shares(door, *mid, 1.5f).graded, 0.5f, 1e-3f);  // (1.5 - 1) / 1
  EXPECT_NEAR(cover_shares(door, *deeper, 1.5f).graded, 0.25f, 1e-3f);
  EXPECT_FLOAT_EQ(cover_shares(door, *beyond, 1.5f).graded, 0.0f);
  // the same rays give the closing test's share: only faces within 0.5 m count, in full
  EXPECT_FLOAT_EQ(cover_shares(door, *near, 1.5f).covered, 1.0f);
  EXPECT_FLOAT_EQ(cover_shares(door, *mid, 1.5f).covered, 0.0f);
  EXPECT_FLOAT_EQ(covered_fraction(door, *near), 1.0f);
  EXPECT_FLOAT_EQ(covered_fraction(door, *mid), 0.0f);
  // without a fade depth past 0.5 m the graded share is the closing test's
  EXPECT_FLOAT_EQ(cover_shares(door, *mid, 0.5f).graded, 0.0f);
  EXPECT_FLOAT_EQ(cover_shares(door, *near, 0.0f).graded, 1.0f);
}

TEST(ArenaTest, NoFlyingOverTheRoom) {
  BulletWorld world;
  Arena arena(world, at_level(4));
  // a ray just under the ceiling across the room hits its wall
  const float y = arena.params().height - 0.05f;
  EXPECT_LT(ray_fraction(world, btVector3(-8, y, 0.5f), btVector3(8, y, 0.5f)), 1.0f);
}

TEST(ArenaTest, WithoutARoomOnlyFloorCeilingAndBoundary) {
  BulletWorld world;
  ArenaParams params;
  params.room = false;
  params.level = 0;  // ignored without a room
  params.half_size = 5.0f;
  Arena arena(world, params);
  EXPECT_EQ(arena.num_boxes(), 6);
  EXPECT_EQ(world.num_bodies(), 6);
  EXPECT_TRUE(arena.openings().empty());
  EXPECT_FALSE(arena.inside_room(btVector3(0, 1, 0)));
  EXPECT_TRUE(arena.inside_arena(btVector3(4.9f, 1, -4.9f)));
  EXPECT_FALSE(arena.inside_arena(btVector3(5.1f, 1, 0)));
}

}  // namespace
}  // namespace rlt::drone
