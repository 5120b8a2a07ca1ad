// TargetDrone: spec, conformance, touching the target ends the episode with +1 (terminated), one
// collision penalty for one wall contact, the scripted target moves, seeded determinism, and a
// scripted chaser that catches the target where a still drone does not.
#include "env/drone/target_drone.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "env/register_builtin_envs.h"
#include "rl/env_api/conformance.h"
#include "tests/env/drone/scripted_pilot.h"
#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += s + "\n";
  return out;
}

void act(SingleEnvHarness& h, float forward, float strafe, float vertical, float yaw) {
  h.set_continuous(0, forward);
  h.set_continuous(1, strafe);
  h.set_continuous(2, vertical);
  h.set_continuous(3, yaw);
}

TEST(TargetDroneTest, Spec) {
  TargetDrone env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "TargetDrone");
  ASSERT_EQ(spec.behaviors.size(), 1u);
  const BehaviorSpec& b = spec.behaviors[0];
  EXPECT_EQ(b.name, "TargetDrone");
  EXPECT_EQ(b.agent_slots, 1);
  EXPECT_EQ(b.action.continuous_size, 4);
  EXPECT_EQ(b.observations.at(0).size(), 19);
  EXPECT_EQ(b.observations.at(1).size(), 119);
  EXPECT_EQ(spec.default_parameters.at("target_reward"), 1.f);
  EXPECT_EQ(spec.default_parameters.at("collision_reward"), -1.f);
}

TEST(TargetDroneTest, Conforms) {
  register_builtin_envs();
  ConformanceOptions opts;
  opts.num_envs = 2;
  opts.steps = 70;
  for (const Parameters& p :
       {Parameters{{"episode_length", 90.f}},
        Parameters{{"episode_length", 60.f}, {"arena_half_size", 3.f}, {"spawn_distance", 1.f}}}) {
    const auto violations = check_env_conformance("TargetDrone", p, opts);
    EXPECT_TRUE(violations.empty()) << joined(violations);
  }
}

TEST(TargetDroneTest, TargetMovesOnItsOwn) {
  TargetDrone env;
  SingleEnvHarness h(env);
  h.reset();
  const btVector3 start = env.target().position();
  act(h, 0, 0, 0, 0);
  for (int k = 0; k < 20; ++k) h.step();
  EXPECT_GT(env.target().position().distance(start), 2.0);  // 1.2 s at up to 2.5 m/s
  EXPECT_LE(env.target().velocity().length(), 2.5 + 1e-3);
}

TEST(TargetDroneTest, TouchingTheTargetEndsTheEpisodeWithPlusOne) {
  TargetDrone env;
  SingleEnvHarness h(env);
  h.reset();
  env.freeze_target(true);
  drone::DroneTask::place(env.target(), btVector3(0, 3, 2));
  drone::DroneTask::place(env.chaser(), btVector3(0, 3, 0), 0.f);  // faces +z, 1.3 m gap
  act(h, 1, 0, 0, 0);
  double total = 0;
  int steps = 0;
  while (h.step_type() != StepType::kLast && steps < 50) {
    h.step();
    total += h.reward();
    ++steps;
  }
  EXPECT_EQ(h.step_type(), StepType::kLast);
  EXPECT_EQ(h.terminated(), 1);
  EXPECT_FLOAT_EQ(static_cast<float>(total), 1.f);
  EXPECT_LT(steps, 15);
  EXPECT_EQ(env.episode_metrics().at("success"), 1.f);
  EXPECT_EQ(env.episode_metrics().at("collisions"), 0.f);
  h.step();  // the agent is gone
  EXPECT_EQ(h.step_type(), StepType::kAbsent);
}

TEST(TargetDroneTest, OneWallContactIsOneCollision) {
  TargetDrone env;
  SingleEnvHarness h(env);
  h.reset();
  env.freeze_target(true);
  drone::DroneTask::place(env.target(), btVector3(-8, 3, -8));
  // 2 m from the -z wall (inner face z = -10), facing it (yaw pi: forward = -z)
  drone::DroneTask::place(env.chaser(), btVector3(5, 3, -8), static_cast<float>(M_PI));
  act(h, 1, 0, 0, 0);
  double total = 0;
  for (int k = 0; k < 60; ++k) {
    h.step();
    total += h.reward();
  }
  EXPECT_LT(env.chaser().position().z(), -10 + 0.35 + 0.05);
  EXPECT_FLOAT_EQ(static_cast<float>(total), -1.f);
  EXPECT_EQ(env.episode_metrics().at("collisions"), 1.f);
  EXPECT_EQ(h.step_type(), StepType::kMid);
}

std::vector<float> rollout(uint64_t seed, int steps) {
  TargetDrone env;
  env.seed(seed);
  SingleEnvHarness h(env);
  h.reset();
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<float> out;
  for (int k = 0; k < steps && needs_action(h.step_type()); ++k) {
    act(h, u(rng), u(rng), u(rng), u(rng));
    h.step();
    for (int o = 0; o < 2; ++o)
      out.insert(out.end(), h.buffers().observations[o].begin(), h.buffers().observations[o].end());
    out.push_back(h.reward());
  }
  return out;
}

TEST(TargetDroneTest, SameSeedSameTrajectory) {
  const std::vector<float> a = rollout(7, 150), b = rollout(7, 150), c = rollout(8, 150);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
  EXPECT_NE(a, c);
}

// success of one episode with the pilot flying at the target's observed position, or still
float chase(uint64_t seed, bool fly) {
  TargetDrone env;
  env.seed(seed);
  SingleEnvHarness h(env);
  h.reset();
  const drone::DroneTaskSettings s = drone::read_drone_task_settings(env);
  while (needs_action(h.step_type())) {
    const float* obs = h.observation(0);
    const auto rel = drone::decode_relative(obs + 12, s);
    // aim a little ahead of the target, along its observed velocity
    const float lead = 0.3f;
    const float dx = rel[0] + lead * obs[15] * s.drone.max_speed;
    const float dy = rel[1] + lead * obs[16] * s.drone.max_speed;
    const float dz = rel[2] + lead * obs[17] * s.drone.max_speed;
    const auto a = fly ? drone::pilot_actions(obs, dx, dy, dz, s.drone.max_speed, 5.f, 4.f)
                       : std::array<float, 4>{0, 0, 0, 0};
    act(h, a[0], a[1], a[2], a[3]);
    h.step();
  }
  return env.episode_metrics().at("success");
}

TEST(TargetDroneTest, PilotCatchesTheTargetStillDroneDoesNot) {
  int flown = 0, still = 0;
  const int episodes = 10;
  for (uint64_t seed = 1; seed <= episodes; ++seed) {
    flown += chase(seed, true) > 0;
    still += chase(seed, false) > 0;
  }
  EXPECT_GE(flown, 9);
  EXPECT_EQ(still, 0);
}

}  // namespace
}  // namespace rlt
