// Eye: two allied drones search a small arena for a target at an unknown place (SPEC.md section 7,
// the third of the paper's pre-experiments).
//
// World (DroneTask conventions, drone_task.h): an open arena, default 10 x 10 x 4 m. The target
// is a static cube of half side target_half_size (tag kHider) at a seeded free place with its
// centre at heights in [0.5, height - 0.5] m. The two drones (tag kSeeker) spawn at seeded free
// places at least spawn_distance from the target and 1 m apart, with seeded yaws.
// Behavior "Eye": 2 slots, both in group 0, agent ids 0 and 1; 4 continuous actions in [-1, 1]
// (forward, strafe, vertical, yaw rate) repeated for `decision_period` physics frames at 50 Hz.
// Seeing: drone i sees the target when vision.h sees() says so (cone vision_cone degrees, range
// vision_range, line of sight not blocked by the ally).
// Rewards, summed over the frames of a decision (group_reward is shared by both drones, reward is
// each drone's own):
//   group_reward +target_reward (1) when either drone touches the target (a contact point at
//     <= 0.01 m, contacts.h): the episode ends at once for both (kLast, terminated 1);
//   group_reward +view_reward (0.001) per frame the target is in view of at least one drone;
//   reward +wall_reward (-0.2) per collision of that drone with a wall, the floor or the ceiling,
//     counted when the contact starts (ContactTracker);
//   reward +ally_reward (-0.5) for each drone of the pair when the two drones collide (contact
//     start).
// End: the touch, or truncation after episode_length frames (kLast, terminated 0, both drones).
// Parameters (defaults): the DroneTask ones (episode_length 1500 frames = 500 decisions,
// decision_period 3, arena_half_size 5, arena_height 4, drone_max_speed 5, drone_max_force 20,
// drone_max_yaw_rate 3), target_reward 1, view_reward 0.001, wall_reward -0.2, ally_reward -0.5,
// target_half_size 0.3 (m), spawn_distance 3 (m), vision_cone 135 (degrees, full angle),
// vision_range 20 (m).
// Observations of drone i (the ally is the other slot):
//   "vector" [21] in [-1, 1]: [0, 12) the DroneTask common block; [12, 15) relative position of
//     the target (write_relative) while either drone sees it (the pair shares what it spots),
//     zeros otherwise; [15] 1 when this drone sees the target; [16] 1 when the ally sees it;
//     [17, 20) relative position of the ally; [20] ally present flag (always 1: both drones
//     stay the whole episode).
//   "rays" [119] in [0, 1]: RaySensor (the target is a kHider hit, the ally a kSeeker hit).
// Metrics: "success" (1 if the target was reached), "seen_fraction" (frames with the target in
// view of some drone / frames played), "wall_collisions", "ally_collisions", "frames".
#ifndef RLT_ENV_DRONE_EYE_H_
#define RLT_ENV_DRONE_EYE_H_

#include <array>
#include <cstdint>
#include <random>

#include "env/drone/drone_task.h"
#include "rl/env_api/env.h"

namespace rlt {

class Eye : public Env {
 public:
  static constexpr int kObservationSize = 21;
  static constexpr int kDrones = 2;

  Eye();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override { engine_.seed(seed); }
  void reset(StepView& out) override;
  void step(StepView& io) override;
  EpisodeMetrics episode_metrics() const override;
  uint64_t physics_frames() const override { return task_.total_frames(); }

  // the current episode, for tests
  drone::DroneTask& task() { return task_; }
  drone::DroneBody& drone(int i) { return task_.drone(i); }
  const btRigidBody& target() const { return *target_; }
  bool seen_by(int i) const { return seen_[i]; }

 private:
  void update_sight();
  void write_observation(BehaviorView& view, int slot);

  EnvSpec spec_;
  std::mt19937_64 engine_;
  drone::DroneTask task_;

  // settings of the episode
  float target_reward_ = 1.f;
  float view_reward_ = 0.001f;
  float wall_reward_ = -0.2f;
  float ally_reward_ = -0.5f;
  float vision_cone_ = 135.f;
  float vision_range_ = 20.f;

  // state
  btRigidBody* target_ = nullptr;  // owned by the world
  std::array<bool, kDrones> seen_{};
  bool reached_ = false;
  int seen_frames_ = 0;
  int wall_collisions_ = 0;
  int ally_collisions_ = 0;
};

}  // namespace rlt

#endif  // RLT_ENV_DRONE_EYE_H_
