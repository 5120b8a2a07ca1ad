// GridSensor: hand-built scenes with known answers (a hider at a known direction and distance, out
// of range, nearest wins within each channel, own body, behind the drone, yaw), equivalence with a
// naive reference using std::atan2 / std::asin on random scenes, fast_atan2 against std::atan2, and
// the cost of both presets on a hide-and-seek scene (printed, not asserted).
#include "env/drone/grid_sensor.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "env/drone/arena.h"
#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"
#include "env/drone/fast_atan2.h"
#include "env/drone/prop.h"
#include "env/drone/surface_points.h"

namespace rlt::drone {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kDeg = kPi / 180.0f;

// the world position at (lat, lon) degrees and `distance` from a drone at `origin` with `yaw`
btVector3 at(const btVector3& origin, float yaw, float lat, float lon, float distance) {
  const btVector3 forward(std::sin(yaw), 0, std::cos(yaw));
  const btVector3 right(-std::cos(yaw), 0, std::sin(yaw));
  const btVector3 up(0, 1, 0);
  const float h = std::cos(lat * kDeg);
  return origin + distance * (h * std::cos(lon * kDeg) * forward +
                              h * std::sin(lon * kDeg) * right + std::sin(lat * kDeg) * up);
}

std::vector<float> observe(const GridSensor& sensor, BulletWorld& world, const DroneBody& self) {
  SurfacePoints points;
  points.update(world);
  std::vector<float> out(sensor.size(), -7.0f);
  sensor.observe(points, points.body_index(self.body()), self.body().getWorldTransform(),
                 out.data());
  return out;
}

// cells with any non-zero channel
int occupied(const std::vector<float>& out) {
  int n = 0;
  for (size_t c = 0; c < out.size() / kNumTags; ++c) {
    bool any = false;
    for (int t = 0; t < kNumTags; ++t) any |= out[c * kNumTags + t] != 0.0f;
    n += any;
  }
  return n;
}

TEST(GridSensorTest, PresetShapes) {
  const GridSensor spatial(GridSensorParams::spatial());
  EXPECT_EQ(spatial.lat_cells(), 6);
  EXPECT_EQ(spatial.lon_cells(), 12);
  EXPECT_EQ(spatial.size(), 6 * 12 * kNumTags);
  const GridSensor frontal(GridSensorParams::frontal());
  EXPECT_EQ(frontal.lat_cells(), 9);
  EXPECT_EQ(frontal.lon_cells(), 8);
  EXPECT_FLOAT_EQ(frontal.lon_arc_degrees(), 21.0f);
  EXPECT_EQ(frontal.size(), 9 * 8 * kNumTags);
  // row 0 is up, column 0 is left (lon = -180), longitude positive to the right
  EXPECT_EQ(spatial.cell_of(89.0f, -179.0f), 0);
  EXPECT_EQ(spatial.cell_of(15.0f, 45.0f), 2 * 12 + 7);
  EXPECT_EQ(frontal.cell_of(0.0f, 100.0f), -1);
  EXPECT_THROW(GridSensor(GridSensorParams{90, 90, 180, 0.0f}), std::invalid_argument);
}

TEST(GridSensorTest, HiderAtAKnownDirectionFillsItsCell) {
  BulletWorld world;
  const btVector3 origin(0, 2, 0);
  DroneBody seeker(world, origin, 0.0f, kSeeker);
  // 15 degrees up and 45 degrees to the right (-x at yaw 0), 6 m away: a cell centre
  DroneBody hider(world, at(origin, 0.0f, 15.0f, 45.0f, 6.0f), 0.0f, kHider);
  EXPECT_LT(hider.position().x(), 0.0f);
  const GridSensor sensor(GridSensorParams::spatial());
  const std::vector<float> out = observe(sensor, world, seeker);
  const int cell = sensor.cell_of(15.0f, 45.0f);
  ASSERT_EQ(cell, 2 * 12 + 7);
  // nearest surface point about 6 - 0.35 m away (the samples sit within ~3 cm of the closest point)
  EXPECT_NEAR(out[cell * kNumTags + kHider], 1.0f - 5.65f / 20.0f, 0.005f);
  EXPECT_EQ(occupied(out), 1);
  for (float v : out) EXPECT_TRUE(v >= 0.0f && v <= 1.0f);

  // normalization bends the same proximity; min_distance shifts it
  GridSensorParams curved = GridSensorParams::spatial();
  curved.normalization = 0.5f;
  curved.min_distance = 1.0f;
  const std::vector<float> bent = observe(GridSensor(curved), world, seeker);
  const float distance = (1.0f - out[cell * kNumTags + kHider]) * 20.0f;
  const float linear = 1.0f - (distance - 1.0f) / 19.0f;
  EXPECT_NEAR(bent[cell * kNumTags + kHider], std::sqrt(linear), 1e-4f);
}

TEST(GridSensorTest, BeyondMaxDistanceIsNotSeen) {
  BulletWorld world;
  const btVector3 origin(0, 2, 0);
  DroneBody seeker(world, origin, 0.0f, kSeeker);
  DroneBody far(world, at(origin, 0.0f, 15.0f, -45.0f, 20.5f), 0.0f, kHider);  // nearest 20.15 m
  const GridSensor sensor(GridSensorParams::spatial());
  EXPECT_EQ(occupied(observe(sensor, world, seeker)), 0);
  // control: the same hider at 19 m is seen, faintly
  far.body().getWorldTransform().setOrigin(at(origin, 0.0f, 15.0f, -45.0f, 19.0f));
  const std::vector<float> out = observe(sensor, world, seeker);
  EXPECT_EQ(occupied(out), 1);
  EXPECT_NEAR(out[sensor.cell_of(15.0f, -45.0f) * kNumTags + kHider], 1.0f - 18.65f / 20.0f,
              0.005f);
}

TEST(GridSensorTest, NearestWinsWithinEachChannel) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 1, 0), 0.0f, kSeeker);
  world.add_static_box(btVector3(0, 1, 10.5f), btVector3(5, 5, 0.5f), kWall);  // face at z = 10
  // one cell straight ahead, +-10 degrees
  GridSensorParams narrow;
  narrow.lat_north_degrees = narrow.lat_south_degrees = 10.0f;
  narrow.lon_degrees = 10.0f;
  narrow.cell_arc_degrees = 20.0f;
  const GridSensor sensor(narrow);
  ASSERT_EQ(sensor.num_cells(), 1);
  // the wall alone: nearest samples at (+-0.5, +-0.5) off the axis, 10.025 m away
  const std::vector<float> wall = observe(sensor, world, drone);
  EXPECT_NEAR(wall[kWall], 1.0f - 10.025f / 20.0f, 0.002f);
  for (int t = 1; t < kNumTags; ++t) EXPECT_EQ(wall[t], 0.0f);
  // a prop panel 3 m ahead (its near face at 2.9 m) and a hider behind the wall (12 m): each
  // channel holds its own nearest point, so the wall stays and the hider shows through it
  PropSet props(world);
  props.add(btVector3(0, 1, 3));
  DroneBody hider(world, btVector3(0, 1, 12.0f), 0.0f, kHider);
  const std::vector<float> out = observe(sensor, world, drone);
  EXPECT_GT(out[kProp], 1.0f - 3.0f / 20.0f);
  EXPECT_NEAR(out[kWall], wall[kWall], 1e-6f);
  EXPECT_NEAR(out[kHider], 1.0f - 11.65f / 20.0f, 0.002f);
  EXPECT_EQ(out[kObstacle] + out[kSeeker], 0.0f);
  // within one channel the nearer point wins: a second hider at 6 m replaces the first
  DroneBody near_hider(world, btVector3(0, 1, 6.0f), 0.0f, kHider);
  const std::vector<float> nearer = observe(sensor, world, drone);
  EXPECT_NEAR(nearer[kHider], 1.0f - 5.65f / 20.0f, 0.002f);
}

