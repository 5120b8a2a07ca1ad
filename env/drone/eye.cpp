#include "env/drone/eye.h"

#include <algorithm>
#include <cmath>

#include "env/drone/vision.h"
#include "rl/env_api/uniform_random.h"

namespace rlt {

namespace {
constexpr float kTargetMinHeight = 0.5f;  // m, of the target's centre
constexpr float kDroneSpacing = 1.0f;     // m, between the drones at spawn
}  // namespace

Eye::Eye() {
  spec_.name = "Eye";
  spec_.behaviors = {drone::drone_behavior_spec("Eye", kObservationSize, kDrones)};
  spec_.max_episode_steps = drone::kMaxEpisodeFrames;
  spec_.default_parameters = drone::drone_task_parameters(1500.f, 5.f, 4.f);
  spec_.default_parameters.insert({{"target_reward", 1.f},
                                   {"view_reward", 0.001f},
                                   {"wall_reward", -0.2f},
                                   {"ally_reward", -0.5f},
                                   {"target_half_size", 0.3f},
                                   {"spawn_distance", 3.f},
                                   {"vision_cone", 135.f},
                                   {"vision_range", 20.f}});
}

void Eye::update_sight() {
  for (int i = 0; i < kDrones; ++i)
    seen_[i] =
        drone::sees(task_.world(), task_.drone(i).body(), *target_, vision_cone_, vision_range_);
}

void Eye::write_observation(BehaviorView& view, int slot) {
  const drone::DroneBody& me = task_.drone(slot);
  const drone::DroneBody& ally = task_.drone(1 - slot);
  float* obs = view.observation(slot, 0);  // [21]
  std::fill(obs, obs + kObservationSize, 0.f);
  task_.write_common(me, obs);
  if (seen_[0] || seen_[1])
    task_.write_relative(me.position(), target_->getWorldTransform().getOrigin(), obs + 12);
  obs[15] = seen_[slot] ? 1.f : 0.f;
  obs[16] = seen_[1 - slot] ? 1.f : 0.f;
  task_.write_relative(me.position(), ally.position(), obs + 17);
  obs[20] = 1.f;
  task_.write_rays(me, view.observation(slot, 1));
}

void Eye::reset(StepView& out) {
  // settings
  const drone::DroneTaskSettings settings = drone::read_drone_task_settings(*this);
  target_reward_ = parameter("target_reward");
  view_reward_ = parameter("view_reward");
  wall_reward_ = parameter("wall_reward");
  ally_reward_ = parameter("ally_reward");
  vision_cone_ = drone::float_parameter(*this, "vision_cone", 0.f, 360.f);
  vision_range_ = drone::float_parameter(*this, "vision_range", 0.f);
  const float height = settings.arena.height;
  const float half = drone::float_parameter(*this, "target_half_size", 0.05f, 0.25f * height);
  const float spawn_distance = drone::float_parameter(*this, "spawn_distance", 0.f);

  // world, target, drones
  task_.build(settings);
  const btVector3 centre = task_.sample_free_position(
      engine_, std::sqrt(3.f) * half + 0.05f, {}, 0.f, kTargetMinHeight, height - kTargetMinHeight);
  target_ = task_.world().add_static_box(centre, btVector3(half, half, half), drone::kHider);
  const float clearance = settings.drone.radius + 0.05f;
  const btVector3 first = task_.sample_free_position(engine_, clearance, {centre}, spawn_distance);
  const float yaw0 = static_cast<float>(uniform(engine_, -M_PI, M_PI));
  task_.add_drone(first, yaw0, drone::kSeeker);
  btVector3 second;
  for (int attempt = 0; attempt < 1000; ++attempt) {
    second = task_.sample_free_position(engine_, clearance, {centre}, spawn_distance);
    if (second.distance(first) >= 2 * settings.drone.radius + kDroneSpacing) break;
  }
  const float yaw1 = static_cast<float>(uniform(engine_, -M_PI, M_PI));
  task_.add_drone(second, yaw1, drone::kSeeker);
  reached_ = false;
  seen_frames_ = 0;
  wall_collisions_ = 0;
  ally_collisions_ = 0;
  update_sight();

  BehaviorView& view = out[0];
  for (int s = 0; s < kDrones; ++s) {
    view.step_type(s) = StepType::kFirst;
    view.agent_id(s) = s;
    view.group_id(s) = 0;
    view.reward(s) = 0.f;
    view.group_reward(s) = 0.f;
    view.terminated(s) = 0;
    write_observation(view, s);
  }
}

void Eye::step(StepView& io) {
  BehaviorView& view = io[0];
  std::array<bool, kDrones> acting{};
  for (int s = 0; s < kDrones; ++s) {
    acting[s] = needs_action(view.step_type(s));
    if (acting[s]) continue;
    view.step_type(s) = StepType::kAbsent;
    view.agent_id(s) = -1;
  }
  if (!acting[0] && !acting[1]) return;

  const int period = task_.settings().decision_period;
  std::array<double, kDrones> reward{};
  double group_reward = 0.0;
  for (int f = 0; f < period && !task_.time_up() && !reached_; ++f) {
    for (int s = 0; s < kDrones; ++s) {
      const float* a = view.continuous_action(s);  // [4]
      if (acting[s]) task_.drone(s).apply_action(a[0], a[1], a[2], a[3]);
    }
    task_.step_frame();
    // collisions that start in this frame
    for (int s = 0; s < kDrones; ++s) {
      const int hits = task_.started_contacts(task_.drone(s).body(), drone::kWall);
      reward[s] += hits * wall_reward_;
      wall_collisions_ += hits;
    }
    if (task_.contacts().started(&task_.drone(0).body(), &task_.drone(1).body())) {
      reward[0] += ally_reward_;
      reward[1] += ally_reward_;
      ++ally_collisions_;
    }
    // sight and reaching
    update_sight();
    if (seen_[0] || seen_[1]) {
      group_reward += view_reward_;
      ++seen_frames_;
    }
    for (int s = 0; s < kDrones; ++s)
      reached_ = reached_ || task_.contacts().touching(&task_.drone(s).body(), target_);
    if (reached_) group_reward += target_reward_;
  }

  for (int s = 0; s < kDrones; ++s) {
    if (!acting[s]) continue;
    view.reward(s) = static_cast<float>(reward[s]);
    view.group_reward(s) = static_cast<float>(group_reward);
    write_observation(view, s);
    if (reached_) {
      view.step_type(s) = StepType::kLast;
      view.terminated(s) = 1;
    } else if (task_.time_up()) {
      view.step_type(s) = StepType::kLast;
      view.terminated(s) = 0;
    } else {
      view.step_type(s) = StepType::kMid;
    }
  }
}

EpisodeMetrics Eye::episode_metrics() const {
  const int frames = std::max(task_.frame(), 1);
  return {{"success", reached_ ? 1.f : 0.f},
          {"seen_fraction", static_cast<float>(seen_frames_) / static_cast<float>(frames)},
          {"wall_collisions", static_cast<float>(wall_collisions_)},
          {"ally_collisions", static_cast<float>(ally_collisions_)},
          {"frames", static_cast<float>(task_.frame())}};
}

}  // namespace rlt
