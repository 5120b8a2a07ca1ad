// rlt: train, evaluate, export and benchmark reinforcement-learning runs.
#include <iostream>
#include <string>
#include <vector>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "env/register_builtin_envs.h"
#include "rl/core/blas_kernels.h"

namespace {

const char* kHelp =
    R"(rlt - reinforcement learning toolkit on LibTorch: PPO, MA-POCA, self-play, curricula

Usage: rlt COMMAND [ARGS...]

Commands:
  train CONFIG     train the behaviors of a YAML run configuration (ML-Agents schema)
  eval RUN_DIR     play episodes with a trained run and report returns and episode metrics
  eval --env ID    play an env with random, still, scripted or trained policies per behavior
                   (--policy Hider=scripted), optionally recording the episodes (--record FILE)
  export RUN_DIR   write each behavior's TorchScript policy to RUN_DIR/<Behavior>.pt
  plot RUN_DIR...  draw the learning curves of one run or several side by side as PNG files
  lessons RUN_DIR  where a run spent its curriculum: each lesson's steps and episode metrics
  replay FILE      play a recorded episode in a 3D viewer in the browser (served on localhost)
  envs             list the registered environments and their behavior specs
  bench            measure training, environment or matrix-product throughput

Run 'rlt COMMAND --help' for the options of a command.

Environment: OPENBLAS_CORETYPE is kept when set. When it is not and Debian's OpenBLAS does not know
the CPU (it then runs its oldest kernels, Prescott), rlt starts itself again with SkylakeX on a CPU
with AVX-512 or Haswell with AVX2: 2-5x faster matrix products ('rlt bench gemm' names the kernels).

Quick start:
  rlt train configs/cartpole_ppo.yaml --run-id cartpole
  rlt eval results/cartpole --episodes 20 --json
  rlt eval --env HideAndSeek --policy Hider=scripted --policy Seeker=still --param level=1
)";

}  // namespace

int main(int argc, char** argv) {
  // OpenBLAS's newest kernels for this CPU when it fell back to its oldest (blas_kernels.h)
  rlt::use_best_openblas_kernels(argv);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << kHelp;
    return args.empty() ? 2 : 0;
  }
  rlt::register_builtin_envs();
  const std::string command = args[0];
  args.erase(args.begin());
  struct Entry {
    const char* name;
    int (*run)(const std::vector<std::string>&);
    const char* help;
  };
  const Entry entries[] = {
      {"train", rlt::run_train, rlt::kTrainHelp},    {"eval", rlt::run_eval, rlt::kEvalHelp},
      {"export", rlt::run_export, rlt::kExportHelp}, {"envs", rlt::run_envs, rlt::kEnvsHelp},
      {"bench", rlt::run_bench, rlt::kBenchHelp},    {"plot", rlt::run_plot, rlt::kPlotHelp},
      {"replay", rlt::run_replay, rlt::kReplayHelp}, {"lessons", rlt::run_lessons, rlt::kLessonsHelp}};
  for (const auto& e : entries) {
    if (command != e.name) continue;
    for (const auto& a : args)
      if (a == "--help" || a == "-h") {
        std::cout << e.help;
        return 0;
      }
    try {
      return e.run(args);
    } catch (const rlt::UsageError& err) {
      std::cerr << "rlt " << command << ": " << err.what() << "\n\n" << e.help;
      return 2;
    } catch (const std::exception& err) {
      std::cerr << "rlt " << command << ": error: " << err.what() << "\n";
      return 1;
    }
  }
  std::cerr << "rlt: unknown command '" << command << "'\n\n" << kHelp;
  return 2;
}
