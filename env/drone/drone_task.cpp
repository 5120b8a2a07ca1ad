#include "env/drone/drone_task.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rl/env_api/uniform_random.h"

namespace rlt::drone {
namespace {

constexpr int kSpawnAttempts = 1000;

// records whether anything overlaps the probe (penetration, not mere proximity)
struct OverlapCallback : btCollisionWorld::ContactResultCallback {
  bool hit = false;
  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int,
                           const btCollisionObjectWrapper*, int, int) override {
    if (cp.getDistance() < 0) hit = true;
    return 0;
  }
};

}  // namespace

namespace {
std::string bad_parameter(const Env& env, const std::string& name, const std::string& what) {
  return env.spec().name + ": parameter " + name + " = " + std::to_string(env.parameter(name)) +
         " must be " + what;
}
}  // namespace

int int_parameter(const Env& env, const std::string& name, int lo, int hi) {
  const float v = env.parameter(name);
  if (!(v >= lo && v <= hi) || v != std::floor(v))
    throw std::invalid_argument(bad_parameter(
        env, name, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]"));
  return static_cast<int>(v);
}

float float_parameter(const Env& env, const std::string& name, float lo, float hi) {
  const float v = env.parameter(name);
  if (!(v >= lo && v <= hi))
    throw std::invalid_argument(bad_parameter(
        env, name, "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]"));
  return v;
}

Parameters drone_task_parameters(float episode_length, float arena_half_size, float arena_height) {
  const DroneParams d;
  return {{"episode_length", episode_length},    {"decision_period", 3.f},
          {"arena_half_size", arena_half_size},  {"arena_height", arena_height},
          {"drone_max_speed", d.max_speed},      {"drone_max_force", d.max_force},
          {"drone_max_yaw_rate", d.max_yaw_rate}};
}

DroneTaskSettings read_drone_task_settings(const Env& env) {
  DroneTaskSettings s;
  s.decision_period = int_parameter(env, "decision_period", 1, kMaxDecisionPeriod);
  s.episode_frames = int_parameter(env, "episode_length", s.decision_period, kMaxEpisodeFrames);
  s.arena.room = false;
  s.arena.half_size = float_parameter(env, "arena_half_size", 2.f, 50.f);
  s.arena.height = float_parameter(env, "arena_height", 2.f, 20.f);
  s.drone.max_speed = float_parameter(env, "drone_max_speed", 0.1f);
  s.drone.max_force = float_parameter(env, "drone_max_force", 0.f);
  s.drone.max_yaw_rate = float_parameter(env, "drone_max_yaw_rate", 0.f);
  return s;
}

int drone_ray_size() { return RaySensor().size(); }

BehaviorSpec drone_behavior_spec(const std::string& name, int vector_size, int slots) {
  BehaviorSpec b;
  b.name = name;
  b.observations.push_back({"vector", {vector_size}, ObservationKind::kVector, -1.f, 1.f});
  b.observations.push_back({"rays", {drone_ray_size()}, ObservationKind::kVector, 0.f, 1.f});
  b.action.continuous_size = kDroneActionSize;
  b.agent_slots = slots;
  return b;
}

DroneTask::DroneTask() {
  settings_.arena.room = false;
  arena_ = std::make_unique<Arena>(world_, settings_.arena);
}

void DroneTask::build(const DroneTaskSettings& settings) {
  settings_ = settings;
  drones_.clear();
  contacts_.clear();
  arena_.reset();
  world_.reset();
  arena_ = std::make_unique<Arena>(world_, settings_.arena);
  frame_ = 0;
}

DroneBody& DroneTask::add_drone(const btVector3& position, float yaw, Tag tag,
                                const DroneParams* params) {
  drones_.emplace_back(world_, position, yaw, tag, params ? *params : settings_.drone);
  return drones_.back();
}

void DroneTask::place(DroneBody& d, const btVector3& position, float yaw) {
  btTransform pose = btTransform::getIdentity();
  pose.setOrigin(position);
  pose.setRotation(btQuaternion(btVector3(0, 1, 0), yaw));
  btRigidBody& body = d.body();
  body.setWorldTransform(pose);
  body.setInterpolationWorldTransform(pose);
  if (body.getMotionState()) body.getMotionState()->setWorldTransform(pose);
  body.setLinearVelocity(btVector3(0, 0, 0));
  body.setAngularVelocity(btVector3(0, 0, 0));
  body.setInterpolationLinearVelocity(btVector3(0, 0, 0));
  body.setInterpolationAngularVelocity(btVector3(0, 0, 0));
  body.clearForces();
}

bool DroneTask::is_free(const btVector3& p, float radius) {
  const float h = settings_.arena.half_size - radius;
  if (std::abs(p.x()) > h || std::abs(p.z()) > h || p.y() < radius ||
      p.y() > settings_.arena.height - radius)
    return false;
  btSphereShape sphere(radius);
  btCollisionObject probe;
  probe.setCollisionShape(&sphere);
  btTransform pose = btTransform::getIdentity();
  pose.setOrigin(p);
  probe.setWorldTransform(pose);
  OverlapCallback overlap;
  world_.world().contactTest(&probe, overlap);
  return !overlap.hit;
}

btVector3 DroneTask::sample_free_position(std::mt19937_64& rng, float clearance,
                                          const std::vector<btVector3>& away, float min_distance,
                                          float y_min, float y_max) {
  const double h = settings_.arena.half_size - clearance;
  const double lo = std::max<double>(y_min, clearance);
  const double hi = std::max(lo, std::min<double>(y_max, settings_.arena.height - clearance));
  btVector3 p;
  for (int attempt = 0; attempt < kSpawnAttempts; ++attempt) {
    const double x = uniform(rng, -h, h);
    const double y = uniform(rng, lo, hi);
    const double z = uniform(rng, -h, h);
    p = btVector3(static_cast<btScalar>(x), static_cast<btScalar>(y), static_cast<btScalar>(z));
    bool ok = is_free(p, clearance);
    for (const btVector3& q : away) ok = ok && p.distance(q) >= min_distance;
    if (ok) break;
  }
  return p;
}

void DroneTask::step_frame() {
  world_.step_frame();
  contacts_.update(world_);
  ++frame_;
  ++total_frames_;
}

void DroneTask::write_common(const DroneBody& d, float* out) const {
  const btVector3 p = d.position(), v = d.velocity(), f = d.forward();
  const double half = settings_.arena.half_size, height = settings_.arena.height;
  const double speed = settings_.drone.max_speed;
  const float yaw = d.yaw();
  out[0] = clip1(p.x() / half);
  out[1] = clip1(2.0 * p.y() / height - 1.0);
  out[2] = clip1(p.z() / half);
  out[3] = clip1(v.x() / speed);
  out[4] = clip1(v.y() / speed);
  out[5] = clip1(v.z() / speed);
  out[6] = clip1(f.x());
  out[7] = clip1(f.y());
  out[8] = clip1(f.z());
  out[9] = clip1(std::sin(yaw));
  out[10] = clip1(std::cos(yaw));
  out[11] = std::clamp(static_cast<float>(frame_) / static_cast<float>(settings_.episode_frames),
                       0.f, 1.f);
}

void DroneTask::write_relative(const btVector3& from, const btVector3& to, float* out) const {
  const btVector3 a = to - from;
  const double span = 2.0 * settings_.arena.half_size;
  out[0] = clip1(a.x() / span);
  out[1] = clip1(a.y() / settings_.arena.height);
  out[2] = clip1(a.z() / span);
}

void DroneTask::write_rays(const DroneBody& d, float* out) const {
  rays_.observe(world_.world(), d.body(), out);
  // the sensor's values are in [0, 1] by construction; keep the declared bounds exact
  for (int i = 0; i < rays_.size(); ++i) out[i] = std::clamp(out[i], 0.f, 1.f);
}

int DroneTask::started_contacts(const btCollisionObject& body, Tag tag) const {
  int n = 0;
  for (const ContactPair& p : contacts_.started()) {
    const btCollisionObject* other = p.other(&body);
    n += other != nullptr && tag_of(*other) == tag;
  }
  return n;
}

}  // namespace rlt::drone
