// Sphere casts: golden answers worked out by hand (a face at a known distance, an edge and a corner
// of a rotated box, a miss that the box grown by r on every axis would wrongly report, sphere
// against sphere, a thin ray, starts in contact), equivalence of the box cast with a naive
// reference (first root of the distance to the box, by bisection) on random casts, and first_hit
// over a snapshot (closest wins, the caster is ignored, unknown shapes throw).
#include "env/drone/sphere_cast.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>

#include "env/drone/bullet_world.h"
#include "env/drone/shape_snapshot.h"

namespace rlt::drone {
namespace {

const float kSqrt2 = std::sqrt(2.0f);
const float kSqrt3 = std::sqrt(3.0f);

OrientedBox cube_at(const btVector3& centre, const btQuaternion& rotation, float half = 1.0f) {
  return OrientedBox{centre, btMatrix3x3(rotation), btVector3(half, half, half), 0.0f};
}

// casts along +z over 20 m from (x, y, 0)
float cast_z(const OrientedBox& box, float x, float y, float radius) {
  return sweep_sphere_box(btVector3(x, y, 0), btVector3(x, y, 20), radius, box);
}

TEST(SphereCastTest, FaceAtKnownDistance) {
  const OrientedBox box = cube_at(btVector3(0, 0, 10), btQuaternion::getIdentity());
  // the face is at z = 9; a 0.5 m sphere touches it with its centre at z = 8.5
  EXPECT_NEAR(cast_z(box, 0, 0, 0.5f), 8.5f / 20, 1e-6f);
  // anywhere over the face (|x|, |y| <= 1) gives the same answer
  EXPECT_NEAR(cast_z(box, 0.9f, -0.95f, 0.5f), 8.5f / 20, 1e-6f);
  // a box turned 90 degrees about y is the same box
  const OrientedBox turned =
      cube_at(btVector3(0, 0, 10), btQuaternion(btVector3(0, 1, 0), 1.5707963f));
  EXPECT_NEAR(cast_z(turned, 0.3f, 0.2f, 0.5f), 8.5f / 20, 1e-5f);
  // too short a segment: no hit
  EXPECT_EQ(sweep_sphere_box(btVector3(0, 0, 0), btVector3(0, 0, 8), 0.5f, box), kNoHit);
}

TEST(SphereCastTest, EdgeOfARotatedBox) {
  // a unit cube turned 45 degrees about y shows a vertical edge to the ray at z = 10 - sqrt(2)
  const OrientedBox box =
      cube_at(btVector3(0, 0, 10), btQuaternion(btVector3(0, 1, 0), 0.785398163f));
  const float edge_z = 10 - kSqrt2;
  EXPECT_NEAR(cast_z(box, 0, 0, 0.5f), (edge_z - 0.5f) / 20, 1e-5f);
  // 0.3 m to the side the sphere meets the edge 0.4 m before it (3-4-5), still on the edge's
  // rounded part (the offset (0.3, -0.4) is 37 degrees from the edge's bisector, less than 45)
  EXPECT_NEAR(cast_z(box, 0.3f, 0.5f, 0.5f), (edge_z - 0.4f) / 20, 1e-5f);
}

TEST(SphereCastTest, CornerOfARotatedBox) {
  // a unit cube turned so that its corner (1, 1, 1) points at the caster: the corner is at
  // z = 10 - sqrt(3)
  const btQuaternion corner_to_caster =
      shortestArcQuat(btVector3(1, 1, 1).normalized(), btVector3(0, 0, -1));
  const OrientedBox box = cube_at(btVector3(0, 0, 10), corner_to_caster);
  const float corner_z = 10 - kSqrt3;
  EXPECT_NEAR(cast_z(box, 0, 0, 0.5f), (corner_z - 0.5f) / 20, 1e-5f);
  // 0.3 m to the side: the sphere meets the corner 0.4 m before it
  EXPECT_NEAR(cast_z(box, 0.3f, 0, 0.5f), (corner_z - 0.4f) / 20, 1e-5f);
  EXPECT_NEAR(cast_z(box, 0, -0.3f, 0.5f), (corner_z - 0.4f) / 20, 1e-5f);
}

TEST(SphereCastTest, MissPastAnEdgeThatAGrownBoxWouldHit) {
  const OrientedBox box = cube_at(btVector3(0, 0, 10), btQuaternion::getIdentity());
  // along z at (1.4, 1.4): inside the box grown by 0.5 on every axis (|x|, |y| <= 1.5) but
  // sqrt(0.32) = 0.566 m from the edge at (1, 1), more than the radius
  EXPECT_EQ(cast_z(box, 1.4f, 1.4f, 0.5f), kNoHit);
  // 0.3 m from the edge it hits, 0.4 m before the face (3-4-5 again)
  const float off = 1 + 0.3f / kSqrt2;
  EXPECT_NEAR(cast_z(box, off, off, 0.5f), (9 - 0.4f) / 20, 1e-5f);
  // past a corner: across the diagonal at 0.55 m from the corner (1, 1, 11), in the box grown by
  // 0.5 on every axis, but no nearer than 0.55 m to the box anywhere
  const btVector3 corner(1, 1, 11);
  const btVector3 across = btVector3(1, -1, 0).normalized();
  const btVector3 from = corner + 0.55f * btVector3(1, 1, 1).normalized() - 5 * across;
  EXPECT_EQ(sweep_sphere_box(from, from + 10 * across, 0.5f, box), kNoHit);
}

TEST(SphereCastTest, RoundedBoxShrinksItsCoreAndGrowsTheSphere) {
  // Bullet's margin: half extents 1 with rounding 0.04; faces stay at 1, the corner moves in
  OrientedBox box = cube_at(btVector3(0, 0, 10), btQuaternion::getIdentity());
  box.rounding = 0.04f;
  EXPECT_NEAR(cast_z(box, 0, 0, 0.5f), 8.5f / 20, 1e-6f);
  box.basis.setRotation(shortestArcQuat(btVector3(1, 1, 1).normalized(), btVector3(0, 0, -1)));
  const float corner_z = 10 - kSqrt3 * 0.96f - 0.04f;
  EXPECT_NEAR(cast_z(box, 0, 0, 0.5f), (corner_z - 0.5f) / 20, 1e-5f);
}

TEST(SphereCastTest, SphereAgainstSphere) {
  // radii 1 + 0.5; 0.9 m off the line the contact is sqrt(1.5^2 - 0.9^2) = 1.2 m before the centre
  EXPECT_NEAR(sweep_sphere_sphere(btVector3(0.9f, 0, 0), btVector3(0.9f, 0, 20), 0.5f,
                                  btVector3(0, 0, 10), 1.0f),
              8.8f / 20, 1e-6f);
  EXPECT_EQ(sweep_sphere_sphere(btVector3(1.6f, 0, 0), btVector3(1.6f, 0, 20), 0.5f,
                                btVector3(0, 0, 10), 1.0f),
            kNoHit);
  // behind the caster: no hit
  EXPECT_EQ(sweep_sphere_sphere(btVector3(0, 0, 12), btVector3(0, 0, 20), 0.5f, btVector3(0, 0, 10),
                                1.0f),
            kNoHit);
}

TEST(SphereCastTest, ThinRay) {
  const OrientedBox box = cube_at(btVector3(0, 0, 10), btQuaternion::getIdentity());
  EXPECT_NEAR(cast_z(box, 0.99f, -0.99f, 0.0f), 9.0f / 20, 1e-6f);
  EXPECT_EQ(cast_z(box, 1.01f, 0, 0.0f), kNoHit);
  const OrientedBox edge_on =
      cube_at(btVector3(0, 0, 10), btQuaternion(btVector3(0, 1, 0), 0.785398163f));
  EXPECT_NEAR(cast_z(edge_on, 0, 0, 0.0f), (10 - kSqrt2) / 20, 1e-5f);
  EXPECT_NEAR(sweep_sphere_sphere(btVector3(0.6f, 0, 0), btVector3(0.6f, 0, 20), 0.0f,
                                  btVector3(0, 0, 10), 1.0f),
              9.2f / 20, 1e-6f);
}

TEST(SphereCastTest, StartingInContactHitsAtZeroOnlyWhenMovingIn) {
  const OrientedBox box = cube_at(btVector3(0, 0, 10), btQuaternion::getIdentity());
  // centre 0.3 m in front of the face, sphere 0.5: overlapping
  EXPECT_EQ(sweep_sphere_box(btVector3(0, 0, 8.7f), btVector3(0, 0, 20), 0.5f, box), 0.0f);
  EXPECT_EQ(sweep_sphere_box(btVector3(0, 0, 8.7f), btVector3(0, 0, -20), 0.5f, box), kNoHit);
  // sliding along the face (no motion into it) sees nothing
  EXPECT_EQ(sweep_sphere_box(btVector3(0, 0, 8.7f), btVector3(5, 0, 8.7f), 0.5f, box), kNoHit);
  // centre inside the box, nearest face z = 11: leaving through it misses, going in hits
  EXPECT_EQ(sweep_sphere_box(btVector3(0, 0, 10.8f), btVector3(0, 0, 20), 0.5f, box), kNoHit);
  EXPECT_EQ(sweep_sphere_box(btVector3(0, 0, 10.8f), btVector3(0, 0, 0), 0.5f, box), 0.0f);
  // spheres: towards the centre hits at 0, away misses
  EXPECT_EQ(
      sweep_sphere_sphere(btVector3(0, 0, 9), btVector3(0, 0, 20), 0.5f, btVector3(0, 0, 10), 1.0f),
      0.0f);
  EXPECT_EQ(
      sweep_sphere_sphere(btVector3(0, 0, 9), btVector3(0, 0, 0), 0.5f, btVector3(0, 0, 10), 1.0f),
      kNoHit);
}

// naive reference: the first t in [0, 1] with dist(o + t d, box) <= r, by golden-section search
// for the minimum of the (convex) distance and bisection before it
float reference_aligned_box(const float o[3], const float d[3], const float h[3], float r) {
  auto gap = [&](double t) {
    double e2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double e = std::fabs(o[k] + t * d[k]) - h[k];
      if (e > 0) e2 += e * e;
    }
    return std::sqrt(e2) - r;
  };
  if (gap(0) <= 0) return -1;  // starts in contact: not compared here
  double lo = 0, hi = 1;
  for (int it = 0; it < 200; ++it) {
    const double a = lo + (hi - lo) * 0.381966, b = hi - (hi - lo) * 0.381966;
    if (gap(a) < gap(b))
      hi = b;
    else
      lo = a;
  }
  double t_min = 0.5 * (lo + hi);
  if (gap(t_min) > 0) return kNoHit;
  lo = 0, hi = t_min;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (gap(mid) <= 0)
      hi = mid;
    else
      lo = mid;
  }
  return static_cast<float>(hi);
}

