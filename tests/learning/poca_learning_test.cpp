// MA-POCA solves the Escape game (one agent must sacrifice itself so that another can carry the
// key out) within 150k agent steps, and independent PPO learners with the same budget and settings
// do measurably worse: they learn to avoid the sacrifice. Label: learning.
#include <gtest/gtest.h>

#include <sstream>

#include "env/register_builtin_envs.h"
#include "rl/config/config_parser.h"
#include "rl/trainer/evaluation.h"
#include "rl/trainer/training_run.h"

namespace rlt {
namespace {

// trains `config_path` for `steps` and returns the success rate of 200 evaluation episodes
double train_and_evaluate(const std::string& config_path, int64_t steps) {
  register_builtin_envs();
  TrainOptions opt;
  opt.write_results = false;
  opt.progress = false;
  opt.max_steps = steps;
  std::ostringstream log;
  opt.log = &log;
  TrainingRun run(load_run_config(config_path), opt);
  run.train();
  VectorEnv env("Escape", 8, 424242);
  std::vector<std::unique_ptr<BehaviorPolicy>> policies;
  auto& t = run.trainer(0);
  policies.push_back(std::make_unique<NetworkPolicy>(t.fast_actor(), t.obs_size(), false, 7));
  Evaluation ev = evaluate(env, policies, 200);
  std::cout << config_path << " after " << steps << " steps: success " << ev.metrics.at("success_rate")
            << ", sacrificed " << ev.metrics.at("sacrificed") << "\n";
  return ev.metrics.at("success_rate");
}

TEST(PocaLearning, PocaSolvesEscapeAndIndependentPpoDoesWorse) {
  const double poca = train_and_evaluate("configs/escape_poca.yaml", 150000);
  const double ppo = train_and_evaluate("configs/escape_ppo.yaml", 150000);
  EXPECT_GE(poca, 0.9);
  EXPECT_LT(ppo, 0.5);
  EXPECT_GT(poca - ppo, 0.4);
}

}  // namespace
}  // namespace rlt