TEST(GridSensorTest, OwnBodyIsNeverSeen) {
  BulletWorld world;
  DroneBody drone(world, btVector3(0, 1, 0), 0.4f, kSeeker);
  const GridSensor spatial(GridSensorParams::spatial());
  EXPECT_EQ(occupied(observe(spatial, world, drone)), 0);
  // control: the same points observed without skipping the body fill the cells around it
  SurfacePoints points;
  points.update(world);
  std::vector<float> out(spatial.size());
  spatial.observe(points, -1, drone.body().getWorldTransform(), out.data());
  EXPECT_GT(occupied(out), 6);
  for (int c = 0; c < spatial.num_cells(); ++c) {
    const float v = out[c * kNumTags + kSeeker];
    if (v != 0.0f) {
      EXPECT_NEAR(v, 1.0f - 0.35f / 20.0f, 1e-5f);
    }
  }
}

TEST(GridSensorTest, BehindIsInTheSpatialGridOnly) {
  BulletWorld world;
  const btVector3 origin(0, 2, 0);
  DroneBody seeker(world, origin, 0.0f, kSeeker);
  DroneBody hider(world, at(origin, 0.0f, 5.0f, 170.0f, 5.0f), 0.0f, kHider);
  const GridSensor spatial(GridSensorParams::spatial());
  const GridSensor frontal(GridSensorParams::frontal());
  const std::vector<float> around = observe(spatial, world, seeker);
  EXPECT_GT(around[spatial.cell_of(5.0f, 170.0f) * kNumTags + kHider], 0.0f);
  EXPECT_EQ(occupied(observe(frontal, world, seeker)), 0);
  // control: in front it is in both
  hider.body().getWorldTransform().setOrigin(at(origin, 0.0f, 5.0f, -10.0f, 5.0f));
  EXPECT_GT(observe(frontal, world, seeker)[frontal.cell_of(5.0f, -10.0f) * kNumTags + kHider],
            0.0f);
  EXPECT_EQ(occupied(observe(frontal, world, seeker)), 1);
}

