// MaskedChoice: masks, penalties for forbidden options, returns against the analytic values.
#include "env/toy/masked_choice.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

constexpr int kOffsets[2] = {0, 4};  // first mask index of each branch

// option of `branch` chosen by `pick(allowed options, all options)`
template <typename Pick>
double play_episode(SingleEnvHarness& h, Pick pick) {
  h.reset();
  double ret = 0;
  while (h.step_type() != StepType::kLast) {
    for (int b = 0; b < 2; ++b) h.set_discrete(b, pick(b, h.action_mask() + kOffsets[b]));
    h.step();
    ret += h.reward();
  }
  return ret;
}

// index of the one-hot bonus option of `branch` in the observation
int observed_bonus(const float* obs, int branch) {
  const int n = MaskedChoice::kOptions[branch];
  for (int k = 0; k < n; ++k)
    if (obs[MaskedChoice::kMaskSize + kOffsets[branch] + k] == 1.f) return k;
  return -1;
}

TEST(MaskedChoiceTest, SpecHasTwoMaskedBranches) {
  MaskedChoice env;
  const BehaviorSpec& b = env.spec().behaviors.at(0);
  EXPECT_EQ(env.spec().name, "MaskedChoice");
  EXPECT_EQ(env.spec().max_episode_steps, 10);
  EXPECT_EQ(b.action.discrete_branches, std::vector<int>({4, 3}));
  EXPECT_EQ(b.action.mask_size(), 7);
  EXPECT_EQ(b.observations.at(0).shape, std::vector<int>({14}));
}

TEST(MaskedChoiceTest, MasksAllowSomethingInEveryBranchAndMatchTheObservation) {
  MaskedChoice env;
  SingleEnvHarness h(env);
  env.seed(5);
  std::vector<int> allowed_count(7, 0);
  int decisions = 0;
  for (int e = 0; e < 300; ++e) {
    h.reset();
    while (h.step_type() != StepType::kLast) {
      const uint8_t* mask = h.action_mask();
      const float* obs = h.observation();
      for (int b = 0; b < 2; ++b) {
        int allowed = 0;
        for (int k = 0; k < MaskedChoice::kOptions[b]; ++k) {
          const int i = kOffsets[b] + k;
          EXPECT_EQ(obs[i], mask[i] ? 1.f : 0.f);
          allowed += mask[i];
          allowed_count[i] += mask[i];
        }
        EXPECT_GE(allowed, 1);
        const int bonus = observed_bonus(obs, b);
        ASSERT_GE(bonus, 0);
        EXPECT_EQ(bonus, env.bonus(b));
        EXPECT_EQ(mask[kOffsets[b] + bonus], 1) << "the bonus option is allowed";
      }
      ++decisions;
      h.step();
    }
  }
  // each option is allowed with probability 1/2 given a nonempty branch: 8/15 and 4/7
  for (int i = 0; i < 7; ++i)
    EXPECT_NEAR(double(allowed_count[i]) / decisions, i < 4 ? 8.0 / 15 : 4.0 / 7, 0.04) << i;
}

TEST(MaskedChoiceTest, ForbiddenOptionsCostOneAndAreCounted) {
  MaskedChoice env;
  SingleEnvHarness h(env);
  env.seed(12);
  int expected_forbidden = 0;
  h.reset();
  while (h.step_type() != StepType::kLast) {
    // first forbidden option of each branch when there is one, else the bonus
    float expected = 0.f;
    for (int b = 0; b < 2; ++b) {
      int pick = env.bonus(b);
      for (int k = 0; k < MaskedChoice::kOptions[b]; ++k)
        if (!h.action_mask()[kOffsets[b] + k]) {
          pick = k;
          break;
        }
      const bool forbidden = pick != env.bonus(b);
      expected += forbidden ? -1.f : 0.5f;
      expected_forbidden += forbidden;
      h.set_discrete(b, pick);
    }
    h.step();
    EXPECT_EQ(h.reward(), expected);
  }
  EXPECT_GT(expected_forbidden, 0);
  EXPECT_EQ(env.episode_metrics().at("forbidden_actions"), float(expected_forbidden));
}

TEST(MaskedChoiceTest, OracleReturnsTen) {
  MaskedChoice env;
  SingleEnvHarness h(env);
  env.seed(3);
  for (int e = 0; e < 20; ++e) {
    const double ret = play_episode(h, [&](int b, const uint8_t*) { return env.bonus(b); });
    EXPECT_EQ(ret, 10.0);
    EXPECT_EQ(env.episode_metrics().at("bonus_rate"), 1.f);
    EXPECT_EQ(env.episode_metrics().at("forbidden_actions"), 0.f);
  }
}

TEST(MaskedChoiceTest, RandomReturnsMatchTheAnalyticValues) {
  MaskedChoice env;
  SingleEnvHarness h(env);
  env.seed(21);
  std::mt19937_64 rng(77);
  const int episodes = 4000;
  // uniform among allowed options: 5 * (103/180 + 29/42) = 6.31
  double masked = 0;
  for (int e = 0; e < episodes; ++e)
    masked += play_episode(h, [&](int b, const uint8_t* mask) {
      std::vector<int> allowed;
      for (int k = 0; k < MaskedChoice::kOptions[b]; ++k)
        if (mask[k]) allowed.push_back(k);
      return allowed[std::uniform_int_distribution<size_t>(0, allowed.size() - 1)(rng)];
    });
  EXPECT_NEAR(masked / episodes, 5.0 * (103.0 / 180 + 29.0 / 42), 0.1);
  // uniform over all options: 10 * (-41/120 - 11/42) = -6.04
  double unmasked = 0;
  for (int e = 0; e < episodes; ++e)
    unmasked += play_episode(h, [&](int b, const uint8_t*) {
      return std::uniform_int_distribution<int>(0, MaskedChoice::kOptions[b] - 1)(rng);
    });
  EXPECT_NEAR(unmasked / episodes, 10.0 * (-41.0 / 120 - 11.0 / 42), 0.15);
}

TEST(MaskedChoiceTest, TruncatesAfterTenSteps) {
  MaskedChoice env;
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

TEST(MaskedChoiceTest, RejectsAnOutOfRangeOption) {
  MaskedChoice env;
  SingleEnvHarness h(env);
  h.reset();
  h.set_discrete(1, 3);
  EXPECT_THROW(h.step(), std::invalid_argument);
}

TEST(MaskedChoiceTest, SameSeedSameMasks) {
  auto masks = [](uint64_t seed) {
    MaskedChoice env;
    SingleEnvHarness h(env);
    env.seed(seed);
    h.reset();
    std::vector<uint8_t> out;
    for (int t = 0; t < 10; ++t) {
      out.insert(out.end(), h.action_mask(), h.action_mask() + 7);
      out.push_back(static_cast<uint8_t>(env.bonus(0) * 4 + env.bonus(1)));
      h.step();
    }
    return out;
  };
  EXPECT_EQ(masks(6), masks(6));
  EXPECT_NE(masks(6), masks(7));
}

}  // namespace
}  // namespace rlt
