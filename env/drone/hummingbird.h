// Hummingbird: one drone collects nectar in a wide open arena (SPEC.md section 7, the first of the
// paper's pre-experiments; after Unity ML-Agents' "Hummingbird" tutorial world).
//
// World (metres, seconds, y up; DroneTask conventions, drone_task.h): an open arena of
// 2 arena_half_size x 2 arena_half_size x arena_height (default 24 x 24 x 6 m, no room) with
// `num_obstacles` pillars (static boxes tagged kObstacle, floor to ceiling, square section of side
// 2 obstacle_half_size, centres seeded uniformly at least 3 m from each other and 2 m inside the
// boundary walls). Nectar: `num_nectar` spheres of radius nectar_radius that bodies do not collide
// with and the rays do not see (they are not in the physics world). Their centres are seeded per
// episode: clear of walls, floor, ceiling and pillars by the radius, heights in [1, height - 1] m,
// at least 2 radii apart. The drone (DroneBody, tag kSeeker) spawns at a seeded free place outside
// every nectar sphere (at least radius + 1 m from its centre) with a seeded yaw.
// Behavior "Hummingbird": 1 slot, group 0, agent id 0; 4 continuous actions in [-1, 1] (forward,
// strafe, vertical, yaw rate) repeated for `decision_period` physics frames at 50 Hz.
// Rewards, summed over the frames of a decision:
//   +nectar_reward (0.01) per frame the drone's centre is inside a nectar sphere that has nectar
//     left (distance to its centre <= nectar_radius); with nectar_capacity > 0 each sphere holds
//     that many frames of nectar and is then empty (0 = unlimited, the default);
//   +collision_reward (-0.5) per collision: a contact of the drone with a wall, the floor, the
//     ceiling or a pillar that starts in this frame (ContactTracker: a pair that touches now and
//     did not touch the frame before; a drone pressed against a wall collides once).
// End: truncation after episode_length frames (kLast, terminated 0); there is no terminal state.
// Parameters (defaults): the DroneTask ones (episode_length 3000 frames = 1000 decisions,
// decision_period 3, arena_half_size 12, arena_height 6, drone_max_speed 5, drone_max_force 20,
// drone_max_yaw_rate 3), num_nectar 5 (1-16), nectar_radius 1 (m), nectar_reward 0.01,
// nectar_capacity 0 (frames, 0 = unlimited), collision_reward -0.5, num_obstacles 4 (0-8),
// obstacle_half_size 0.5 (m).
// Observations:
//   "vector" [16] in [-1, 1]: [0, 12) the DroneTask common block (position, velocity, forward,
//     yaw sin/cos, time); [12, 15) relative position of the centre of the nearest sphere with
//     nectar left (DroneTask::write_relative; zeros when all are empty); [15] 1 while the drone is
//     inside a sphere with nectar left, else 0.
//   "rays" [119] in [0, 1]: RaySensor (walls, floor and ceiling are kWall, pillars kObstacle).
// Metrics: "nectar_frames" (frames rewarded with nectar), "collisions", "nectar_fraction"
// (nectar_frames / frames played).
#ifndef RLT_ENV_DRONE_HUMMINGBIRD_H_
#define RLT_ENV_DRONE_HUMMINGBIRD_H_

#include <cstdint>
#include <random>
#include <vector>

#include "env/drone/drone_task.h"
#include "rl/env_api/env.h"

namespace rlt {

class Hummingbird : public Env {
 public:
  static constexpr int kObservationSize = 16;
  static constexpr int kMaxNectar = 16;
  static constexpr int kMaxObstacles = 8;

  struct Nectar {
    btVector3 centre;
    int left;  // frames of nectar left; < 0 = unlimited
  };

  Hummingbird();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override { engine_.seed(seed); }
  void reset(StepView& out) override;
  void step(StepView& io) override;
  EpisodeMetrics episode_metrics() const override;
  uint64_t physics_frames() const override { return task_.total_frames(); }

  // the current episode, for tests
  drone::DroneTask& task() { return task_; }
  drone::DroneBody& drone() { return task_.drone(0); }
  const std::vector<Nectar>& nectar() const { return nectar_; }
  // index of the sphere with nectar left that contains `p`, or -1
  int nectar_at(const btVector3& p) const;

 private:
  void write_observation(BehaviorView& view);

  EnvSpec spec_;
  std::mt19937_64 engine_;
  drone::DroneTask task_;

  // settings of the episode
  float nectar_radius_ = 1.f;
  float nectar_reward_ = 0.01f;
  float collision_reward_ = -0.5f;

  // state
  std::vector<Nectar> nectar_;
  int nectar_frames_ = 0;
  int collisions_ = 0;
};

}  // namespace rlt

#endif  // RLT_ENV_DRONE_HUMMINGBIRD_H_
