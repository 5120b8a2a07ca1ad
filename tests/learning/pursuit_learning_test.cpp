// Pursuit with configs/pursuit_selfplay.yaml (MA-POCA seekers, PPO hiders, asymmetric self-play,
// curriculum): the trained seekers tag the trained hiders far more often than random seekers do.
// Label: learning.
#include <gtest/gtest.h>

#include <sstream>

#include "env/register_builtin_envs.h"
#include "rl/config/config_parser.h"
#include "rl/trainer/evaluation.h"
#include "rl/trainer/training_run.h"

namespace rlt {
namespace {

TEST(PursuitLearning, PocaSeekersTagFarMoreOftenThanRandomSeekers) {
  register_builtin_envs();
  TrainOptions opt;
  opt.write_results = false;
  opt.progress = false;
  std::ostringstream log;
  opt.log = &log;
  TrainingRun run(load_run_config("configs/pursuit_selfplay.yaml"), opt);
  run.train();
  const int seeker = run.trainer(0).behavior() == "Seeker" ? 0 : 1;
  const Parameters level = {{"level", float(run.parameters().lessons().at("level") + 1)}};
  auto tag_rate = [&](bool random_seekers) {
    VectorEnv env("Pursuit", 8, 99);
    env.set_parameters(level);
    std::vector<std::unique_ptr<BehaviorPolicy>> policies;
    for (int b = 0; b < 2; ++b) {
      auto& t = run.trainer(b);
      if (b == seeker && random_seekers)
        policies.push_back(std::make_unique<RandomPolicy>(5));
      else
        policies.push_back(std::make_unique<NetworkPolicy>(t.fast_actor(), t.obs_size(), false, 6 + b));
    }
    return evaluate(env, policies, 200).metrics.at("tag_rate");
  };
  const double trained = tag_rate(false), random = tag_rate(true);
  std::cout << "tag rate against the trained hiders at level " << level.at("level")
            << ": MA-POCA seekers " << trained << ", random seekers " << random << "\n"
            << log.str().substr(log.str().rfind("[Seeker]")) << "\n";
  // measured (seed 1, final lesson level 3): 0.93 against 0.005 with 1M steps per behavior; with
  // 500k the seekers tagged in 0.34 on a machine with OpenBLAS's Zen kernels and in 0.23 on one
  // with its Haswell kernels, too near the bar, so the config trains 1M
  EXPECT_GE(trained, 0.25);
  EXPECT_LE(random, 0.1);
  EXPECT_GE(trained, 5 * random);
}

}  // namespace
}  // namespace rlt
