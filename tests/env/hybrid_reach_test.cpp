// HybridReach: reward formula, oracle and random returns against the analytic values, episodes.
#include "env/toy/hybrid_reach.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

// Plays one episode; `policy(obs, &a, &choice)` picks the actions. Returns the episode return.
template <typename Policy>
double play_episode(HybridReach& env, SingleEnvHarness& h, Policy policy) {
  h.reset();
  double ret = 0;
  while (h.step_type() != StepType::kLast) {
    float a = 0;
    int choice = 0;
    policy(h.observation(), &a, &choice);
    h.set_continuous(0, a);
    h.set_discrete(0, choice);
    h.step();
    ret += h.reward();
  }
  return ret;
}

int observed_class(const float* obs) {
  for (int k = 0; k < 3; ++k)
    if (obs[1 + k] == 1.f) return k;
  return -1;
}

TEST(HybridReachTest, SpecIsHybrid) {
  HybridReach env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "HybridReach");
  EXPECT_EQ(spec.max_episode_steps, 10);
  const BehaviorSpec& b = spec.behaviors.at(0);
  EXPECT_EQ(b.observations.at(0).shape, std::vector<int>({4}));
  EXPECT_EQ(b.action.continuous_size, 1);
  EXPECT_EQ(b.action.discrete_branches, std::vector<int>({3}));
  EXPECT_TRUE(b.action.is_hybrid());
}

TEST(HybridReachTest, ObservationShowsTheTarget) {
  HybridReach env;
  SingleEnvHarness h(env);
  env.seed(4);
  h.reset();
  for (int t = 0; t < 10; ++t) {
    const float* obs = h.observation();
    EXPECT_EQ(obs[0], env.target_value());
    EXPECT_EQ(observed_class(obs), env.target_class());
    EXPECT_EQ(obs[1] + obs[2] + obs[3], 1.f);
    h.step();
  }
}

TEST(HybridReachTest, RewardIsHalfReachHalfClass) {
  HybridReach env;
  SingleEnvHarness h(env);
  env.seed(8);
  h.reset();
  for (int t = 0; t < 9; ++t) {
    const float target = env.target_value();
    const int cls = env.target_class();
    // off by 0.25 (towards 0, so no clipping), wrong class on odd steps
    const float a = target > 0 ? target - 0.25f : target + 0.25f;
    const bool right = t % 2 == 0;
    h.set_continuous(0, a);
    h.set_discrete(0, right ? cls : (cls + 1) % 3);
    h.step();
    EXPECT_NEAR(h.reward(), 0.5 * (1 - 0.25) + (right ? 0.5 : 0.0), 1e-6) << "step " << t;
  }
}

TEST(HybridReachTest, ContinuousActionIsClipped) {
  HybridReach env;
  SingleEnvHarness h(env);
  env.seed(2);
  h.reset();
  const float target = env.target_value();
  h.set_continuous(0, 7.f);
  h.set_discrete(0, (env.target_class() + 1) % 3);
  h.step();
  EXPECT_NEAR(h.reward(), 0.5 * (1 - (1 - target)), 1e-6);
}

TEST(HybridReachTest, OracleReturnsTen) {
  HybridReach env;
  SingleEnvHarness h(env);
  env.seed(1);
  for (int e = 0; e < 20; ++e) {
    const double ret = play_episode(env, h, [](const float* obs, float* a, int* choice) {
      *a = obs[0];
      *choice = observed_class(obs);
    });
    EXPECT_EQ(ret, 10.0);
    const EpisodeMetrics m = env.episode_metrics();
    EXPECT_EQ(m.at("class_accuracy"), 1.f);
    EXPECT_EQ(m.at("mean_abs_error"), 0.f);
  }
}

TEST(HybridReachTest, RandomPolicyReturnsTenThirds) {
  HybridReach env;
  SingleEnvHarness h(env);
  env.seed(1);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<float> action(-1.f, 1.f);
  std::uniform_int_distribution<int> option(0, 2);
  const int episodes = 4000;
  double total = 0;
  for (int e = 0; e < episodes; ++e)
    total += play_episode(env, h, [&](const float*, float* a, int* choice) {
      *a = action(rng);
      *choice = option(rng);
    });
  // analytic mean 10/3; the standard error over 4000 episodes is about 0.017
  EXPECT_NEAR(total / episodes, 10.0 / 3.0, 0.08);
}

TEST(HybridReachTest, TruncatesAfterTenSteps) {
  HybridReach env;
  SingleEnvHarness h(env);
  h.reset();
  for (int t = 1; t <= 10; ++t) {
    h.step();
    EXPECT_EQ(h.terminated(), 0);
    ASSERT_EQ(h.step_type(), t < 10 ? StepType::kMid : StepType::kLast);
  }
  h.step();
  EXPECT_EQ(h.step_type(), StepType::kAbsent);
}

TEST(HybridReachTest, RejectsAnInvalidChoice) {
  HybridReach env;
  SingleEnvHarness h(env);
  h.reset();
  h.set_discrete(0, 3);
  EXPECT_THROW(h.step(), std::invalid_argument);
}

TEST(HybridReachTest, SameSeedSameTargets) {
  auto targets = [](uint64_t seed) {
    HybridReach env;
    SingleEnvHarness h(env);
    env.seed(seed);
    h.reset();
    std::vector<float> out;
    for (int t = 0; t < 10; ++t) {
      out.insert(out.end(), h.observation(), h.observation() + 4);
      h.step();
    }
    return out;
  };
  EXPECT_EQ(targets(3), targets(3));
  EXPECT_NE(targets(3), targets(4));
}

}  // namespace
}  // namespace rlt
