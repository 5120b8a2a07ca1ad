#include <cmath>
#include <fstream>
#include <iostream>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "apps/recording_json.h"
#include "rl/core/json.h"
#include "rl/core/sample_stats.h"
#include "rl/curriculum/environment_parameter_manager.h"
#include "rl/env_api/env_registry.h"
#include "rl/trainer/evaluation.h"
#include "rl/trainer/saved_run.h"

namespace rlt {

const char* const kEvalHelp = R"(Usage:
  rlt eval RUN_DIR [options]
  rlt eval --env ID [options]

Plays episodes and reports, per behavior, the mean and standard deviation of the agents' episode
returns and the mean of every episode metric of the env (e.g. success_rate, tag_rate, fort_rate).
With RUN_DIR, every behavior plays the newest checkpoint of that training run (or the one
--checkpoint names), in the run's env with its parameters at the curriculum lesson the
checkpoint had reached. With --env, every behavior acts uniformly at random unless --policy says
otherwise.

Options:
  --env ID                  the registered env to play (see `rlt envs`) instead of a run's
  --policy BEHAVIOR=WHO     who plays BEHAVIOR (repeat for several behaviors); WHO is one of
                              random    uniform random actions that obey the masks
                              still     continuous actions 0, the first allowed discrete option
                              scripted  the env's hand-written policy (e.g. HideAndSeek's hider
                                        that locks a prop in an opening, seeker that chases)
                              RUN_DIR   that behavior's network from a training run's newest
                                        checkpoint
  --checkpoint N            with RUN_DIR: play checkpoints/checkpoint-N.pt, one of those the
                            run's training_status.json lists (with their steps), instead of the
                            newest
  --param NAME=VALUE        set an env parameter (repeat), over the run's (e.g. --param level=2)
  --record FILE             write every counted episode, frame by frame, as JSON for replay
                            viewers (envs that record: the drone envs; format in
                            docs/recording_format.md)
  --episodes N              episodes to play (default 10)
  --deterministic           networks act with each distribution's mode instead of sampling
  --json                    one JSON object per line per behavior: behavior, policy, episodes,
                            mean_return, std_return, mean_length, then the env's episode metrics
  --seed S                  base seed of the evaluation envs (default 1000000)
  --num-envs N              environment instances (default: min(episodes, 8))
)";

namespace {

// the network of behavior `name` in the run at `run_dir`, as a policy for `spec`
std::unique_ptr<BehaviorPolicy> run_policy(const std::string& run_dir, const BehaviorSpec& spec,
                                           bool deterministic, uint64_t seed) {
  SavedRun run = load_saved_run(run_dir);
  for (auto& t : run.trainers) {
    if (t->behavior() != spec.name) continue;
    int obs = 0;
    for (const auto& o : spec.observations) obs += o.size();
    if (t->obs_size() != obs)
      throw UsageError("--policy " + spec.name + "=" + run_dir + ": the run's " + spec.name +
                       " observes " + std::to_string(t->obs_size()) + " floats, the env gives " +
                       std::to_string(obs));
    return std::make_unique<NetworkPolicy>(t->fast_actor(), t->obs_size(), deterministic, seed);
  }
  throw UsageError("--policy " + spec.name + "=" + run_dir + ": the run has no behavior " +
                   spec.name);
}

}  // namespace

