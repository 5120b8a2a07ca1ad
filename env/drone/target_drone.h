// TargetDrone: one drone chases a moving target drone (SPEC.md section 7, the second of the
// paper's pre-experiments).
//
// World (DroneTask conventions, drone_task.h): an open arena, default 20 x 20 x 6 m, no obstacles.
// The target is a scripted DroneBody (tag kHider, sphere of radius target_radius, speed capped at
// target_speed): it flies at full thrust towards a waypoint and draws the next waypoint when it is
// within 1 m of it, except that while the chaser's centre is closer than evade_distance it flies
// straight away from the chaser instead (so a still drone is avoided). Waypoints are seeded,
// uniform over the free arena (1 m clearance) at heights in [1, height - 1] m, drawn from the
// env's engine, so the motion is the same for the same seed and the same chaser actions (a push by
// the chaser changes it). The chaser (tag kSeeker) spawns at a seeded free place at least
// spawn_distance from the target, with a seeded yaw.
// Behavior "TargetDrone": 1 slot, group 0, agent id 0; 4 continuous actions in [-1, 1] (forward,
// strafe, vertical, yaw rate) repeated for `decision_period` physics frames at 50 Hz.
// Rewards, summed over the frames of a decision:
//   +target_reward (1) when the chaser touches the target (a contact point at <= 0.01 m, see
//     contacts.h): the episode ends at once (kLast, terminated 1);
//   +collision_reward (-1) per collision of the chaser with a wall, the floor or the ceiling,
//     counted when the contact starts (ContactTracker).
// End: the touch, or truncation after episode_length frames (kLast, terminated 0).
// Parameters (defaults): the DroneTask ones (episode_length 1500 frames = 500 decisions,
// decision_period 3, arena_half_size 10, arena_height 6, drone_max_speed 5, drone_max_force 20,
// drone_max_yaw_rate 3), target_speed 2.5 (m/s), target_radius 0.35 (m), target_reward 1,
// collision_reward -1, spawn_distance 5 (m), evade_distance 2 (m, 0 = no evasion).
// Observations:
//   "vector" [19] in [-1, 1]: [0, 12) the DroneTask common block; [12, 15) relative position of
//     the target (write_relative; the chaser always knows where it is); [15, 18) the target's
//     velocity / drone_max_speed (clipped); [18] 1 when the chaser sees the target (vision.h
//     sees(): 135-degree cone, 20 m, line of sight), else 0.
//   "rays" [119] in [0, 1]: RaySensor (the target is a kHider hit).
// Metrics: "success" (1 if the target was touched), "collisions", "frames" (frames played).
#ifndef RLT_ENV_DRONE_TARGET_DRONE_H_
#define RLT_ENV_DRONE_TARGET_DRONE_H_

#include <cstdint>
#include <random>

#include "env/drone/drone_task.h"
#include "rl/env_api/env.h"

namespace rlt {

class TargetDrone : public Env {
 public:
  static constexpr int kObservationSize = 19;
  static constexpr float kWaypointReach = 1.0f;  // m

  TargetDrone();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override { engine_.seed(seed); }
  void reset(StepView& out) override;
  void step(StepView& io) override;
  EpisodeMetrics episode_metrics() const override;
  uint64_t physics_frames() const override { return task_.total_frames(); }

  // the current episode, for tests
  drone::DroneTask& task() { return task_; }
  drone::DroneBody& chaser() { return task_.drone(0); }
  drone::DroneBody& target() { return task_.drone(1); }
  const btVector3& waypoint() const { return waypoint_; }
  // test hook: the target stays where it is (no scripted thrust) while frozen
  void freeze_target(bool frozen) { target_frozen_ = frozen; }

 private:
  void move_target();
  void write_observation(BehaviorView& view);

  EnvSpec spec_;
  std::mt19937_64 engine_;
  drone::DroneTask task_;

  // settings of the episode
  float target_reward_ = 1.f;
  float collision_reward_ = -1.f;
  float evade_distance_ = 2.f;

  // state
  btVector3 waypoint_{0, 0, 0};
  bool target_frozen_ = false;
  bool touched_ = false;
  int collisions_ = 0;
};

}  // namespace rlt

#endif  // RLT_ENV_DRONE_TARGET_DRONE_H_
