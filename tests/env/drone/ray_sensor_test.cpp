// RaySensor: hand-built scenes with known answers (a wall at a known distance, a drone to the
// right, an empty world), the ML-Agents ray order, and rays that ignore the casting drone, each for
// both implementations (analytic casts on a ShapeSnapshot, Bullet's convexSweepTest); and the
// equivalence of the two on random scenes of rotated boxes and spheres.
#include "env/drone/ray_sensor.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"
#include "env/drone/shape_snapshot.h"
#include "env/drone/sphere_cast.h"

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

enum class Path { kSnapshot, kBullet };

std::vector<float> observe(Path path, const RaySensor& sensor, BulletWorld& world,
                           const btCollisionObject& self) {
  std::vector<float> out(sensor.size(), -7.0f);
  if (path == Path::kSnapshot) {
    ShapeSnapshot scene;
    scene.capture(world.world());
    sensor.observe(scene, self, out.data());
  } else {
    // ray tests read broadphase aabbs, which a world updates on a step or on request
    world.world().updateAabbs();
    sensor.observe_with_bullet_sweeps(world.world(), self, out.data());
  }
  return out;
}

// each hand-built scene runs on both implementations
class RaySensorTest : public ::testing::TestWithParam<Path> {
 protected:
  std::vector<float> observe(const RaySensor& sensor, BulletWorld& world,
                             const btCollisionObject& self) {
    return rlt::drone::observe(GetParam(), sensor, world, self);
  }
};

INSTANTIATE_TEST_SUITE_P(BothPaths, RaySensorTest,
                         ::testing::Values(Path::kSnapshot, Path::kBullet), [](const auto& info) {
                           return info.param == Path::kSnapshot ? "Snapshot" : "Bullet";
                         });

TEST(RaySensorLayoutTest, LayoutFollowsMlAgents) {
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

TEST_P(RaySensorTest, WallAtKnownDistanceAndFreeDirectionsMiss) {
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

TEST_P(RaySensorTest, RaysTurnWithTheDrone) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 1, 0), kPi / 2, kHider);  // facing +x
  world.add_static_box(btVector3(3.5f, 1, 0), btVector3(0.5f, 2, 1), kWall);
  RaySensor sensor;
  const std::vector<float> out = observe(sensor, world, drone.body());
  EXPECT_EQ(Ray{out.data()}.tag(), kWall);
  EXPECT_NEAR(Ray{out.data()}.fraction(), (3.0f - 0.3f) / 20.0f, 1e-3f);
}