TEST(GridSensorTest, YawTurnsTheView) {
  const btVector3 origin(1, 2, -3);
  const float yaw = 3.0f;
  const GridSensor spatial(GridSensorParams::spatial());
  const GridSensor frontal(GridSensorParams::frontal());
  // the hider at the same place relative to the drone's heading gives the same grids
  BulletWorld world;
  DroneBody turned(world, origin, yaw, kSeeker);
  // (the hider turned too, so that the whole scene turns rigidly)
  DroneBody hider(world, at(origin, yaw, 20.0f, 40.0f, 4.0f), yaw, kHider);
  BulletWorld straight_world;
  DroneBody straight(straight_world, origin, 0.0f, kSeeker);
  DroneBody straight_hider(straight_world, at(origin, 0.0f, 20.0f, 40.0f, 4.0f), 0.0f, kHider);
  for (const GridSensor* sensor : {&spatial, &frontal}) {
    const std::vector<float> a = observe(*sensor, world, turned);
    const std::vector<float> b = observe(*sensor, straight_world, straight);
    EXPECT_GE(occupied(a), 1);  // the hider may straddle a cell edge
    for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-4f) << i;
  }
  // and the same world place seen from the same spot at yaw 0 is elsewhere: positive yaw turns to
  // the left, so the hider is at lon 40 - 171.9 = -131.9 degrees, outside the frontal grid
  SurfacePoints points;
  points.update(world);
  const btTransform unturned(btQuaternion::getIdentity(), origin);
  const int self = points.body_index(turned.body());
  std::vector<float> front(frontal.size()), around(spatial.size());
  frontal.observe(points, self, unturned, front.data());
  EXPECT_EQ(occupied(front), 0);
  spatial.observe(points, self, unturned, around.data());
  EXPECT_EQ(occupied(around), 1);
  EXPECT_GT(around[spatial.cell_of(20.0f, -131.9f) * kNumTags + kHider], 0.0f);
}

