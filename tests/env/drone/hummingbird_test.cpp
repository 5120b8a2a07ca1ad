// Hummingbird: spec, conformance, +nectar_reward per frame inside nectar, one collision penalty
// for one wall contact, seeded determinism, and a scripted pilot that finds nectar where a still
// drone finds none.
#include "env/drone/hummingbird.h"

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

TEST(HummingbirdTest, Spec) {
  Hummingbird env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "Hummingbird");
  ASSERT_EQ(spec.behaviors.size(), 1u);
  const BehaviorSpec& b = spec.behaviors[0];
  EXPECT_EQ(b.name, "Hummingbird");
  EXPECT_EQ(b.agent_slots, 1);
  EXPECT_EQ(b.action.continuous_size, 4);
  EXPECT_EQ(b.action.num_branches(), 0);
  ASSERT_EQ(b.observations.size(), 2u);
  EXPECT_EQ(b.observations[0].name, "vector");
  EXPECT_EQ(b.observations[0].size(), 16);
  EXPECT_EQ(b.observations[1].name, "rays");
  EXPECT_EQ(b.observations[1].size(), 119);
  EXPECT_EQ(spec.default_parameters.at("episode_length"), 3000.f);
  EXPECT_EQ(spec.default_parameters.at("decision_period"), 3.f);
  EXPECT_EQ(spec.default_parameters.at("nectar_reward"), 0.01f);
  EXPECT_EQ(spec.default_parameters.at("collision_reward"), -0.5f);
}

TEST(HummingbirdTest, Conforms) {
  register_builtin_envs();
  ConformanceOptions opts;
  opts.num_envs = 2;
  opts.steps = 50;  // two episodes and some
  for (const Parameters& p :
       {Parameters{{"episode_length", 60.f}},
        Parameters{{"episode_length", 61.f}, {"num_obstacles", 8.f}, {"nectar_capacity", 5.f}}}) {
    const auto violations = check_env_conformance("Hummingbird", p, opts);
    EXPECT_TRUE(violations.empty()) << joined(violations);
  }
}

// a parameter out of its range is an error that names it, not a silent clamp (the shared
// DroneTask checks cover Hummingbird, TargetDrone and Eye alike)
TEST(HummingbirdTest, BadParametersAreNamed) {
  for (const auto& [name, value] : std::vector<std::pair<std::string, float>>{
           {"decision_period", 0.f}, {"episode_length", 2.5f}, {"arena_half_size", 100.f},
           {"nectar_radius", -1.f}, {"num_nectar", 40.f}, {"drone_max_speed", NAN}}) {
    Hummingbird env;
    env.set_parameters({{name, value}});
    SingleEnvHarness harness(env);
    try {
      harness.reset();
      ADD_FAILURE() << name << " = " << value << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("Hummingbird: parameter " + name), std::string::npos)
          << e.what();
    }
  }
}

TEST(HummingbirdTest, NectarPaysPerFrameInside) {
  Hummingbird env;
  env.seed(3);
  SingleEnvHarness h(env);
  h.reset();
  EXPECT_EQ(h.observation(0)[15], 0.f);  // spawned outside nectar
  const btVector3 c = env.nectar().at(0).centre;
  drone::DroneTask::place(env.drone(), c);
  act(h, 0, 0, 0, 0);
  for (int k = 0; k < 5; ++k) {
    h.step();
    EXPECT_FLOAT_EQ(h.reward(), 3 * 0.01f);
    EXPECT_EQ(h.observation(0)[15], 1.f);
  }
  EXPECT_EQ(env.episode_metrics().at("nectar_frames"), 15.f);
  EXPECT_EQ(env.episode_metrics().at("collisions"), 0.f);
}

TEST(HummingbirdTest, NectarCapacityEmptiesASphere) {
  Hummingbird env;
  env.set_parameters({{"nectar_capacity", 4.f}, {"num_nectar", 1.f}});
  SingleEnvHarness h(env);
  h.reset();
  drone::DroneTask::place(env.drone(), env.nectar().at(0).centre);
  act(h, 0, 0, 0, 0);
  h.step();
  EXPECT_FLOAT_EQ(h.reward(), 3 * 0.01f);
  h.step();
  EXPECT_FLOAT_EQ(h.reward(), 0.01f);  // the fourth frame empties it
  EXPECT_EQ(h.observation(0)[15], 0.f);
  h.step();
  EXPECT_EQ(h.reward(), 0.f);
}

