#include "env/drone/hummingbird.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rl/env_api/uniform_random.h"

namespace rlt {

using drone::DroneTask;

namespace {
constexpr float kPillarSpacing = 3.0f;  // between pillar centres (m)
constexpr float kPillarMargin = 2.0f;   // from the boundary walls to a pillar centre (m)
constexpr float kNectarMinHeight = 1.0f;
constexpr float kSpawnGap = 1.0f;  // from a nectar sphere's surface to the spawned drone (m)
constexpr int kPlacementAttempts = 1000;
}  // namespace

Hummingbird::Hummingbird() {
  spec_.name = "Hummingbird";
  spec_.behaviors = {drone::drone_behavior_spec("Hummingbird", kObservationSize, 1)};
  spec_.max_episode_steps = drone::kMaxEpisodeFrames;
  spec_.default_parameters = drone::drone_task_parameters(3000.f, 12.f, 6.f);
  spec_.default_parameters.insert({{"num_nectar", 5.f},
                                   {"nectar_radius", 1.f},
                                   {"nectar_reward", 0.01f},
                                   {"nectar_capacity", 0.f},
                                   {"collision_reward", -0.5f},
                                   {"num_obstacles", 4.f},
                                   {"obstacle_half_size", 0.5f}});
}

int Hummingbird::nectar_at(const btVector3& p) const {
  for (size_t i = 0; i < nectar_.size(); ++i)
    if (nectar_[i].left != 0 && p.distance(nectar_[i].centre) <= nectar_radius_)
      return static_cast<int>(i);
  return -1;
}

void Hummingbird::write_observation(BehaviorView& view) {
  const drone::DroneBody& d = task_.drone(0);
  float* obs = view.observation(0, 0);  // [16]
  std::fill(obs, obs + kObservationSize, 0.f);
  task_.write_common(d, obs);
  const btVector3 p = d.position();
  int nearest = -1;
  btScalar best = std::numeric_limits<btScalar>::max();
  for (size_t i = 0; i < nectar_.size(); ++i) {
    if (nectar_[i].left == 0) continue;
    const btScalar dist = p.distance(nectar_[i].centre);
    if (dist < best) best = dist, nearest = static_cast<int>(i);
  }
  if (nearest >= 0) task_.write_relative(p, nectar_[nearest].centre, obs + 12);
  obs[15] = nectar_at(p) >= 0 ? 1.f : 0.f;
  task_.write_rays(d, view.observation(0, 1));
}

void Hummingbird::reset(StepView& out) {
  // settings
  const drone::DroneTaskSettings settings = drone::read_drone_task_settings(*this);
  const int num_nectar = drone::int_parameter(*this, "num_nectar", 1, kMaxNectar);
  const int num_obstacles = drone::int_parameter(*this, "num_obstacles", 0, kMaxObstacles);
  const int capacity = drone::int_parameter(*this, "nectar_capacity", 0, drone::kMaxEpisodeFrames);
  const float half = settings.arena.half_size, height = settings.arena.height;
  nectar_radius_ = drone::float_parameter(*this, "nectar_radius", 0.1f, 0.25f * height);
  nectar_reward_ = parameter("nectar_reward");
  collision_reward_ = parameter("collision_reward");
  const float pillar = drone::float_parameter(*this, "obstacle_half_size", 0.05f, 2.f);

  // world, pillars
  task_.build(settings);
  std::vector<btVector3> pillars;
  const double lim = std::max(half - kPillarMargin, 0.f);
  for (int i = 0; i < num_obstacles; ++i) {
    btVector3 c;
    for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
      c = btVector3(static_cast<btScalar>(uniform(engine_, -lim, lim)), 0.5f * height,
                    static_cast<btScalar>(uniform(engine_, -lim, lim)));
      bool ok = true;
      for (const btVector3& q : pillars) ok = ok && c.distance(q) >= kPillarSpacing;
      if (ok) break;
    }
    pillars.push_back(c);
    task_.world().add_static_box(c, btVector3(pillar, 0.5f * height, pillar), drone::kObstacle);
  }

  // nectar, then the drone outside it
  nectar_.clear();
  std::vector<btVector3> centres;
  for (int i = 0; i < num_nectar; ++i) {
    const btVector3 c =
        task_.sample_free_position(engine_, nectar_radius_, centres, 2 * nectar_radius_,
                                   kNectarMinHeight, height - kNectarMinHeight);
    centres.push_back(c);
    nectar_.push_back({c, capacity > 0 ? capacity : -1});
  }
  const float r = settings.drone.radius;
  const btVector3 start =
      task_.sample_free_position(engine_, r + 0.05f, centres, nectar_radius_ + kSpawnGap);
  const float yaw = static_cast<float>(uniform(engine_, -M_PI, M_PI));
  task_.add_drone(start, yaw, drone::kSeeker);
  nectar_frames_ = 0;
  collisions_ = 0;

  // first step
  BehaviorView& view = out[0];
  view.step_type(0) = StepType::kFirst;
  view.agent_id(0) = 0;
  view.group_id(0) = 0;
  view.reward(0) = 0.f;
  view.group_reward(0) = 0.f;
  view.terminated(0) = 0;
  write_observation(view);
}

void Hummingbird::step(StepView& io) {
  BehaviorView& view = io[0];
  if (!needs_action(view.step_type(0))) {
    view.step_type(0) = StepType::kAbsent;
    view.agent_id(0) = -1;
    return;
  }
  const float* a = view.continuous_action(0);  // [4]
  drone::DroneBody& d = task_.drone(0);
  const int period = task_.settings().decision_period;
  double reward = 0.0;
  for (int f = 0; f < period && !task_.time_up(); ++f) {
    d.apply_action(a[0], a[1], a[2], a[3]);
    task_.step_frame();
    // nectar
    const int i = nectar_at(d.position());
    if (i >= 0) {
      reward += nectar_reward_;
      ++nectar_frames_;
      if (nectar_[i].left > 0) --nectar_[i].left;
    }
    // collisions that start in this frame
    const int hits = task_.started_contacts(d.body(), drone::kWall) +
                     task_.started_contacts(d.body(), drone::kObstacle);
    reward += hits * collision_reward_;
    collisions_ += hits;
  }
  view.reward(0) = static_cast<float>(reward);
  write_observation(view);
  if (task_.time_up()) {
    view.step_type(0) = StepType::kLast;
    view.terminated(0) = 0;
  } else {
    view.step_type(0) = StepType::kMid;
  }
}

EpisodeMetrics Hummingbird::episode_metrics() const {
  const int frames = std::max(task_.frame(), 1);
  return {{"nectar_frames", static_cast<float>(nectar_frames_)},
          {"collisions", static_cast<float>(collisions_)},
          {"nectar_fraction", static_cast<float>(nectar_frames_) / static_cast<float>(frames)}};
}

}  // namespace rlt