// naive reference: std::atan2 / std::asin per point, nearest of each tag per cell by a scan
std::vector<float> reference(const GridSensor& sensor, const SurfacePoints& points, int self_body,
                             const btTransform& pose) {
  const GridSensorParams& p = sensor.params();
  btVector3 forward = pose.getBasis().getColumn(2);
  forward.setY(0);
  forward.normalize();
  const btVector3 right = forward.cross(btVector3(0, 1, 0));
  std::vector<float> nearest(sensor.size(), 1e30f);  // [cells * kNumTags]
  for (int i = 0; i < points.size(); ++i) {
    if (self_body >= 0 && i >= points.body(self_body).begin && i < points.body(self_body).end) {
      continue;
    }
    const btVector3 v = btVector3(points.x()[i], points.y()[i], points.z()[i]) - pose.getOrigin();
    const float d = v.length();
    if (d > p.max_distance || d == 0.0f) continue;
    const float lon = std::atan2(v.dot(right), v.dot(forward)) / kDeg;
    const float lat = std::asin(std::clamp(v.y() / d, -1.0f, 1.0f)) / kDeg;
    const int c = sensor.cell_of(lat, lon);
    if (c < 0) continue;
    float& slot = nearest[c * kNumTags + points.tag()[i]];
    slot = std::min(slot, d);
  }
  std::vector<float> out(sensor.size(), 0.0f);
  for (int k = 0; k < sensor.size(); ++k) {
    if (nearest[k] > 1e29f) continue;
    const float linear = 1.0f - (std::max(nearest[k], p.min_distance) - p.min_distance) /
                                    (p.max_distance - p.min_distance);
    out[k] = std::pow(std::clamp(linear, 0.0f, 1.0f), p.normalization);
  }
  return out;
}

// Arena level 4, 4 props, 5 obstacles and 4 drones at random places
struct Scene {
  BulletWorld world;
  std::unique_ptr<Arena> arena;
  std::unique_ptr<PropSet> props;
  std::vector<DroneBody> drones;

  explicit Scene(std::mt19937& rng) {
    arena = std::make_unique<Arena>(world);
    props = std::make_unique<PropSet>(world);
    std::uniform_real_distribution<float> xz(-11.0f, 11.0f), y(0.5f, 5.0f), turn(-kPi, kPi);
    for (int i = 0; i < 4; ++i) props->add(btVector3(xz(rng), 1.0f, xz(rng)), turn(rng));
    for (int i = 0; i < 5; ++i) add_obstacle(world, btVector3(xz(rng), 0.4f, xz(rng)), turn(rng));
    for (int i = 0; i < 4; ++i) {
      drones.emplace_back(world, btVector3(xz(rng), y(rng), xz(rng)), turn(rng),
                          i < 2 ? kHider : kSeeker);
    }
  }

  SurfacePointsParams inner_points() const {
    const ArenaParams& a = arena->params();
    SurfacePointsParams params;
    const float eps = 0.01f;
    params.static_keep_min = btVector3(-a.half_size - eps, -eps, -a.half_size - eps);
    params.static_keep_max = btVector3(a.half_size + eps, a.height + eps, a.half_size + eps);
    return params;
  }
};

TEST(GridSensorTest, MatchesANaiveReferenceOnRandomScenes) {
  std::mt19937 rng(7);
  GridSensorParams curved = GridSensorParams::frontal();
  curved.normalization = 2.0f;
  curved.min_distance = 0.5f;
  curved.max_distance = 12.0f;
  const GridSensor sensors[] = {GridSensor(GridSensorParams::spatial()),
                                GridSensor(GridSensorParams::frontal()), GridSensor(curved)};
  int cells = 0, differing = 0;
  int multi_channel_cells = 0;  // cells where a wall and something else both show
  for (int scene_index = 0; scene_index < 10; ++scene_index) {
    Scene scene(rng);
    SurfacePoints points(scene.inner_points());
    points.update(scene.world);
    for (const DroneBody& drone : scene.drones) {
      const int self = points.body_index(drone.body());
      ASSERT_GE(self, 0);
      for (const GridSensor& sensor : sensors) {
        std::vector<float> out(sensor.size(), -7.0f);
        sensor.observe(points, self, drone.body().getWorldTransform(), out.data());
        const std::vector<float> expected =
            reference(sensor, points, self, drone.body().getWorldTransform());
        for (int c = 0; c < sensor.num_cells(); ++c) {
          bool same = true;
          for (int t = 0; t < kNumTags; ++t) {
            const float v = out[c * kNumTags + t];
            ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
            same &= std::fabs(v - expected[c * kNumTags + t]) < 1e-4f;
            multi_channel_cells += t > 0 && v != 0.0f && out[c * kNumTags] != 0.0f;
          }
          ++cells;
          differing += !same;
        }
      }
    }
  }
  // a point within ~1e-5 rad of a cell edge may fall on the other side with fast_atan2
  std::printf("%d of %d cells differ from the std::atan2 reference\n", differing, cells);
  EXPECT_LE(differing, cells / 500);
  // the scenes do put things in front of walls: channels are filled independently
  EXPECT_GT(multi_channel_cells, 0);
}

