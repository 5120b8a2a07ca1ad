// DroneTask: what the drone tasks (SPEC.md section 7: Hummingbird, TargetDrone, Eye) share, built
// from the hide-and-seek world's pieces: a BulletWorld with an open Arena (no room), DroneBody
// agents, a ContactTracker, the RaySensor and the common vector observation.
//
// Time (SPEC section 6 conventions): physics at 50 Hz; an agent decides every `decision_period`
// frames (default 3) and its action is repeated for those frames (DroneBody::apply_action before
// every frame). An episode lasts at most `episode_length` frames (truncated at the limit).
// Actions: 4 continuous in [-1, 1]: forward thrust, strafe, vertical thrust, yaw rate.
// The tasks declare spec.max_episode_steps = kMaxEpisodeFrames, the most decisions any setting
// allows (episode_length at its largest with decision_period 1).
// Common parameters of every task (task-specific defaults, see drone_task_parameters()):
//   episode_length      frames per episode, in [decision_period, kMaxEpisodeFrames]
//   decision_period     frames per decision, in [1, kMaxDecisionPeriod] (default 3)
//   arena_half_size     half the side of the square floor (m), in [2, 50]
//   arena_height        floor to ceiling (m), in [2, 20]
//   drone_max_speed     speed cap of a drone (m/s, default 5)
//   drone_max_force     thrust at action 1 (N, default 20)
//   drone_max_yaw_rate  yaw rate at action 1 (rad/s, default 3)
// Common vector observation, kCommonObservationSize = 12 floats, each clipped to [-1, 1]:
//   [0, 3)  position: x / half_size, 2 y / height - 1, z / half_size
//   [3, 6)  velocity / drone_max_speed (x, y, z)
//   [6, 9)  forward vector (x, y, z; y is 0, the drone stays upright)
//   [9, 11) yaw as (sin, cos)
//   [11]    frames elapsed / episode_length (in [0, 1])
// A relative position (write_relative) is (to - from) with x, z divided by 2 half_size and y by
// height, so that any two points of the arena give values in [-1, 1] (clipped as well).
// Rays: a RaySensor with its defaults (17 rays over 360 degrees, 20 m, sphere radius 0.3 m, 7
// floats per ray, 119 floats in [0, 1]); its layout fixes the observation size, so it is not a
// parameter. The tasks tag their drones kSeeker and their targets kHider (the rays' one-hot).
#ifndef RLT_ENV_DRONE_DRONE_TASK_H_
#define RLT_ENV_DRONE_DRONE_TASK_H_

#include <btBulletDynamicsCommon.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "env/drone/arena.h"
#include "env/drone/bullet_world.h"
#include "env/drone/contacts.h"
#include "env/drone/drone_body.h"
#include "env/drone/ray_sensor.h"
#include "rl/env_api/env.h"

namespace rlt::drone {

inline constexpr int kDroneActionSize = 4;  // forward, strafe, vertical, yaw rate
inline constexpr int kCommonObservationSize = 12;
inline constexpr int kMaxEpisodeFrames = 30000;  // the largest episode_length (10 min)
inline constexpr int kMaxDecisionPeriod = 10;

// settings shared by the tasks, read from the env's parameters at reset
struct DroneTaskSettings {
  ArenaParams arena;          // open (room = false), size from the parameters
  DroneParams drone;          // the agents' drones: speed, force, yaw rate from the parameters
  int decision_period = 3;    // frames per decision
  int episode_frames = 3000;  // frames per episode
};

// the common parameters with a task's defaults
Parameters drone_task_parameters(float episode_length, float arena_half_size, float arena_height);
// the common settings of `env` (its current parameters)
DroneTaskSettings read_drone_task_settings(const Env& env);

// a behavior of drones: observations "vector" ([vector_size] in [-1, 1]) and "rays" (RaySensor
// defaults, [0, 1]); 4 continuous actions; `slots` agents
BehaviorSpec drone_behavior_spec(const std::string& name, int vector_size, int slots);
// the rays observation size (119)
int drone_ray_size();

class DroneTask {
 public:
  DroneTask();

  // rebuilds the world (BulletWorld::reset) with settings.arena (open for the tasks; a room is
  // built when arena.room is set); forgets drones and contacts
  void build(const DroneTaskSettings& settings);
  // adds a drone; index = number of drones added before it since build(). The reference is valid
  // until the next add_drone() or build(); drone(i) stays valid.
  DroneBody& add_drone(const btVector3& position, float yaw, Tag tag,
                       const DroneParams* params = nullptr);
  // test hook: moves a drone to `position` facing `yaw`, at rest
  static void place(DroneBody& d, const btVector3& position, float yaw = 0.0f);

  // true when a sphere of `radius` at `p` lies inside the arena's inner faces and overlaps no body
  bool is_free(const btVector3& p, float radius);
  // a seeded position, uniform over the arena shrunk by `clearance` with y in [y_min, y_max]
  // (clamped to the shrunk height), free for a sphere of `clearance` and at least `min_distance`
  // from every point of `away`; after 1000 failed draws the last draw is returned
  btVector3 sample_free_position(std::mt19937_64& rng, float clearance,
                                 const std::vector<btVector3>& away = {}, float min_distance = 0.0f,
                                 float y_min = 0.0f, float y_max = 1e9f);

  // one physics frame: world step, contacts updated, frame counter advanced
  void step_frame();
  int frame() const { return frame_; }  // frames since build()
  uint64_t total_frames() const { return total_frames_; }  // frames since construction
  bool time_up() const { return frame_ >= settings_.episode_frames; }

  // writes kCommonObservationSize floats
  void write_common(const DroneBody& d, float* out) const;
  // writes 3 floats: (to - from) scaled as in the header, clipped to [-1, 1]
  void write_relative(const btVector3& from, const btVector3& to, float* out) const;
  // writes drone_ray_size() floats
  void write_rays(const DroneBody& d, float* out) const;

  // number of contacts of `body` that started this frame with bodies of tag `tag`
  int started_contacts(const btCollisionObject& body, Tag tag) const;

  BulletWorld& world() { return world_; }
  const Arena& arena() const { return *arena_; }
  const ContactTracker& contacts() const { return contacts_; }
  std::vector<DroneBody>& drones() { return drones_; }
  DroneBody& drone(int i) { return drones_[i]; }
  const DroneTaskSettings& settings() const { return settings_; }

 private:
  DroneTaskSettings settings_;
  BulletWorld world_;
  std::unique_ptr<Arena> arena_;
  std::vector<DroneBody> drones_;
  ContactTracker contacts_;
  RaySensor rays_;
  int frame_ = 0;
  uint64_t total_frames_ = 0;
};

// clips to [-1, 1]
inline float clip1(double x) { return static_cast<float>(x < -1.0 ? -1.0 : x > 1.0 ? 1.0 : x); }
// parameter `name` of `env`, which must be an integer in [lo, hi] (a number in [lo, hi]); anything
// else throws std::invalid_argument naming the env, the parameter, its value and the range
int int_parameter(const Env& env, const std::string& name, int lo, int hi);
float float_parameter(const Env& env, const std::string& name, float lo,
                      float hi = std::numeric_limits<float>::infinity());

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_DRONE_TASK_H_
