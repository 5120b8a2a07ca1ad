// A training run killed with SIGKILL at arbitrary moments always leaves a readable status and
// loadable checkpoints, and `rlt train --resume` continues from the newest complete checkpoint.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "env/register_builtin_envs.h"
#include "rl/trainer/run_folder.h"
#include "rl/trainer/saved_run.h"
#include "tests/apps/spawn_process.h"

namespace fs = std::filesystem;

namespace rlt {
namespace {

pid_t spawn_rlt(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = test::spawn_process(RLT_BINARY, args, log.string());
  EXPECT_GT(pid, 0);
  return pid;
}

int wait_exit(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

TEST(KillResume, KilledRunResumesFromItsLastCompleteCheckpoint) {
  register_builtin_envs();
  const fs::path root = fs::temp_directory_path() / ("rlt_kill_test_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  const fs::path config = root / "config.yaml";
  std::ofstream(config) << "behaviors:\n  CartPole:\n    trainer_type: ppo\n"
                           "    hyperparameters: {batch_size: 64, buffer_size: 256}\n"
                           "    network_settings: {hidden_units: 32, num_layers: 2}\n"
                           "    max_steps: 100000000\n    checkpoint_interval: 1500\n"
                           "    keep_checkpoints: 2\n    summary_freq: 100000000\n"
                           "env_settings: {env_id: CartPole, num_envs: 2, seed: 3}\n";
  const fs::path log = root / "log.txt";
  const std::vector<std::string> common = {"train", config.string(), "--results-dir", root.string(),
                                           "--run-id", "killed", "--threads", "1"};
  RunFolder folder(root.string(), "killed");
  std::mt19937 rng(7);
  int64_t last_steps = 0;
  for (int round = 0; round < 6; ++round) {
    auto args = common;
    if (round > 0) args.push_back("--resume");
    const pid_t pid = spawn_rlt(args, log);
    // wait until this round wrote a checkpoint beyond the previous one, then kill at a random moment
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    for (;;) {
      ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "no checkpoint written";
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      if (!fs::exists(folder.status_path())) continue;
      auto s = folder.read_status();
      if (!s.checkpoints.empty() && s.checkpoints.back().steps.at("CartPole") > last_steps) break;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(std::uniform_int_distribution<int>(0, 150000)(rng)));
    kill(pid, SIGKILL);
    EXPECT_EQ(wait_exit(pid), -SIGKILL);
    // what is on disk is consistent: the status reads, every listed checkpoint exists, the newest loads
    auto status = folder.read_status();
    ASSERT_FALSE(status.checkpoints.empty());
    for (const auto& c : status.checkpoints) EXPECT_TRUE(fs::exists(folder.file(c.file))) << c.file;
    SavedRun saved = load_saved_run(folder.path());
    EXPECT_GE(status.checkpoints.back().steps.at("CartPole"), last_steps);
    last_steps = status.checkpoints.back().steps.at("CartPole");
  }
  // a final resume runs to a nearby end and finishes cleanly
  auto args = common;
  args.insert(args.end(), {"--resume", "--max-steps", std::to_string(last_steps + 2000)});
  EXPECT_EQ(wait_exit(spawn_rlt(args, log)), 0) << std::ifstream(log).rdbuf();
  auto status = folder.read_status();
  EXPECT_TRUE(status.finished);
  EXPECT_GE(status.checkpoints.back().steps.at("CartPole"), last_steps + 2000);
  EXPECT_TRUE(fs::exists(folder.policy_path("CartPole")));
  fs::remove_all(root);
}

}  // namespace
}  // namespace rlt