TEST_P(RaySensorTest, OtherDroneToTheRightGivesItsTag) {
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

TEST_P(RaySensorTest, RaysIgnoreTheCastingDrone) {
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

// one random scene: static axis-aligned boxes, rotated dynamic boxes and spheres with random tags
// within 8 m of a caster sphere at the origin (the bodies may overlap it or each other)
void add_random_scene(BulletWorld& world, std::mt19937& rng) {
  std::uniform_real_distribution<float> uni(-1, 1);
  std::uniform_int_distribution<int> tag(0, kNumTags - 1);
  auto position = [&] { return btVector3(8 * uni(rng), 1.5f * uni(rng), 8 * uni(rng)); };
  auto size = [&] { return 0.05f + 1.2f * std::fabs(uni(rng)); };
  const int statics = 1 + static_cast<int>(4 * std::fabs(uni(rng)));
  const int boxes = static_cast<int>(8 * std::fabs(uni(rng)));
  const int spheres = static_cast<int>(6 * std::fabs(uni(rng)));
  for (int i = 0; i < statics; ++i) {
    world.add_static_box(position(), btVector3(size(), size(), size()), static_cast<Tag>(tag(rng)));
  }
  for (int i = 0; i < boxes; ++i) {
    DynamicBodyDesc desc;
    desc.position = position();
    desc.rotation =
        btQuaternion(btVector3(uni(rng), uni(rng), uni(rng)).normalized(), 3.2f * uni(rng));
    desc.tag = static_cast<Tag>(tag(rng));
    world.add_dynamic_body(std::make_unique<btBoxShape>(btVector3(size(), size(), size())), desc);
  }
  for (int i = 0; i < spheres; ++i) {
    DynamicBodyDesc desc;
    desc.position = position();
    desc.tag = static_cast<Tag>(tag(rng));
    world.add_dynamic_body(std::make_unique<btSphereShape>(0.5f * size()), desc);
  }
}

// Equivalence with Bullet on 400 random scenes (6800 rays, thin, 0.3 m and 0.6 m spheres, ray
// lengths 5-20 m): same tag and miss flags, fractions within 1e-3. The snapshot's boxes keep
// Bullet's 0.04 m margin as rounded edges (GJK sees a box so): the median distance between the
// two answers is then ~3e-6 m; with sharp edges they would differ by up to 0.03 m at corners
// (0.04 (sqrt(3) - 1)). Bullet's conservative advancement stops within 1 mm of contact (90% of
// hits agree within 0.7 mm), which along a grazing cast is centimetres, and a cast passing within
// about 1 mm of a shape may be a hit for Bullet only. Tolerated disagreements, under 1% of rays:
//   grazes: a cast 2 mm wider finds Bullet's answer;
//   tangent contacts: the sphere starts in contact with a body and moves along the contact plane
//     (here: bodies above or below the horizontal rays); Bullet then reports a hit at 0 or nothing
//     by GJK/EPA round-off, the snapshot reports nothing (a hit needs motion into the body).
TEST(RaySensorAgreementTest, SnapshotMatchesBulletSweepsOnRandomScenes) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> uni(-1, 1);
  int rays = 0, hits = 0, in_contact = 0, grazes = 0, tangent_contacts = 0;
  float worst = 0;  // largest distance between agreeing hits (m)
  for (int scene_index = 0; scene_index < 400; ++scene_index) {
    BulletWorld world;
    add_random_scene(world, rng);
    DynamicBodyDesc caster_desc;
    caster_desc.rotation = btQuaternion(btVector3(0, 1, 0), 3.2f * uni(rng));
    caster_desc.tag = kSeeker;
    btRigidBody* caster =
        world.add_dynamic_body(std::make_unique<btSphereShape>(0.35f), caster_desc);
    RaySensorParams params;
    params.ray_length = 5 + 15 * std::fabs(uni(rng));
    params.sphere_radius = scene_index % 8 == 0 ? 0.0f : scene_index % 8 == 1 ? 0.6f : 0.3f;
    const RaySensor sensor(params);
    const std::vector<float> exact = observe(Path::kSnapshot, sensor, world, *caster);
    const std::vector<float> bullet = observe(Path::kBullet, sensor, world, *caster);
    ShapeSnapshot scene;
    scene.capture(world.world());
    for (int i = 0; i < sensor.num_rays(); ++i) {
      const Ray e{exact.data() + i * kTagged}, b{bullet.data() + i * kTagged};
      ++rays;
      hits += !e.miss();
      in_contact += !e.miss() && e.fraction() == 0.0f;
      const btVector3 from = caster->getWorldTransform().getOrigin();
      const btVector3 to =
          from + params.ray_length * sensor.direction(caster->getWorldTransform(), i);
      const bool agree = e.miss() == b.miss() && e.tag() == b.tag() &&
                         std::fabs(e.fraction() - b.fraction()) <= 1e-3f;
      if (agree) {
        worst = std::max(worst, std::fabs(e.fraction() - b.fraction()) * params.ray_length);
        continue;
      }
      // a graze: a cast 2 mm wider hits what Bullet hit, near where it did (grazing chords are
      // long: 2 mm at a 0.65 m sphere give 5 cm)
      const CastHit wider = first_hit(scene, from, to, params.sphere_radius + 2e-3f, caster);
      const bool graze = !b.miss() && wider.hit() && wider.tag == b.tag() &&
                         std::fabs(wider.fraction - b.fraction()) * params.ray_length <= 0.1f;
      // in contact at the start with the motion (nearly) tangent to the contact normal: Bullet's
      // choice follows GJK/EPA round-off; a cast tilted by 0.02 rad into the contact hits at 0
      // (among the bodies of Bullet's tag: several may touch, and ties at 0 go either way)
      ShapeSnapshot bullet_tag_only;
      const btCollisionObjectArray& objects = world.world().getCollisionObjectArray();
      for (int n = 0; n < objects.size(); ++n) {
        if (tag_of(*objects[n]) == b.tag()) bullet_tag_only.add(*objects[n]);
      }
      bool tangent_contact = false;
      const btVector3 dir = (to - from).normalized();
      const btVector3 tilts[4] = {btVector3(0, 1, 0), btVector3(0, -1, 0),
                                  dir.cross(btVector3(0, 1, 0)), -dir.cross(btVector3(0, 1, 0))};
      for (const btVector3& tilt : tilts) {
        const btVector3 tilted = from + params.ray_length * (dir + 0.02f * tilt).normalized();
        const CastHit h = first_hit(bullet_tag_only, from, tilted, params.sphere_radius, caster);
        if (!b.miss() && b.fraction() == 0.0f && h.hit() && h.fraction == 0.0f &&
            h.tag == b.tag()) {
          tangent_contact = true;
        }
      }
      grazes += graze;
      tangent_contacts += tangent_contact;
      EXPECT_TRUE(graze || tangent_contact)
          << "scene " << scene_index << " ray " << i << ": snapshot tag " << e.tag() << " fraction "
          << e.fraction() << ", Bullet tag " << b.tag() << " fraction " << b.fraction();
    }
  }
  std::printf(
      "agreement: %d rays, %d hits (%d in contact at the start); disagreements: %d grazes, "
      "%d tangent contacts; otherwise hits within %.3g m\n",
      rays, hits, in_contact, grazes, tangent_contacts, worst);
  EXPECT_GT(hits, rays / 4);
  EXPECT_GT(in_contact, 50);
  EXPECT_LE(grazes + tangent_contacts, rays / 100);
}

}  // namespace
}  // namespace rlt::drone
