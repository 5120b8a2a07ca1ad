// PPO learns the shipped configurations (fixed seeds, success thresholds), and a negative control
// with learning rate 0 stays below each threshold. Label: learning.
#include <gtest/gtest.h>

#include <deque>
#include <sstream>

#include "env/register_builtin_envs.h"
#include "rl/config/config_parser.h"
#include "rl/trainer/training_run.h"

namespace rlt {
namespace {

struct LearningCase {
  const char* config;
  const char* behavior;
  int64_t max_steps;
  float threshold;  // mean return of 20 consecutive episodes to reach within max_steps
};

// trains `c` with `seed` (and learning rate 0 when `frozen`) and returns the best mean return of 20
// consecutive finished episodes seen within max_steps
double train_and_score(const LearningCase& c, int64_t seed, bool frozen) {
  register_builtin_envs();
  RunConfig config = load_run_config(c.config);
  if (frozen) config.behaviors.at(c.behavior).hyperparameters.learning_rate = 0.f;
  TrainOptions opt;
  opt.write_results = false;
  opt.progress = false;
  opt.seed = seed;
  opt.max_steps = c.max_steps;
  std::ostringstream log;
  opt.log = &log;
  std::deque<float> last20;
  double best = -1e30, sum = 0;
  int64_t best_step = 0;
  opt.on_episode = [&](int, int64_t step, float r) {
    last20.push_back(r);
    sum += r;
    if (last20.size() > 20) {
      sum -= last20.front();
      last20.pop_front();
    }
    if (last20.size() == 20 && sum / 20 > best) {
      best = sum / 20;
      best_step = step;
    }
  };
  TrainingRun run(config, opt);
  run.train();
  std::cout << c.config << " seed " << seed << (frozen ? " (learning rate 0)" : "")
            << ": best mean return of 20 consecutive episodes " << best << " (at step " << best_step
            << " of " << c.max_steps << ")\n";
  return best;
}

const LearningCase kCartPole{"configs/cartpole_ppo.yaml", "CartPole", 300000, 475.f};
const LearningCase kPendulum{"configs/pendulum_ppo.yaml", "Pendulum", 300000, -250.f};
const LearningCase kHybrid{"configs/hybrid_reach_ppo.yaml", "HybridReach", 60000, 9.0f};
const LearningCase kMasked{"configs/masked_choice_ppo.yaml", "MaskedChoice", 60000, 9.5f};

TEST(PpoLearning, CartPoleWithCleanRlSettingsReaches475InThreeSeeds) {
  for (int64_t seed : {1, 2, 3}) EXPECT_GE(train_and_score(kCartPole, seed, false), kCartPole.threshold);
}

TEST(PpoLearning, PendulumReachesMinus250) {
  EXPECT_GE(train_and_score(kPendulum, 1, false), kPendulum.threshold);
}

TEST(PpoLearning, HybridActionsAreSolved) {
  EXPECT_GE(train_and_score(kHybrid, 1, false), kHybrid.threshold);
}

TEST(PpoLearning, MaskedDiscreteActionsAreSolved) {
  EXPECT_GE(train_and_score(kMasked, 1, false), kMasked.threshold);
}

// negative controls: the same runs with learning rate 0 stay below every threshold
TEST(PpoLearning, LearningRateZeroLearnsNothing) {
  EXPECT_LT(train_and_score(kCartPole, 1, true), kCartPole.threshold);
  EXPECT_LT(train_and_score(kPendulum, 1, true), kPendulum.threshold);
  EXPECT_LT(train_and_score(kHybrid, 1, true), kHybrid.threshold);
  EXPECT_LT(train_and_score(kMasked, 1, true), kMasked.threshold);
}

}  // namespace
}  // namespace rlt