TEST(GridSensorTest, ObserveManyEqualsSeparateObservations) {
  std::mt19937 rng(3);
  Scene scene(rng);
  SurfacePoints points(scene.inner_points());
  points.update(scene.world);
  const GridSensor spatial(GridSensorParams::spatial());
  const GridSensor frontal(GridSensorParams::frontal());
  const DroneBody& drone = scene.drones[2];
  const int self = points.body_index(drone.body());
  std::vector<float> a(spatial.size()), b(frontal.size()), many_a(a.size()), many_b(b.size());
  spatial.observe(points, self, drone.body().getWorldTransform(), a.data());
  frontal.observe(points, self, drone.body().getWorldTransform(), b.data());
  const GridSensor* sensors[] = {&spatial, &frontal};
  float* outs[] = {many_a.data(), many_b.data()};
  GridSensor::observe_many(sensors, outs, 2, points, self, drone.body().getWorldTransform());
  EXPECT_EQ(a, many_a);
  EXPECT_EQ(b, many_b);
  EXPECT_GT(occupied(a), 10);  // walls all around
}

TEST(GridSensorTest, FastAtan2MatchesStdWithinItsBound) {
  float worst = 0.0f;
  for (int i = 0; i <= 200000; ++i) {
    const float angle = -kPi + 2.0f * kPi * i / 200000.0f;
    for (float r : {1e-3f, 1.0f, 37.0f}) {
      const float y = r * std::sin(angle), x = r * std::cos(angle);
      worst = std::max(worst, std::fabs(fast_atan2(y, x) - std::atan2(y, x)));
    }
  }
  std::printf("fast_atan2: max error %.2e rad\n", worst);
  EXPECT_LE(worst, kFastAtan2MaxError);
  EXPECT_EQ(fast_atan2(0.0f, 0.0f), 0.0f);
  // latitude as atan2(up, horizontal) against asin(up / distance)
  float worst_lat = 0.0f;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-10.0f, 10.0f);
  for (int i = 0; i < 100000; ++i) {
    const float x = u(rng), y = u(rng), z = u(rng);
    const float h = std::sqrt(x * x + z * z), d = std::sqrt(x * x + y * y + z * z);
    worst_lat = std::max(worst_lat, std::fabs(fast_atan2(y, h) - std::asin(y / d)));
  }
  std::printf("latitude: max error %.2e rad against std::asin\n", worst_lat);
  EXPECT_LE(worst_lat, kFastAtan2MaxError + 1e-6f);
}

TEST(GridSensorTest, CostOfBothPresetsInAHideAndSeekScene) {
  std::mt19937 rng(11);
  Scene scene(rng);
  SurfacePoints points(scene.inner_points());
  points.update(scene.world);
  const GridSensor spatial(GridSensorParams::spatial());
  const GridSensor frontal(GridSensorParams::frontal());
  const GridSensor* sensors[] = {&spatial, &frontal};
  std::vector<float> a(spatial.size()), b(frontal.size());
  float* outs[] = {a.data(), b.data()};
  std::vector<int> self;
  for (const DroneBody& d : scene.drones) self.push_back(points.body_index(d.body()));
  const int reps = 2000;
  double seen = 0.0;
  auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < reps; ++r) {
    for (size_t k = 0; k < scene.drones.size(); ++k) {
      GridSensor::observe_many(sensors, outs, 2, points, self[k],
                               scene.drones[k].body().getWorldTransform());
      seen += a[0] + b[0];
    }
  }
  const double observe_us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() /
      (reps * scene.drones.size());
  t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < reps; ++r) points.update(scene.world);
  const double update_us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() /
      reps;
  std::printf("grid sensors: %.2f us per observation of both presets (%d + %d cells) over %d "
              "points (%d static, %d dynamic); %.2f us per SurfacePoints::update\n",
              observe_us, spatial.num_cells(), frontal.num_cells(), points.size(),
              points.num_static_points(), points.num_dynamic_points(), update_us);
  EXPECT_GE(seen, 0.0);
}

}  // namespace
}  // namespace rlt::drone