TEST(HummingbirdTest, OneWallContactIsOneCollision) {
  Hummingbird env;
  env.set_parameters({{"num_obstacles", 0.f}, {"nectar_reward", 0.f}});
  SingleEnvHarness h(env);
  h.reset();
  // 2 m from the +x wall (inner face x = 12), facing it (yaw pi/2: forward = +x)
  drone::DroneTask::place(env.drone(), btVector3(10, 3, 0), static_cast<float>(M_PI / 2));
  act(h, 1, 0, 0, 0);
  double total = 0;
  int penalised = 0;
  for (int k = 0; k < 60; ++k) {  // 3.6 s: reach the wall and keep pushing
    h.step();
    total += h.reward();
    penalised += h.reward() != 0.f;
  }
  EXPECT_GT(env.drone().position().x(), 12 - 0.35 - 0.05);  // at the wall
  EXPECT_FLOAT_EQ(static_cast<float>(total), -0.5f);
  EXPECT_EQ(penalised, 1);
  EXPECT_EQ(env.episode_metrics().at("collisions"), 1.f);
}

TEST(HummingbirdTest, TruncatesAtEpisodeLength) {
  Hummingbird env;
  env.set_parameters({{"episode_length", 10.f}});
  SingleEnvHarness h(env);
  h.reset();
  act(h, 0, 0, 0, 0);
  for (int k = 0; k < 3; ++k) {
    h.step();
    EXPECT_EQ(h.step_type(), StepType::kMid);
  }
  h.step();  // frame 10 of 10: a short last decision
  EXPECT_EQ(h.step_type(), StepType::kLast);
  EXPECT_EQ(h.terminated(), 0);
  EXPECT_EQ(env.task().frame(), 10);
  EXPECT_EQ(h.observation(0)[11], 1.f);
}

// observations of `steps` decisions of random actions from seed `seed`
std::vector<float> rollout(uint64_t seed, int steps) {
  Hummingbird env;
  env.seed(seed);
  SingleEnvHarness h(env);
  h.reset();
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<float> out;
  for (int k = 0; k < steps; ++k) {
    act(h, u(rng), u(rng), u(rng), u(rng));
    h.step();
    for (int o = 0; o < 2; ++o)
      out.insert(out.end(), h.buffers().observations[o].begin(), h.buffers().observations[o].end());
    out.push_back(h.reward());
  }
  return out;
}

TEST(HummingbirdTest, SameSeedSameTrajectory) {
  const std::vector<float> a = rollout(7, 100), b = rollout(7, 100), c = rollout(8, 100);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
  EXPECT_NE(a, c);
}

// nectar frames of one episode flown by the pilot towards the nearest nectar, or standing still
float nectar_frames(uint64_t seed, bool fly) {
  Hummingbird env;
  env.set_parameters({{"episode_length", 600.f}, {"num_obstacles", 0.f}});
  env.seed(seed);
  SingleEnvHarness h(env);
  h.reset();
  const drone::DroneTaskSettings s = drone::read_drone_task_settings(env);
  while (needs_action(h.step_type())) {
    const float* obs = h.observation(0);
    const auto rel = drone::decode_relative(obs + 12, s);
    const auto a = fly ? drone::pilot_actions(obs, rel[0], rel[1], rel[2], s.drone.max_speed)
                       : std::array<float, 4>{0, 0, 0, 0};
    act(h, a[0], a[1], a[2], a[3]);
    h.step();
  }
  return env.episode_metrics().at("nectar_frames");
}

TEST(HummingbirdTest, PilotFindsNectarStillDroneDoesNot) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const float flown = nectar_frames(seed, true), still = nectar_frames(seed, false);
    EXPECT_GT(flown, 400.f) << "seed " << seed;  // most of the 600 frames
    EXPECT_EQ(still, 0.f) << "seed " << seed;
  }
}

}  // namespace
}  // namespace rlt