TEST(SphereCastTest, AlignedBoxMatchesNaiveReference) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(-1, 1);
  int hits = 0, misses = 0, compared = 0;
  for (int n = 0; n < 20000; ++n) {
    const float h[3] = {0.2f + std::fabs(uni(rng)), 0.2f + std::fabs(uni(rng)),
                        0.2f + std::fabs(uni(rng))};
    const float r = n % 10 == 0 ? 0.0f : 0.6f * std::fabs(uni(rng));
    float o[3], target[3], d[3];
    for (int k = 0; k < 3; ++k) {
      o[k] = 3 * uni(rng);
      target[k] = 1.5f * uni(rng);  // aim near the box, so that edges and corners get hit
      d[k] = (target[k] - o[k]) * 2;
    }
    const float expected = reference_aligned_box(o, d, h, r);
    if (expected < 0) continue;
    const float got = sweep_sphere_aligned_box(o, d, h, r, 1.0f);
    ++compared;
    if (expected == kNoHit) {
      ++misses;
      // a graze within 1e-5 of touching may go either way
      if (got != kNoHit) {
        float p[3], e2 = 0;
        for (int k = 0; k < 3; ++k) {
          p[k] = o[k] + got * d[k];
          const float e = std::fabs(p[k]) - h[k];
          if (e > 0) e2 += e * e;
        }
        EXPECT_NEAR(std::sqrt(e2), r, 1e-4f) << "case " << n;
      }
    } else {
      ++hits;
      // a thin ray grazing an edge is measure zero; compare the rest
      ASSERT_NE(got, kNoHit) << "case " << n << " expected " << expected;
      EXPECT_NEAR(got, expected, 1e-4f) << "case " << n;
    }
  }
  EXPECT_GT(hits, 3000);
  EXPECT_GT(misses, 3000);
  EXPECT_GT(compared, 15000);
}

