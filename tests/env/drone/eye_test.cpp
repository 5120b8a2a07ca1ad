// Eye: spec, conformance, the shared view reward, reaching the target ends the episode for both
// with +1 group reward, one wall collision costs the drone -0.2 once, hitting the ally costs both
// -0.5 once, seeded determinism, and a scripted search (turn until one of the pair sees the
// target, then fly at it) that succeeds where still drones do not.
#include "env/drone/eye.h"

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

// the rows of the two drones in the harness
struct Pair {
  explicit Pair(Eye& env) : h(env), b(h.buffers(0)) { h.reset(); }
  void act(int slot, float forward, float strafe, float vertical, float yaw) {
    float* a = b.continuous_actions.data() + 4 * slot;
    a[0] = forward, a[1] = strafe, a[2] = vertical, a[3] = yaw;
  }
  const float* obs(int slot) const { return b.observations[0].data() + slot * 21; }
  SingleEnvHarness h;
  BehaviorBuffers& b;
};

// yaw that makes forward = (sin yaw, 0, cos yaw) point along (dx, dz)
float yaw_towards(double dx, double dz) { return static_cast<float>(std::atan2(dx, dz)); }

// unit horizontal direction from the target towards the arena's centre
btVector3 inward(const btVector3& c) {
  btVector3 d(-c.x(), 0, -c.z());
  return d.length() > 0.1 ? d.normalized() : btVector3(1, 0, 0);
}

TEST(EyeTest, Spec) {
  Eye env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "Eye");
  ASSERT_EQ(spec.behaviors.size(), 1u);
  const BehaviorSpec& b = spec.behaviors[0];
  EXPECT_EQ(b.name, "Eye");
  EXPECT_EQ(b.agent_slots, 2);
  EXPECT_EQ(b.action.continuous_size, 4);
  EXPECT_EQ(b.observations.at(0).size(), 21);
  EXPECT_EQ(b.observations.at(1).size(), 119);
  EXPECT_EQ(spec.default_parameters.at("arena_half_size"), 5.f);
  EXPECT_EQ(spec.default_parameters.at("view_reward"), 0.001f);
  EXPECT_EQ(spec.default_parameters.at("wall_reward"), -0.2f);
  EXPECT_EQ(spec.default_parameters.at("ally_reward"), -0.5f);
}

TEST(EyeTest, Conforms) {
  register_builtin_envs();
  ConformanceOptions opts;
  opts.num_envs = 2;
  opts.steps = 50;
  for (const Parameters& p :
       {Parameters{{"episode_length", 60.f}},
        Parameters{{"episode_length", 45.f}, {"arena_half_size", 2.5f}, {"spawn_distance", 1.f}}}) {
    const auto violations = check_env_conformance("Eye", p, opts);
    EXPECT_TRUE(violations.empty()) << joined(violations);
  }
}

TEST(EyeTest, TargetInViewPaysTheGroupAndIsShared) {
  Eye env;
  env.seed(5);
  Pair p(env);
  const btVector3 c = env.target().getWorldTransform().getOrigin();
  const btVector3 d = inward(c);
  drone::DroneTask::place(env.drone(0), c + 2 * d, yaw_towards(-d.x(), -d.z()));  // looks at it
  drone::DroneTask::place(env.drone(1), c + 3.5 * d, yaw_towards(d.x(), d.z()));  // looks away
  p.act(0, 0, 0, 0, 0);
  p.act(1, 0, 0, 0, 0);
  p.h.step();
  for (int s = 0; s < 2; ++s) {
    EXPECT_FLOAT_EQ(p.b.group_reward[s], 3 * 0.001f) << s;
    EXPECT_EQ(p.b.reward[s], 0.f) << s;
    EXPECT_EQ(p.b.step_type[s], StepType::kMid);
  }
  EXPECT_TRUE(env.seen_by(0));
  EXPECT_FALSE(env.seen_by(1));
  EXPECT_EQ(p.obs(0)[15], 1.f);
  EXPECT_EQ(p.obs(0)[16], 0.f);
  EXPECT_EQ(p.obs(1)[15], 0.f);
  EXPECT_EQ(p.obs(1)[16], 1.f);
  // the drone that does not see it still gets where it is: 3.5 m back along d
  const auto rel = drone::decode_relative(p.obs(1) + 12, drone::read_drone_task_settings(env));
  EXPECT_NEAR(rel[0], -3.5 * d.x(), 1e-3);
  EXPECT_NEAR(rel[2], -3.5 * d.z(), 1e-3);
  EXPECT_EQ(env.episode_metrics().at("seen_fraction"), 1.f);
}

TEST(EyeTest, ReachingTheTargetEndsTheEpisodeForBoth) {
  Eye env;
  env.seed(6);
  Pair p(env);
  const btVector3 c = env.target().getWorldTransform().getOrigin();
  const btVector3 d = inward(c);
  drone::DroneTask::place(env.drone(0), c + 1.5 * d, yaw_towards(-d.x(), -d.z()));
  drone::DroneTask::place(env.drone(1), c + 3.5 * d, yaw_towards(d.x(), d.z()));
  p.act(0, 1, 0, 0, 0);
  p.act(1, 0, 0, 0, 0);
  int steps = 0;
  while (p.b.step_type[0] != StepType::kLast && steps < 30) {
    p.h.step();
    ++steps;
  }
  EXPECT_LT(steps, 10);
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(p.b.step_type[s], StepType::kLast) << s;
    EXPECT_EQ(p.b.terminated[s], 1) << s;
    EXPECT_GE(p.b.group_reward[s], 1.f) << s;
    EXPECT_LE(p.b.group_reward[s], 1.f + 3 * 0.001f + 1e-6f) << s;
    EXPECT_EQ(p.b.reward[s], 0.f) << s;
  }
  EXPECT_EQ(env.episode_metrics().at("success"), 1.f);
  p.h.step();
  EXPECT_EQ(p.b.step_type[0], StepType::kAbsent);
  EXPECT_EQ(p.b.step_type[1], StepType::kAbsent);
}