int run_eval(const std::vector<std::string>& args) {
  CommandLine cl(args, {"--deterministic", "--json"},
                 {"--episodes", "--seed", "--num-envs", "--env", "--policy", "--param", "--record",
                  "--checkpoint"});
  const bool from_run = cl.positional().size() == 1;
  if (cl.positional().size() > 1) throw UsageError("expected at most one RUN_DIR");
  if (from_run == cl.has("--env")) throw UsageError("expected either RUN_DIR or --env ID");
  const int episodes = int(cl.integer("--episodes", 10, 1));
  const uint64_t seed = uint64_t(cl.integer("--seed", 1000000, 0));
  const int num_envs = int(cl.integer("--num-envs", std::min(episodes, 8), 1));
  const bool deterministic = cl.has("--deterministic");
  const Parameters overrides = cl.parameters();
  const int64_t checkpoint = cl.integer("--checkpoint", 0, 1);
  if (cl.has("--checkpoint") && !from_run)
    throw UsageError("--checkpoint N picks a checkpoint of RUN_DIR; with --env there is none");

  std::unique_ptr<SavedRun> run;
  std::string env_id = cl.value("--env");
  Parameters construction;
  if (from_run) {
    run = std::make_unique<SavedRun>(load_saved_run(cl.positional()[0], checkpoint));
    env_id = run->config.env_settings.env_id;
    construction = run->config.env_settings.params;
  }
  for (const auto& [k, v] : overrides) construction[k] = v;
  std::unique_ptr<VectorEnv> env;
  try {
    env = std::make_unique<VectorEnv>(env_id, num_envs, seed, construction, 1);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const EnvSpec& spec = env->spec();
  if (run) {
    // the run's parameters at the lessons it had reached, drawn for each instance
    std::mt19937_64 parameter_rng(seed);
    for (int i = 0; i < num_envs; ++i) env->set_parameters(i, run->parameters.sample(parameter_rng));
  }
  env->set_parameters(overrides);

  // who plays each behavior
  const int nb = env->num_behaviors();
  std::vector<std::unique_ptr<BehaviorPolicy>> policies(nb);
  std::vector<std::string> who(nb, run ? "run" : "random");
  for (const auto& p : cl.values("--policy")) {
    const auto eq = p.find('=');
    if (eq == std::string::npos) throw UsageError("--policy expects BEHAVIOR=WHO, got '" + p + "'");
    const int b = spec.behavior_index(p.substr(0, eq));
    if (b < 0) {
      std::string names;
      for (const auto& be : spec.behaviors) names += (names.empty() ? "" : ", ") + be.name;
      throw UsageError("--policy " + p + ": env " + spec.name + " has no behavior '" +
                       p.substr(0, eq) + "' (it has " + names + ")");
    }
    who[b] = p.substr(eq + 1);
    if (who[b].empty()) throw UsageError("--policy " + p + ": say who plays " + spec.behaviors[b].name);
  }
  for (int b = 0; b < nb; ++b) {
    const uint64_t policy_seed = seed * 31 + b;
    if (who[b] == "random") {
      policies[b] = std::make_unique<RandomPolicy>(policy_seed);
    } else if (who[b] == "still") {
      policies[b] = std::make_unique<StillPolicy>();
    } else if (who[b] == "scripted") {
      policies[b] = std::make_unique<ScriptedPolicy>(*env, b);
    } else if (who[b] == "run") {
      auto& t = *run->trainers.at(b);
      policies[b] = std::make_unique<NetworkPolicy>(t.fast_actor(), t.obs_size(), deterministic,
                                                    policy_seed);
    } else {
      policies[b] = run_policy(who[b], spec.behaviors[b], deterministic, policy_seed);
    }
  }
  std::ofstream record;
  const std::string record_path = cl.value("--record");
  if (!record_path.empty()) {
    record.open(record_path);
    if (!record) throw UsageError("--record " + record_path + ": cannot open it for writing");
    env->set_recording(true);
  }

  Evaluation ev;
  try {
    ev = evaluate(*env, policies, episodes);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (record.is_open()) {
    if (ev.recordings.empty())
      std::cerr << "rlt eval: env " << spec.name << " does not record episodes; " << record_path
                << " lists none\n";
    write_recordings_json(record, ev.recordings);
    record.close();
    if (!record) throw std::runtime_error("--record " + record_path + ": writing failed");
  }

  for (size_t b = 0; b < ev.behaviors.size(); ++b) {
    const auto& be = ev.behaviors[b];
    const std::string& policy = who[b] == "run" ? cl.positional()[0] : who[b];
    const double mean = mean_of(be.returns), sd = std_of(be.returns), len = mean_of(be.lengths);
    if (cl.has("--json")) {
      std::cout << "{\"behavior\":" << json_string(be.behavior) << ",\"policy\":" << json_string(policy)
                << ",\"episodes\":" << ev.episodes << ",\"agent_episodes\":" << be.returns.size()
                << ",\"mean_return\":" << json_number(mean) << ",\"std_return\":" << json_number(sd)
                << ",\"mean_length\":" << json_number(len);
      for (const auto& [k, v] : ev.metrics) std::cout << "," << json_string(k) << ":" << json_number(v);
      std::cout << "}" << std::endl;
    } else {
      std::cout << be.behavior << " (" << policy << "): " << ev.episodes << " episodes, mean return "
                << mean << " +- " << sd << ", mean length " << len;
      for (const auto& [k, v] : ev.metrics) std::cout << ", " << k << " " << v;
      std::cout << std::endl;
    }
  }
  return 0;
}

}  // namespace rlt