TEST(SphereCastTest, FirstHitTakesTheClosestAndIgnoresTheCaster) {
  BulletWorld world;
  btRigidBody* caster =
      world.add_dynamic_body(std::make_unique<btSphereShape>(0.35f), {btVector3(0, 1, 0)});
  caster->setUserIndex(kSeeker);
  world.add_static_box(btVector3(0, 1, 10), btVector3(2, 2, 0.5f), kWall);  // face at z = 9.5
  DynamicBodyDesc prop;
  prop.position = btVector3(0.2f, 1, 5);
  prop.rotation = btQuaternion(btVector3(0, 1, 0), 0.785398163f);
  prop.tag = kProp;
  world.add_dynamic_body(std::make_unique<btBoxShape>(btVector3(0.5f, 0.5f, 0.5f)), prop);
  DynamicBodyDesc hider;
  hider.position = btVector3(-3, 1, 0);
  hider.tag = kHider;
  world.add_dynamic_body(std::make_unique<btSphereShape>(0.35f), hider);
  ShapeSnapshot scene;
  scene.capture(world.world());
  ASSERT_EQ(scene.boxes().size(), 2);
  ASSERT_EQ(scene.spheres().size(), 2);
  EXPECT_FLOAT_EQ(scene.boxes().half_x[0], 2.0f);  // half extents with margin
  EXPECT_FLOAT_EQ(scene.boxes().rounding[0], 0.04f);

  const btVector3 from(0, 1, 0);
  // forward: the prop in front of the wall
  CastHit hit = first_hit(scene, from, from + btVector3(0, 0, 20), 0.3f, caster);
  EXPECT_EQ(hit.kind, CastHit::kBox);
  EXPECT_EQ(hit.tag, kProp);
  EXPECT_LT(hit.fraction, 5.0f / 20);
  // sideways: the hider, radii 0.35 + 0.3
  hit = first_hit(scene, from, from + btVector3(-20, 0, 0), 0.3f, caster);
  EXPECT_EQ(hit.kind, CastHit::kSphere);
  EXPECT_EQ(hit.tag, kHider);
  EXPECT_NEAR(hit.fraction, (3 - 0.65f) / 20, 1e-6f);
  // not ignoring the caster: it overlaps the start, and the cast moves out of it: still nothing
  hit = first_hit(scene, from, from + btVector3(20, 0, 0), 0.3f, nullptr);
  EXPECT_FALSE(hit.hit());
  EXPECT_EQ(hit.fraction, 1.0f);
  EXPECT_EQ(hit.tag, -1);
  // up: the wall is beside the path, nothing else
  hit = first_hit(scene, from, from + btVector3(0, 20, 0), 0.3f, caster);
  EXPECT_FALSE(hit.hit());
}

TEST(SphereCastTest, SnapshotRejectsUnknownShapesAndReusesItsArrays) {
  BulletWorld world;
  world.add_static_box(btVector3(0, 0, 0), btVector3(1, 1, 1));
  ShapeSnapshot scene;
  scene.capture(world.world());
  scene.capture(world.world());
  EXPECT_EQ(scene.size(), 1);
  world.add_dynamic_body(std::make_unique<btCapsuleShape>(0.3f, 1.0f), {});
  try {
    scene.capture(world.world());
    FAIL() << "a capsule should throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("CapsuleShape"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rlt::drone