TEST(EyeTest, HittingTheAllyCostsBothOnce) {
  Eye env;
  env.seed(7);
  Pair p(env);
  const btVector3 c = env.target().getWorldTransform().getOrigin();
  const btVector3 q = c + 3 * inward(c);
  drone::DroneTask::place(env.drone(0), q - btVector3(0, 0, 0.8f), 0.f);  // faces +z
  drone::DroneTask::place(env.drone(1), q + btVector3(0, 0, 0.8f), static_cast<float>(M_PI));
  p.act(0, 1, 0, 0, 0);
  p.act(1, 1, 0, 0, 0);
  double total[2] = {0, 0};
  for (int k = 0; k < 30; ++k) {
    p.h.step();
    for (int s = 0; s < 2; ++s) total[s] += p.b.reward[s];
  }
  EXPECT_FLOAT_EQ(static_cast<float>(total[0]), -0.5f);
  EXPECT_FLOAT_EQ(static_cast<float>(total[1]), -0.5f);
  EXPECT_EQ(env.episode_metrics().at("ally_collisions"), 1.f);
  EXPECT_EQ(env.episode_metrics().at("wall_collisions"), 0.f);
}

TEST(EyeTest, OneWallContactCostsThatDroneOnce) {
  Eye env;
  env.seed(8);
  Pair p(env);
  const btVector3 c = env.target().getWorldTransform().getOrigin();
  const float side = c.x() > 0 ? -1.f : 1.f;  // the wall away from the target
  drone::DroneTask::place(env.drone(0), btVector3(side * 3.5f, 2, 0),
                          yaw_towards(side, 0));  // faces that wall, 1.5 m away
  drone::DroneTask::place(env.drone(1), btVector3(side * 1.f, 2, 3), 0.f);
  p.act(0, 1, 0, 0, 0);
  p.act(1, 0, 0, 0, 0);
  double total[2] = {0, 0};
  for (int k = 0; k < 30; ++k) {
    p.h.step();
    for (int s = 0; s < 2; ++s) total[s] += p.b.reward[s];
  }
  EXPECT_GT(side * env.drone(0).position().x(), 5 - 0.35 - 0.05);
  EXPECT_FLOAT_EQ(static_cast<float>(total[0]), -0.2f);
  EXPECT_EQ(total[1], 0.0);
  EXPECT_EQ(env.episode_metrics().at("wall_collisions"), 1.f);
}

std::vector<float> rollout(uint64_t seed, int steps) {
  Eye env;
  env.seed(seed);
  Pair p(env);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<float> out;
  for (int k = 0; k < steps && needs_action(p.b.step_type[0]); ++k) {
    for (int s = 0; s < 2; ++s) p.act(s, u(rng), u(rng), u(rng), u(rng));
    p.h.step();
    for (int o = 0; o < 2; ++o)
      out.insert(out.end(), p.b.observations[o].begin(), p.b.observations[o].end());
    out.insert(out.end(), p.b.reward.begin(), p.b.reward.end());
    out.insert(out.end(), p.b.group_reward.begin(), p.b.group_reward.end());
  }
  return out;
}

TEST(EyeTest, SameSeedSameTrajectory) {
  const std::vector<float> a = rollout(7, 150), b = rollout(7, 150), c = rollout(8, 150);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
  EXPECT_NE(a, c);
}

// success of one episode: each drone turns in place until the pair sees the target, then flies at
// it facing it; or both stay still
float search(uint64_t seed, bool fly) {
  Eye env;
  env.seed(seed);
  Pair p(env);
  const drone::DroneTaskSettings s = drone::read_drone_task_settings(env);
  while (needs_action(p.b.step_type[0])) {
    for (int slot = 0; slot < 2; ++slot) {
      const float* obs = p.obs(slot);
      std::array<float, 4> a{0, 0, 0, 0};
      if (fly && (obs[15] > 0 || obs[16] > 0)) {
        const auto rel = drone::decode_relative(obs + 12, s);
        a = drone::pilot_actions(obs, rel[0], rel[1], rel[2], s.drone.max_speed, 3.f, 2.f, true);
      } else if (fly) {
        a = drone::pilot_actions(obs, 0, 0, 0, s.drone.max_speed);  // brake
        a[3] = 1.f;                                                 // and look around
      }
      p.act(slot, a[0], a[1], a[2], a[3]);
    }
    p.h.step();
  }
  return env.episode_metrics().at("success");
}

TEST(EyeTest, ScriptedSearchFindsTheTargetStillDronesDoNot) {
  int flown = 0, still = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    flown += search(seed, true) > 0;
    still += search(seed, false) > 0;
  }
  EXPECT_GE(flown, 9);
  EXPECT_EQ(still, 0);
}

}  // namespace
}  // namespace rlt
