#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <thread>
#include <sstream>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "rl/config/config_parser.h"
#include "rl/core/json.h"
#include "rl/trainer/behavior_policy.h"
#include "rl/trainer/training_run.h"

namespace rlt {

const char* const kBenchHelp = R"(Usage:
  rlt bench train CONFIG [--steps N] [--num-envs N] [--threads T] [--seed S] [--json]
      trains CONFIG for N agent steps per behavior (default 100000) without writing a run folder
      and reports env_steps_per_s and agent_steps_per_s, end to end (acting, env, learning).
  rlt bench env ID [--frames N] [--num-envs N] [--threads T] [--param NAME=VALUE]... [--json]
      runs N frames (default 100000) with uniform random actions and reports frames_per_s and
      env_steps_per_s. A frame is a physics frame in the drone envs (a step is decision_period
      frames: 3 by default), an env step elsewhere. --threads defaults to the number of cores.
)";

namespace {

int bench_train(const CommandLine& cl) {
  if (cl.positional().size() != 2) throw UsageError("expected: bench train CONFIG");
  TrainOptions opt;
  opt.write_results = false;
  opt.progress = false;
  opt.max_steps = cl.integer("--steps", 100000, 1);
  opt.num_envs = int(cl.integer("--num-envs", 0, 1));
  opt.threads = int(cl.integer("--threads", 0, 1));
  opt.seed = cl.integer("--seed", -1, 0);
  std::ostringstream quiet;
  opt.log = &quiet;
  TrainingRun run(load_run_config(cl.positional()[1]), opt);
  TrainResult r = run.train();
  const double env_rate = r.env_steps / r.seconds, agent_rate = r.agent_steps / r.seconds;
  if (cl.has("--json")) {
    std::cout << "{\"env_steps_per_s\":" << json_number(env_rate) << ",\"agent_steps_per_s\":"
              << json_number(agent_rate) << ",\"seconds\":" << json_number(r.seconds)
              << ",\"agent_steps\":" << r.agent_steps << ",\"acting_s\":" << json_number(r.acting_seconds)
              << ",\"env_s\":" << json_number(r.env_seconds)
              << ",\"trajectory_s\":" << json_number(r.trajectory_seconds)
              << ",\"update_s\":" << json_number(r.update_seconds) << "}" << std::endl;
  } else {
    std::cout << r.agent_steps << " agent steps in " << r.seconds << " s: " << env_rate
              << " env steps/s, " << agent_rate << " agent steps/s (acting " << r.acting_seconds
              << " s, envs " << r.env_seconds << " s, trajectories " << r.trajectory_seconds
              << " s, updates " << r.update_seconds << " s)" << std::endl;
  }
  return 0;
}

int bench_env(const CommandLine& cl) {
  if (cl.positional().size() != 2) throw UsageError("expected: bench env ID");
  const Parameters params = cl.parameters();
  const int64_t frames = cl.integer("--frames", 100000, 1);
  const int num_envs = int(cl.integer("--num-envs", 1, 1));
  // all cores by default, as training steps its envs
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  const int threads = int(cl.integer("--threads", std::min(cores, num_envs), 1));
  std::unique_ptr<VectorEnv> made;
  try {
    made = std::make_unique<VectorEnv>(cl.positional()[1], num_envs, 0, params, threads);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  VectorEnv& env = *made;
  env.set_parameters(params);
  std::vector<RandomPolicy> policies;
  for (int b = 0; b < env.num_behaviors(); ++b) policies.emplace_back(b + 1);
  env.reset();
  // physics frames when the env counts them (drone envs: several per step), else env steps
  const uint64_t frames0 = env.physics_frames();
  const auto start = std::chrono::steady_clock::now();
  int64_t steps = 0, counted = 0;
  while (counted < frames) {
    for (int b = 0; b < env.num_behaviors(); ++b) policies[b].act(env.buffers(b));
    env.step();
    steps += num_envs;
    const uint64_t physics = env.physics_frames() - frames0;
    counted = physics > 0 ? int64_t(physics) : steps;
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (cl.has("--json"))
    std::cout << "{\"frames_per_s\":" << json_number(counted / s) << ",\"env_steps_per_s\":"
              << json_number(steps / s) << ",\"frames\":" << counted << ",\"seconds\":"
              << json_number(s) << "}\n";
  else
    std::cout << counted << " frames (" << steps << " env steps) in " << s << " s: " << counted / s
              << " frames/s, " << steps / s << " env steps/s\n";
  return 0;
}

}  // namespace

int run_bench(const std::vector<std::string>& args) {
  CommandLine cl(args, {"--json"}, {"--steps", "--frames", "--num-envs", "--threads", "--seed", "--param"});
  if (cl.positional().empty()) throw UsageError("expected 'train' or 'env'");
  if (cl.positional()[0] == "train") return bench_train(cl);
  if (cl.positional()[0] == "env") return bench_env(cl);
  throw UsageError("unknown benchmark '" + cl.positional()[0] + "'");
}

}  // namespace rlt
