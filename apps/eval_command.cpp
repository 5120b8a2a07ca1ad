#include <cmath>
#include <iostream>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "rl/core/json.h"
#include "rl/core/sample_stats.h"
#include "rl/curriculum/environment_parameter_manager.h"
#include "rl/trainer/evaluation.h"
#include "rl/trainer/saved_run.h"

namespace rlt {

const char* const kEvalHelp = R"(Usage: rlt eval RUN_DIR [options]

Plays episodes with the newest checkpoint of a training run and reports, per behavior, the mean and
standard deviation of the agents' episode returns and the mean of every episode metric of the env
(e.g. success_rate, tag_rate). Environment parameters are those of the run at the curriculum
lesson its checkpoint had reached.

Options:
  --episodes N       episodes to play (default 10)
  --deterministic    act with each distribution's mode instead of sampling
  --json             one JSON object per line per behavior: behavior, episodes, mean_return,
                     std_return, mean_length, then the env's episode metrics
  --seed S           base seed of the evaluation envs (default 1000000)
  --num-envs N       environment instances (default: min(episodes, 8))
)";

int run_eval(const std::vector<std::string>& args) {
  CommandLine cl(args, {"--deterministic", "--json"}, {"--episodes", "--seed", "--num-envs"});
  if (cl.positional().size() != 1) throw UsageError("expected one RUN_DIR");
  const int episodes = int(cl.integer("--episodes", 10, 1));
  const uint64_t seed = uint64_t(cl.integer("--seed", 1000000, 0));
  const int num_envs = int(cl.integer("--num-envs", std::min(episodes, 8), 1));
  const bool deterministic = cl.has("--deterministic");
  SavedRun run = load_saved_run(cl.positional()[0]);
  const auto& es = run.config.env_settings;
  VectorEnv env(es.env_id, num_envs, seed, es.params, 1);
  // the run's parameters at the lessons it had reached, drawn for each instance
  std::mt19937_64 parameter_rng(seed);
  for (int i = 0; i < num_envs; ++i) env.set_parameters(i, run.parameters.sample(parameter_rng));
  std::vector<std::unique_ptr<BehaviorPolicy>> policies;
  for (size_t b = 0; b < run.trainers.size(); ++b) {
    auto& t = *run.trainers[b];
    policies.push_back(
        std::make_unique<NetworkPolicy>(t.fast_actor(), t.obs_size(), deterministic, seed * 31 + b));
  }
  Evaluation ev = evaluate(env, policies, episodes);
  for (const auto& be : ev.behaviors) {
    const double mean = mean_of(be.returns), sd = std_of(be.returns), len = mean_of(be.lengths);
    if (cl.has("--json")) {
      std::cout << "{\"behavior\":" << json_string(be.behavior) << ",\"episodes\":" << ev.episodes
                << ",\"agent_episodes\":" << be.returns.size() << ",\"mean_return\":" << json_number(mean)
                << ",\"std_return\":" << json_number(sd) << ",\"mean_length\":" << json_number(len);
      for (const auto& [k, v] : ev.metrics) std::cout << "," << json_string(k) << ":" << json_number(v);
      std::cout << "}" << std::endl;
    } else {
      std::cout << be.behavior << ": " << ev.episodes << " episodes, mean return " << mean << " +- " << sd
                << ", mean length " << len;
      for (const auto& [k, v] : ev.metrics) std::cout << ", " << k << " " << v;
      std::cout << std::endl;
    }
  }
  return 0;
}

}  // namespace rlt
