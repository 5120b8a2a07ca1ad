#include "env/drone/target_drone.h"

#include <algorithm>
#include <cmath>

#include "env/drone/vision.h"
#include "rl/env_api/uniform_random.h"

namespace rlt {

namespace {
constexpr float kWaypointClearance = 1.0f;  // m, from walls, floor and ceiling
constexpr float kWaypointMinHeight = 1.0f;
}  // namespace

TargetDrone::TargetDrone() {
  spec_.name = "TargetDrone";
  spec_.behaviors = {drone::drone_behavior_spec("TargetDrone", kObservationSize, 1)};
  spec_.max_episode_steps = drone::kMaxEpisodeFrames;
  spec_.default_parameters = drone::drone_task_parameters(1500.f, 10.f, 6.f);
  spec_.default_parameters.insert({{"target_speed", 2.5f},
                                   {"target_radius", 0.35f},
                                   {"target_reward", 1.f},
                                   {"collision_reward", -1.f},
                                   {"spawn_distance", 5.f},
                                   {"evade_distance", 2.f}});
}

void TargetDrone::move_target() {
  drone::DroneBody& t = task_.drone(1);
  if (target_frozen_) {
    drone::DroneTask::place(t, t.position(), t.yaw());
    return;
  }
  const btVector3 p = t.position();
  if (p.distance(waypoint_) < kWaypointReach) {
    const float height = task_.settings().arena.height;
    waypoint_ = task_.sample_free_position(engine_, kWaypointClearance, {}, 0.f, kWaypointMinHeight,
                                           height - kWaypointMinHeight);
  }
  btVector3 dir = waypoint_ - p;
  // flee straight away from a close chaser
  const btVector3 away = p - task_.drone(0).position();
  if (away.length() < evade_distance_) dir = away;
  const btScalar len = dir.length();
  if (len > 1e-6f) dir /= len;
  t.apply_action(dir.dot(t.forward()), dir.dot(t.right()), dir.y(), 0.f);
}

void TargetDrone::write_observation(BehaviorView& view) {
  const drone::DroneBody& c = task_.drone(0);
  const drone::DroneBody& t = task_.drone(1);
  float* obs = view.observation(0, 0);  // [19]
  std::fill(obs, obs + kObservationSize, 0.f);
  task_.write_common(c, obs);
  task_.write_relative(c.position(), t.position(), obs + 12);
  const btVector3 v = t.velocity();
  const double speed = task_.settings().drone.max_speed;
  obs[15] = drone::clip1(v.x() / speed);
  obs[16] = drone::clip1(v.y() / speed);
  obs[17] = drone::clip1(v.z() / speed);
  obs[18] = drone::sees(task_.world(), c.body(), t.body()) ? 1.f : 0.f;
  task_.write_rays(c, view.observation(0, 1));
}

void TargetDrone::reset(StepView& out) {
  // settings
  const drone::DroneTaskSettings settings = drone::read_drone_task_settings(*this);
  target_reward_ = parameter("target_reward");
  collision_reward_ = parameter("collision_reward");
  const float height = settings.arena.height;
  drone::DroneParams target_params = settings.drone;
  target_params.max_speed = drone::float_parameter(*this, "target_speed", 0.f);
  target_params.radius = drone::float_parameter(*this, "target_radius", 0.05f, 0.25f * height);
  const float spawn_distance = drone::float_parameter(*this, "spawn_distance", 0.f);
  evade_distance_ = drone::float_parameter(*this, "evade_distance", 0.f);

  // world; target start, first waypoint and chaser start are drawn first, then the chaser is
  // added as drone 0 and the target as drone 1
  task_.build(settings);
  const btVector3 target_start =
      task_.sample_free_position(engine_, target_params.radius + 0.05f, {}, 0.f, kWaypointMinHeight,
                                 height - kWaypointMinHeight);
  waypoint_ = task_.sample_free_position(engine_, kWaypointClearance, {}, 0.f, kWaypointMinHeight,
                                         height - kWaypointMinHeight);
  const btVector3 start = task_.sample_free_position(engine_, settings.drone.radius + 0.05f,
                                                     {target_start}, spawn_distance);
  const float yaw = static_cast<float>(uniform(engine_, -M_PI, M_PI));
  task_.add_drone(start, yaw, drone::kSeeker);
  task_.add_drone(target_start, 0.f, drone::kHider, &target_params);
  target_frozen_ = false;
  touched_ = false;
  collisions_ = 0;

  BehaviorView& view = out[0];
  view.step_type(0) = StepType::kFirst;
  view.agent_id(0) = 0;
  view.group_id(0) = 0;
  view.reward(0) = 0.f;
  view.group_reward(0) = 0.f;
  view.terminated(0) = 0;
  write_observation(view);
}

void TargetDrone::step(StepView& io) {
  BehaviorView& view = io[0];
  if (!needs_action(view.step_type(0))) {
    view.step_type(0) = StepType::kAbsent;
    view.agent_id(0) = -1;
    return;
  }
  const float* a = view.continuous_action(0);  // [4]
  const int period = task_.settings().decision_period;
  double reward = 0.0;
  for (int f = 0; f < period && !task_.time_up() && !touched_; ++f) {
    task_.drone(0).apply_action(a[0], a[1], a[2], a[3]);
    move_target();
    task_.step_frame();
    drone::DroneBody& c = task_.drone(0);
    const int hits = task_.started_contacts(c.body(), drone::kWall);
    reward += hits * collision_reward_;
    collisions_ += hits;
    if (task_.contacts().touching(&c.body(), &task_.drone(1).body())) {
      touched_ = true;
      reward += target_reward_;
    }
  }
  view.reward(0) = static_cast<float>(reward);
  write_observation(view);
  if (touched_) {
    view.step_type(0) = StepType::kLast;
    view.terminated(0) = 1;
  } else if (task_.time_up()) {
    view.step_type(0) = StepType::kLast;
    view.terminated(0) = 0;
  } else {
    view.step_type(0) = StepType::kMid;
  }
}

EpisodeMetrics TargetDrone::episode_metrics() const {
  return {{"success", touched_ ? 1.f : 0.f},
          {"collisions", static_cast<float>(collisions_)},
          {"frames", static_cast<float>(task_.frame())}};
}

}  // namespace rlt
