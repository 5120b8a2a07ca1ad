// Timing of the drone ray sensor (not a test: nothing is asserted). A hide-and-seek-like scene:
// the level-4 Arena, 4 drones (2 hiders, 2 seekers), 4 props and 5 obstacles; the drones fly with
// random actions, and on every frame each drone observes its 17 rays through
//   bullet:   RaySensor::observe_with_bullet_sweeps (one convexSweepTest per ray),
//   snapshot: one ShapeSnapshot::capture per frame, then RaySensor::observe(snapshot) per drone.
// Prints microseconds per 17-ray observation for both (the snapshot's capture shared by the 4
// drones of a frame is reported apart and included in the per-observation figure) and how many
// rays the two disagree on (casts passing within 1 mm of a shape are hits for Bullet only; see
// ray_sensor.h). Run: build/tests/ray_sensor_timing [frames]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "env/drone/arena.h"
#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"
#include "env/drone/prop.h"
#include "env/drone/ray_sensor.h"
#include "env/drone/shape_snapshot.h"

using namespace rlt::drone;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::atoi(argv[1]) : 500;
  const int reps = 5;  // timed repetitions per frame (the first warms the caches like the rest)
  BulletWorld world;
  Arena arena(world, ArenaParams{});
  std::vector<DroneBody> drones;
  drones.emplace_back(world, btVector3(-6, 1.5f, -7), 0.3f, kHider);
  drones.emplace_back(world, btVector3(1, 1.5f, 1), 2.0f, kHider);  // inside the room
  drones.emplace_back(world, btVector3(7, 1.5f, 6), -2.5f, kSeeker);
  drones.emplace_back(world, btVector3(-7, 2.5f, 7), 1.2f, kSeeker);
  PropSet props(world);
  props.add(btVector3(0, 1.01f, -6), 0.0f);
  props.add(btVector3(6, 1.01f, 0), 1.2f);
  props.add(btVector3(-2, 1.01f, 2), 0.4f);
  props.add(btVector3(-9, 1.01f, -2), 2.0f);
  const btVector3 obstacle_at[5] = {btVector3(-8, 0.41f, 4), btVector3(8, 0.41f, -8),
                                    btVector3(3, 0.41f, 8), btVector3(-3, 0.41f, -9),
                                    btVector3(9, 0.41f, 3)};
  for (int i = 0; i < 5; ++i) add_obstacle(world, obstacle_at[i], 0.5f * i);

  RaySensor sensor;
  ShapeSnapshot scene;
  std::vector<float> out_bullet(sensor.size()), out_snapshot(sensor.size());
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> action(-1, 1);
  double bullet_us = 0, capture_us = 0, snapshot_us = 0;
  long observations = 0, rays = 0, hits = 0, disagreements = 0;
  for (int frame = 0; frame < frames; ++frame) {
    for (DroneBody& d : drones) {
      d.apply_action(action(rng), action(rng), 0.3f * action(rng), action(rng));
    }
    world.step_frame();
    for (int r = 0; r < reps; ++r) {
      auto t0 = Clock::now();
      for (const DroneBody& d : drones) {
        sensor.observe_with_bullet_sweeps(world.world(), d.body(), out_bullet.data());
      }
      auto t1 = Clock::now();
      scene.capture(world.world());
      auto t2 = Clock::now();
      for (const DroneBody& d : drones) sensor.observe(scene, d.body(), out_snapshot.data());
      auto t3 = Clock::now();
      bullet_us += std::chrono::duration<double, std::micro>(t1 - t0).count();
      capture_us += std::chrono::duration<double, std::micro>(t2 - t1).count();
      snapshot_us += std::chrono::duration<double, std::micro>(t3 - t2).count();
      observations += drones.size();
    }
    // agreement on this frame, every drone
    for (const DroneBody& d : drones) {
      sensor.observe_with_bullet_sweeps(world.world(), d.body(), out_bullet.data());
      sensor.observe(scene, d.body(), out_snapshot.data());
      for (int i = 0; i < sensor.num_rays(); ++i) {
        const float* b = out_bullet.data() + i * RaySensor::kFloatsPerRay;
        const float* s = out_snapshot.data() + i * RaySensor::kFloatsPerRay;
        bool same = std::fabs(b[kNumTags + 1] - s[kNumTags + 1]) <= 1e-3f;
        for (int t = 0; t <= kNumTags; ++t) same = same && b[t] == s[t];
        ++rays;
        hits += s[kNumTags] == 0.0f;
        disagreements += !same;
      }
    }
  }
  std::printf(
      "scene: %d collision objects (%d boxes, %d spheres), %d frames x %d reps x %zu drones\n",
      scene.size(), scene.boxes().size(), scene.spheres().size(), frames, reps, drones.size());
  std::printf("bullet sweeps: %.2f us per observation of %d rays\n", bullet_us / observations,
              sensor.num_rays());
  std::printf(
      "snapshot:      %.2f us per observation (%.2f us casting + %.2f us capture per "
      "frame shared by %zu drones)\n",
      (snapshot_us + capture_us) / observations, snapshot_us / observations,
      capture_us * drones.size() / observations, drones.size());
  std::printf("rays: %ld, hits %ld, disagreements (tag, miss or fraction > 1e-3) %ld\n", rays, hits,
              disagreements);
  return 0;
}
