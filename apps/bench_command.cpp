#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "apps/local_launcher.h"
#include "rl/config/config_parser.h"
#include "rl/core/blas_kernels.h"
#include "rl/core/compute_threads.h"
#include "rl/core/json.h"
#include "rl/distributed/gloo_communicator.h"
#include "rl/trainer/behavior_policy.h"
#include "rl/trainer/training_run.h"

namespace rlt {

const char* const kBenchHelp = R"(Usage:
  rlt bench train CONFIG [--steps N] [--num-envs N] [--threads T] [--seed S] [--nproc R] [--json]
      trains CONFIG for N agent steps per behavior (default 100000) without writing a run folder
      and reports env_steps_per_s and agent_steps_per_s, end to end (acting, env, learning),
      where the time went, and learner_gflops: the updates' matrix-product operations (counted
      from the layer shapes) per second of update time; behaviors gives each behavior's
      update_s and learner_gflops. --nproc R trains with R data-parallel
      ranks on this machine (as rlt train --nproc; the rates are of all ranks together, each with
      --num-envs instances); parameters gives each behavior's trained parameters, whose
      gradient (4 bytes each) is all-reduced once per minibatch.
  rlt bench env ID [--frames N] [--num-envs N] [--threads T] [--param NAME=VALUE]... [--json]
      runs N frames (default 100000) with uniform random actions and reports frames_per_s and
      env_steps_per_s. A frame is a physics frame in the drone envs (a step is decision_period
      frames: 3 by default), an env step elsewhere. --threads defaults to the number of cores.
  rlt bench gemm [--size N] [--threads T] [--json]
      the machine's matrix-product peak: N x N times N x N single-precision products (default
      2048) through LibTorch's BLAS, and the learner's first-layer shape (3072 x 943 times
      943 x 256), with T threads (default: all cores); reports gflops of each and the kernel
      family OpenBLAS runs (blas_core; see 'rlt --help' on OPENBLAS_CORETYPE).
)";

