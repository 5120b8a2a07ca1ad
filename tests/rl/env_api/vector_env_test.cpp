// VectorEnv: per-env seeds, auto-reset keeping final observations, thread-count independence,
// finished episodes with metrics. Runs the built-in envs.
#include "rl/env_api/vector_env.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "env/classic/cartpole.h"
#include "env/register_builtin_envs.h"
#include "rl/env_api/derived_seed.h"
#include "rl/env_api/env_registry.h"

namespace rlt {
namespace {

class VectorEnvTest : public ::testing::Test {
 protected:
  void SetUp() override { register_builtin_envs(); }
};

// Writes random actions that obey the masks into every row.
void random_actions(BehaviorBuffers& b, std::mt19937_64& rng) {
  const ActionSpec& a = b.spec.action;
  std::uniform_real_distribution<float> cont(-1.f, 1.f);
  for (int r = 0; r < b.rows; ++r) {
    for (int c = 0; c < a.continuous_size; ++c)
      b.continuous_actions[size_t(r) * a.continuous_size + c] = cont(rng);
    int offset = 0;
    for (int br = 0; br < a.num_branches(); ++br) {
      const int n = a.discrete_branches[br];
      int pick;
      do {
        pick = std::uniform_int_distribution<int>(0, n - 1)(rng);
      } while (!b.action_mask[size_t(r) * a.mask_size() + offset + pick]);
      b.discrete_actions[size_t(r) * a.num_branches() + br] = pick;
      offset += n;
    }
  }
}

template <typename T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool same_buffers(const BehaviorBuffers& a, const BehaviorBuffers& b) {
  for (size_t k = 0; k < a.observations.size(); ++k)
    if (!same_bytes(a.observations[k], b.observations[k])) return false;
  return same_bytes(a.reward, b.reward) && same_bytes(a.group_reward, b.group_reward) &&
         same_bytes(a.agent_id, b.agent_id) && same_bytes(a.group_id, b.group_id) &&
         same_bytes(a.step_type, b.step_type) && same_bytes(a.terminated, b.terminated) &&
         same_bytes(a.action_mask, b.action_mask);
}

TEST_F(VectorEnvTest, EnvIBehavesLikeAStandaloneEnvWithItsDerivedSeed) {
  const uint64_t base = 100;
  const int n = 3;
  VectorEnv venv("CartPole", n, base);
  venv.reset();

  // standalone copies driven exactly as the vector env drives its instances
  std::vector<std::unique_ptr<Env>> solo;
  std::vector<BehaviorBuffers> solo_buffers;
  solo_buffers.reserve(n);
  std::vector<StepView> solo_views;
  for (int i = 0; i < n; ++i) {
    solo.push_back(EnvRegistry::instance().make("CartPole"));
    solo[i]->seed(derived_seed(base, i));
    solo_buffers.emplace_back(solo[i]->spec().behaviors[0], 1);
    solo_views.push_back({BehaviorView(&solo_buffers[i], 0)});
    solo[i]->reset(solo_views[i]);
  }

  std::mt19937_64 rng(1);
  bool over[3] = {false, false, false};
  int resets_seen = 0;
  for (int t = 0; t < 300; ++t) {
    BehaviorBuffers& vb = venv.buffers(0);
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(std::memcmp(vb.observations[0].data() + 4 * i,
                            solo_buffers[i].observations[0].data(), 4 * sizeof(float)),
                0)
          << "env " << i << ", step " << t;
      ASSERT_EQ(vb.step_type[i], solo_buffers[i].step_type[0]);
      ASSERT_EQ(vb.reward[i], solo_buffers[i].reward[0]);
    }
    random_actions(vb, rng);
    for (int i = 0; i < n; ++i) {
      solo_buffers[i].discrete_actions[0] = vb.discrete_actions[i];
      solo_views[i][0].clear_step();
      if (over[i]) {
        solo_views[i][0].clear_agents();
        solo[i]->reset(solo_views[i]);
        ++resets_seen;
      } else {
        solo[i]->step(solo_views[i]);
      }
      over[i] = solo_buffers[i].step_type[0] == StepType::kLast;
    }
    venv.step();
  }
  EXPECT_GT(resets_seen, 3);  // random CartPole episodes are short: auto-resets were compared
}

TEST_F(VectorEnvTest, FinalObservationStaysOneStepThenAutoReset) {
  VectorEnv venv("CartPole", 2, 7);
  venv.reset();
  BehaviorBuffers& b = venv.buffers(0);
  // env 0 always pushes right: the pole falls within a few dozen steps; env 1 alternates
  int t = 0;
  while (b.step_type[0] != StepType::kLast) {
    ASSERT_LT(++t, 100);
    b.discrete_actions[0] = 1;
    b.discrete_actions[1] = t % 2;
    venv.step();
  }
  // the final step: reward, terminated, and the failing state in the buffers
  EXPECT_EQ(b.terminated[0], 1);
  EXPECT_EQ(b.reward[0], 1.f);
  const float* final_obs = b.observations[0].data();  // env 0: [4]
  EXPECT_TRUE(std::fabs(final_obs[0]) > 2.4f || std::fabs(final_obs[2]) > 0.2094f);
  const auto finished = venv.take_finished_episodes();
  ASSERT_EQ(finished.size(), 1u);
  EXPECT_EQ(finished[0].env_index, 0);

  // next step: env 0 starts over (its action is ignored), env 1 goes on
  b.discrete_actions[0] = 1;
  venv.step();
  EXPECT_EQ(b.step_type[0], StepType::kFirst);
  EXPECT_EQ(b.reward[0], 0.f);
  EXPECT_EQ(b.terminated[0], 0);
  for (int j = 0; j < 4; ++j) EXPECT_LE(std::fabs(b.observations[0][j]), 0.05f);
  EXPECT_EQ(b.step_type[1], StepType::kMid);
  EXPECT_TRUE(venv.take_finished_episodes().empty());
}

TEST_F(VectorEnvTest, OneAndTwoThreadsGiveIdenticalBuffers) {
  for (const char* name : {"CartPole", "Pendulum", "HybridReach", "MaskedChoice"}) {
    VectorEnv one(name, 5, 42, {}, 1);
    VectorEnv two(name, 5, 42, {}, 2);
    one.reset();
    two.reset();
    std::mt19937_64 rng_one(3), rng_two(3);
    for (int t = 0; t < 600; ++t) {
      ASSERT_TRUE(same_buffers(one.buffers(0), two.buffers(0))) << name << ", step " << t;
      random_actions(one.buffers(0), rng_one);
      random_actions(two.buffers(0), rng_two);
      one.step();
      two.step();
    }
    EXPECT_EQ(one.take_finished_episodes().size(), two.take_finished_episodes().size());
  }
}

TEST_F(VectorEnvTest, ReportsFinishedEpisodesWithMetricsInEnvOrder) {
  VectorEnv venv("HybridReach", 4, 0, {}, 2);
  venv.reset();
  for (int t = 0; t < 10; ++t) {
    EXPECT_TRUE(venv.take_finished_episodes().empty()) << "step " << t;
    venv.step();
  }
  // every HybridReach episode lasts 10 steps
  auto finished = venv.take_finished_episodes();
  ASSERT_EQ(finished.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(finished[i].env_index, i);
    EXPECT_EQ(finished[i].metrics.count("class_accuracy"), 1u);
    EXPECT_EQ(finished[i].metrics.count("mean_abs_error"), 1u);
  }
  EXPECT_TRUE(venv.take_finished_episodes().empty());
  // the reset step reports nothing; the next episode ends 10 steps later
  for (int t = 0; t < 10; ++t) venv.step();
  EXPECT_TRUE(venv.take_finished_episodes().empty());
  venv.step();
  EXPECT_EQ(venv.take_finished_episodes().size(), 4u);
}

TEST_F(VectorEnvTest, ResetAndReseedAreDeterministic) {
  VectorEnv venv("Pendulum", 3, 10);
  venv.reset();
  const auto first = venv.buffers(0).observations[0];
  for (int t = 0; t < 5; ++t) venv.step();
  venv.reset();  // reseeds every instance from base seed 10
  EXPECT_EQ(venv.buffers(0).observations[0], first);

  VectorEnv other("Pendulum", 3, 500);
  other.reset();
  venv.reseed_and_reset(500);
  EXPECT_EQ(venv.buffers(0).observations[0], other.buffers(0).observations[0]);
  EXPECT_NE(venv.buffers(0).observations[0], first);
}

// Instance seeds mixed from the base seed and the index: with base + i, seed 11's instance 0 would
// start where seed 10's instance 1 does.
TEST_F(VectorEnvTest, NeighbouringSeedsShareNoInstance) {
  const int n = 4;
  VectorEnv a("Pendulum", n, 10), b("Pendulum", n, 11);
  a.reset();
  b.reset();
  const size_t width = a.spec().behaviors[0].observations[0].size();
  auto row = [&](VectorEnv& v, int i) {
    const auto& o = v.buffers(0).observations[0];
    return std::vector<float>(o.begin() + i * width, o.begin() + (i + 1) * width);
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      EXPECT_NE(row(a, i), row(b, j)) << "seed 10 instance " << i << ", seed 11 instance " << j;
      if (i != j) EXPECT_NE(row(a, i), row(a, j)) << "seed 10 instances " << i << ", " << j;
    }
}

TEST_F(VectorEnvTest, ParametersReachTheEnvsAtTheirNextReset) {
  VectorEnv venv("Pendulum", 2, 0);
  venv.reset();
  EXPECT_THROW(venv.set_parameters({{"gravity", 1.f}}), std::invalid_argument);
  // with g = 0 and no torque, the speed stays at its start value
  venv.set_parameters(1, {{"g", 0.f}});
  venv.reset();
  BehaviorBuffers& b = venv.buffers(0);
  const float start_speed[2] = {b.observations[0][2], b.observations[0][5]};
  b.continuous_actions[0] = b.continuous_actions[1] = 0.f;
  venv.step();
  EXPECT_NE(b.observations[0][2], start_speed[0]);  // env 0 keeps g = 10
  EXPECT_EQ(b.observations[0][5], start_speed[1]);
}

// stagger: instance i plays i * span / n still steps, so the instances are spread over their
// episodes; the episodes it played into are not reported, the ones after them are
TEST_F(VectorEnvTest, StaggerSpreadsTheInstancesOverTheirEpisodes) {
  // 60 frames, a decision every 3: 20 steps per episode; vector [12] is frame / 60
  const Parameters p = {{"episode_frames", 60.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}};
  for (int span : {20, 50}) {
    VectorEnv env("HideAndSeek", 4, 7, p);
    env.reset();
    env.stagger(span);
    BehaviorBuffers& hiders = env.buffers(0);
    const int slots = hiders.spec.agent_slots;
    const int vector = hiders.spec.observations[0].size();
    std::vector<int> into(4);  // steps into the running episode
    for (int i = 0; i < 4; ++i) {
      const int r = i * slots;
      into[i] = (i * span / 4) % 20;
      EXPECT_NEAR(hiders.observations[0][size_t(r) * vector + 12], into[i] * 3 / 60.0f, 1e-6f)
          << "span " << span << ", instance " << i;
      EXPECT_EQ(hiders.step_type[r], into[i] == 0 ? StepType::kFirst : StepType::kMid);
      EXPECT_EQ(hiders.reward[r], 0.0f);  // the warm-up's rewards are nobody's
    }
    EXPECT_TRUE(env.take_finished_episodes().empty());
    // play on: every instance's first episode from here is partial unless it began here
    std::mt19937_64 rng(3);
    std::vector<int> reported(4, 0);
    for (int step = 0; step < 41; ++step) {
      for (int b = 0; b < env.num_behaviors(); ++b) random_actions(env.buffers(b), rng);
      env.step();
      for (const FinishedEpisode& f : env.take_finished_episodes()) ++reported[f.env_index];
    }
    // 41 steps: the episode running ends at step 20 - into (reported only when it began at the
    // stagger, into 0), then a reset step and 20 steps per whole episode
    for (int i = 0; i < 4; ++i) {
      const int first_end = 20 - into[i];
      const int after = (41 - first_end) / 21;
      EXPECT_EQ(reported[i], after + (into[i] == 0 ? 1 : 0))
          << "span " << span << ", instance " << i;
    }
  }
}

TEST_F(VectorEnvTest, RejectsBadConstruction) {
  EXPECT_THROW(VectorEnv("CartPole", 0, 1), std::invalid_argument);
  EXPECT_THROW(VectorEnv("NoSuchEnv", 2, 1), std::invalid_argument);
  EXPECT_THROW(VectorEnv("CartPole", 2, 1, {{"g", 1.f}}), std::invalid_argument);
}

}  // namespace
}  // namespace rlt