namespace {

int bench_train(const CommandLine& cl, const std::vector<std::string>& args) {
  if (cl.positional().size() != 2) throw UsageError("expected: bench train CONFIG");
  LaunchSettings launch = launch_settings_from_environment();
  const int nproc = int(cl.integer("--nproc", 1, 1));
  if (nproc > 1) {
    if (launch.distributed())
      throw UsageError("--nproc starts its own ranks, but WORLD_SIZE is set");
    return launch_local_ranks(nproc, rank_command("bench", args, nproc),
                              launch.timeout_seconds + 10);
  }
  std::unique_ptr<Communicator> communicator;
  if (launch.distributed()) communicator = connect_gloo(launch);
  TrainOptions opt;
  opt.communicator = communicator.get();
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
  if (launch.rank != 0) return 0;  // rank 0 reports for all
  // every rank steps as many env steps as rank 0 (they step together); agent steps are summed
  const double env_rate = double(r.env_steps) * launch.world_size / r.seconds,
               agent_rate = r.agent_steps / r.seconds;
  std::string parameters;
  for (int b = 0; b < run.num_trainers(); ++b)
    parameters += (b ? "," : "") + json_string(run.trainer(b).behavior()) + ":" +
                  std::to_string(run.trainer(b).flat_parameters().numel());
  auto gflops = [](double flops, double seconds) {
    return seconds > 0 ? flops / seconds * 1e-9 : 0.0;
  };
  const double learner_gflops = gflops(r.update_matmul_flops, r.update_seconds);
  // each behavior's updates: seconds and the learner's GFLOP/s in them
  std::string updates_json, updates_text;
  for (int b = 0; b < run.num_trainers(); ++b) {
    const std::string& name = run.trainer(b).behavior();
    const double s = r.trainer_update_seconds[b];
    const double g = gflops(r.trainer_update_matmul_flops[b], s);
    updates_json += (b ? "," : "") + json_string(name) + ":{\"update_s\":" + json_number(s) +
                    ",\"learner_gflops\":" + json_number(g) + "}";
    std::ostringstream t;
    t << (b ? ", " : "") << name << " " << s << " s at " << g << " GFLOP/s";
    updates_text += t.str();
  }
  if (cl.has("--json")) {
    std::cout << "{\"env_steps_per_s\":" << json_number(env_rate)
              << ",\"agent_steps_per_s\":" << json_number(agent_rate)
              << ",\"seconds\":" << json_number(r.seconds) << ",\"agent_steps\":" << r.agent_steps
              << ",\"acting_s\":" << json_number(r.acting_seconds)
              << ",\"env_s\":" << json_number(r.env_seconds)
              << ",\"trajectory_s\":" << json_number(r.trajectory_seconds)
              << ",\"update_s\":" << json_number(r.update_seconds)
              << ",\"learner_gflops\":" << json_number(learner_gflops)
              << ",\"behaviors\":{" << updates_json << "}"
              << ",\"ranks\":" << launch.world_size << ",\"parameters\":{" << parameters << "}}"
              << std::endl;
  } else {
    std::cout << r.agent_steps << " agent steps in " << r.seconds << " s: " << env_rate
              << " env steps/s, " << agent_rate << " agent steps/s (acting " << r.acting_seconds
              << " s, envs " << r.env_seconds << " s, trajectories " << r.trajectory_seconds
              << " s, updates " << r.update_seconds << " s; learner " << learner_gflops
              << " GFLOP/s in matrix products; updates by behavior: " << updates_text << ")"
              << std::endl;
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

// GFLOP/s of repeated a [m, k] x b [k, n] products (about `seconds` of them, after a warm-up)
double gemm_gflops(int64_t m, int64_t k, int64_t n, double seconds) {
  torch::manual_seed(0);
  auto a = torch::randn({m, k}), b = torch::randn({k, n}), c = torch::empty({m, n});
  torch::mm_out(c, a, b);
  int64_t reps = 0;
  const auto start = std::chrono::steady_clock::now();
  double elapsed = 0;
  while (elapsed < seconds) {
    torch::mm_out(c, a, b);
    ++reps;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return 2.0 * double(m) * double(k) * double(n) * double(reps) / elapsed * 1e-9;
}

int bench_gemm(const CommandLine& cl) {
  const int64_t size = cl.integer("--size", 2048, 16);
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  const int threads = int(cl.integer("--threads", cores, 1));
  set_compute_threads(threads);
  const double square = gemm_gflops(size, size, size, 3.0);
  // the hide-and-seek learner's first layer: a 3072-row minibatch of 943 observed floats
  constexpr int kRows = 3072, kInputs = 943, kUnits = 256;
  const double learner = gemm_gflops(kRows, kInputs, kUnits, 3.0);
  const std::string core = openblas_core();
  if (cl.has("--json"))
    std::cout << "{\"threads\":" << threads << ",\"size\":" << size << ",\"square_gflops\":"
              << json_number(square) << ",\"learner_shape_gflops\":" << json_number(learner)
              << ",\"blas_core\":\"" << core << "\"}\n";
  else
    std::cout << threads << " thread(s): " << size << "^3 products " << square
              << " GFLOP/s; " << kRows << " x " << kInputs << " x " << kUnits << " products "
              << learner << " GFLOP/s"
              << (core.empty() ? "" : "; OpenBLAS kernels " + core) << "\n";
  return 0;
}

}  // namespace

int run_bench(const std::vector<std::string>& args) {
  CommandLine cl(
      args, {"--json"},
      {"--steps", "--frames", "--num-envs", "--threads", "--seed", "--param", "--size", "--nproc"});
  if (cl.positional().empty()) throw UsageError("expected 'train', 'env' or 'gemm'");
  if (cl.positional()[0] == "gemm") return bench_gemm(cl);
  if (cl.positional()[0] == "train") return bench_train(cl, args);
  if (cl.positional()[0] == "env") return bench_env(cl);
  throw UsageError("unknown benchmark '" + cl.positional()[0] + "'");
}

}  // namespace rlt
