// Data-parallel training on c10d/Gloo with 2 ranks on 127.0.0.1 (ctest label `dist`), run as
// processes of `rlt train --nproc 2`:
// - every run compares the ranks' parameter hashes after every update and stops when they differ
//   (a rank drifting by one ulp is caught: the negative control);
// - 2 ranks learn CartPole to the threshold 1 rank reaches with the same total batch;
// - hide-and-seek (MA-POCA, self-play, curriculum, normalizers) runs with its replicas equal;
// - a rank killed with SIGKILL makes the other stop within the timeout naming it, and --resume
//   continues from the last checkpoint;
// - bad launch settings are errors that name them.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rl/trainer/run_folder.h"
#include "tests/apps/spawn_process.h"

#ifndef RLT_BINARY
#error "RLT_BINARY must name the rlt executable"
#endif
#ifndef RLT_SOURCE_DIR
#error "RLT_SOURCE_DIR must name the source tree"
#endif

namespace fs = std::filesystem;

namespace rlt {
namespace {

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Result {
  int exit_code = -1;
  std::string out, err;
  double seconds = 0;
};

class RltDistTest : public testing::Test {
 protected:
  void SetUp() override {
    root_ =
        fs::temp_directory_path() / ("rlt_dist_test_" + std::to_string(::getpid()) + "_" +
                                     testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  // `env` (VAR=value ...) before rlt, `args` after it (quoted as needed)
  Result rlt(const std::string& args, const std::string& env = "") {
    const fs::path out = root_ / "out.txt", err = root_ / "err.txt";
    const auto start = std::chrono::steady_clock::now();
    const std::string command =
        env + " " + RLT_BINARY + " " + args + " > '" + out.string() + "' 2> '" + err.string() + "'";
    const int status = std::system(command.c_str());
    Result r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(out), read_text(err)};
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  }

  // the mean return of 20 episodes of the policy's most likely actions: what the run learned. The
  // sampled actions' return moves with the last bits of the run: on an AMD EPYC (Zen 3) the
  // two-rank run's sampled policy scored 455.55 where its most likely actions held the pole for
  // all 500 steps in 20 episodes of 20.
  double eval_return(const std::string& run) {
    Result r = rlt("eval '" + (root_ / run).string() + "' --episodes 20 --deterministic --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::smatch m;
    EXPECT_TRUE(std::regex_search(r.out, m, std::regex("\"mean_return\":([-0-9.e+]+)"))) << r.out;
    return m.empty() ? 0.0 : std::stod(m[1]);
  }

  std::string train(const std::string& config, const std::string& run,
                    const std::string& more = "") {
    return "train '" + config + "' --results-dir '" + root_.string() + "' --run-id " + run + " " +
           more;
  }

  fs::path root_;
};

const std::string kCartPole = std::string(RLT_SOURCE_DIR) + "/configs/cartpole_ppo.yaml";

TEST_F(RltDistTest, TwoRanksLearnCartPoleAsOneDoesWithTheirReplicasEqual) {
  // the same total batch (batch 128, buffer 512): each rank takes half of every minibatch
  Result two = rlt(train(kCartPole, "two", "--nproc 2"));
  ASSERT_EQ(two.exit_code, 0) << two.out << two.err;
  EXPECT_NE(two.out.find("4 environments on each of 2 ranks"), std::string::npos) << two.out;
  // the replicas were compared after each of the run's updates (one CSV row per update)
  const std::string rows = read_text(root_ / "two/metrics/CartPole.csv");
  EXPECT_GT(std::count(rows.begin(), rows.end(), '\n'), 200);
  Result one = rlt(train(kCartPole, "one"));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const double two_return = eval_return("two"), one_return = eval_return("one");
  EXPECT_GE(one_return, 475.0);
  EXPECT_GE(two_return, 475.0) << "2 ranks did not learn what 1 rank learns (" << one_return << ")";
}

TEST_F(RltDistTest, ARankWhoseParametersDriftStopsTheRun) {
  // negative control for the check above: rank 1 moves one parameter by one ulp after updates
  Result r = rlt(train(kCartPole, "drift", "--nproc 2 --max-steps 20000"), "RLT_TEST_DRIFT_RANK=1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("update 1: the parameters of rank 1 differ from rank 0's"),
            std::string::npos)
      << r.err;
}

TEST_F(RltDistTest, HideAndSeekKeepsItsReplicasEqualWithSelfPlayAndLessons) {
  // MA-POCA and PPO with normalizers, asymmetric self-play and the fort-rate curriculum, shrunk
  std::string text = read_text(fs::path(RLT_SOURCE_DIR) / "configs/hide_and_seek.yaml");
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"batch_size: 1024", "batch_size: 256"},
           {"buffer_size: 12288", "buffer_size: 1024"},
           {"num_envs: 16", "num_envs: 2"},
           {"team_change: 100000", "team_change: 1000"},
           {"team_change: 200000", "team_change: 2000"},
           {"save_steps: 50000", "save_steps: 1000"},
           {"min_lesson_length: 100", "min_lesson_length: 1"},
           {"min_lesson_length: 50", "min_lesson_length: 1"}}) {
    size_t at = 0;
    while ((at = text.find(from, at)) != std::string::npos) text.replace(at, from.size(), to);
  }
  const fs::path config = root_ / "hide_and_seek.yaml";
  std::ofstream(config) << text;
  Result r = rlt(train(config.string(), "hs", "--nproc 2 --max-steps 6000"));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* behavior : {"Hider", "Seeker"}) {
    const std::string rows = read_text(root_ / "hs/metrics" / (std::string(behavior) + ".csv"));
    EXPECT_GE(std::count(rows.begin(), rows.end(), '\n'), 3) << behavior << " updated too rarely";
  }
  EXPECT_TRUE(fs::exists(root_ / "hs/Hider.pt"));
  EXPECT_TRUE(fs::exists(root_ / "hs/Seeker.pt"));
}

pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = test::spawn_process(RLT_BINARY, args, log.string());
  EXPECT_GT(pid, 0);
  return pid;
}

// the process among `launcher`'s children that has RANK=`rank` in its environment
pid_t rank_process(pid_t launcher, int rank) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = read_text(entry.path() / "stat");
    const auto close = stat.rfind(')');
    std::istringstream fields(close == std::string::npos ? "" : stat.substr(close + 2));
    std::string state;
    pid_t parent = 0;
    fields >> state >> parent;
    if (parent != launcher) continue;
    std::string environment = read_text(entry.path() / "environ");
    std::replace(environment.begin(), environment.end(), '\0', '\n');
    if (("\n" + environment).find("\nRANK=" + std::to_string(rank) + "\n") != std::string::npos)
      return pid_t(std::stoi(name));
  }
  return -1;
}

TEST_F(RltDistTest, AKilledRankIsNamedWithinTheTimeoutAndTheRunResumes) {
  const fs::path config = root_ / "cartpole.yaml";
  std::string text = read_text(kCartPole);
  text.replace(text.find("checkpoint_interval: 100000"), 27, "checkpoint_interval: 20000");
  std::ofstream(config) << text;
  const fs::path log = root_ / "killed.log";
  const std::vector<std::string> args = {"train",          config.string(),
                                         "--results-dir",  root_.string(),
                                         "--run-id",       "killed",
                                         "--nproc",        "2",
                                         "--dist-timeout", "10"};
  const pid_t launcher = spawn(args, log);
  RunFolder folder(root_.string(), "killed");
  // wait for a checkpoint, then kill rank 1
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  int64_t checkpoint_steps = 0;
  while (checkpoint_steps == 0) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << read_text(log);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!fs::exists(folder.status_path())) continue;
    const auto status = folder.read_status();
    if (!status.checkpoints.empty())
      checkpoint_steps = status.checkpoints.back().steps.at("CartPole");
  }
  const pid_t victim = rank_process(launcher, 1);
  ASSERT_GT(victim, 0);
  const auto killed_at = std::chrono::steady_clock::now();
  ::kill(victim, SIGKILL);
  int status = 0;
  ::waitpid(launcher, &status, 0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - killed_at).count();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0);
  EXPECT_LT(seconds, 10.0 + 5.0) << "the survivor outlived the timeout";
  const std::string said = read_text(log);
  EXPECT_NE(said.find("rank 0: "), std::string::npos) << said;
  EXPECT_NE(said.find("rank 1 stopped answering"), std::string::npos) << said;

  // --resume: both ranks start from the newest checkpoint and finish
  const int64_t resumed_from = folder.read_status().checkpoints.back().steps.at("CartPole");
  EXPECT_GE(resumed_from, checkpoint_steps);
  Result r = rlt(train(config.string(), "killed",
                       "--resume --nproc 2 --max-steps " + std::to_string(resumed_from + 30000)));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto finished = folder.read_status();
  EXPECT_TRUE(finished.finished);
  EXPECT_GE(finished.checkpoints.back().steps.at("CartPole"), resumed_from + 30000);
  // the metrics continue from the checkpoint: the first row after it is a later step
  std::istringstream rows(read_text(root_ / "killed/metrics/CartPole.csv"));
  std::string line;
  std::getline(rows, line);
  int64_t previous = 0;
  while (std::getline(rows, line)) {
    const int64_t step = std::stoll(line.substr(0, line.find(',')));
    EXPECT_GT(step, previous) << "metrics rows out of order after the resume";
    previous = step;
  }
}

TEST_F(RltDistTest, BadLaunchSettingsAreNamed) {
  const std::string run = train(kCartPole, "bad", "--max-steps 1000");
  Result r = rlt(run, "WORLD_SIZE=2 RANK=5");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("RANK=5 is not below WORLD_SIZE=2"), std::string::npos) << r.err;
  r = rlt(run, "WORLD_SIZE=two");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("WORLD_SIZE=two: expected an integer"), std::string::npos) << r.err;
  r = rlt(run + " --nproc 2", "WORLD_SIZE=2 RANK=0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--nproc starts its own ranks"), std::string::npos) << r.err;
  // a master nobody runs: rank 1 gives up after the timeout, naming the address
  r = rlt(run + " --dist-timeout 2", "WORLD_SIZE=2 RANK=1 MASTER_ADDR=127.0.0.1 MASTER_PORT=9");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot reach the master at 127.0.0.1:9"), std::string::npos) << r.err;
  EXPECT_LT(r.seconds, 30.0);
}

TEST_F(RltDistTest, RanksLaunchedWithDifferentWorldSizesAreNamed) {
  const std::string run = train(kCartPole, "mismatch", "--max-steps 1000 --dist-timeout 10");
  const fs::path rank1_log = root_ / "rank1.txt";
  const std::string rank1 = "WORLD_SIZE=3 RANK=1 MASTER_ADDR=127.0.0.1 MASTER_PORT=29517 " +
                            std::string(RLT_BINARY) + " " + run + " > '" + rank1_log.string() +
                            "' 2>&1 &";
  ASSERT_EQ(std::system(rank1.c_str()), 0);
  Result r = rlt(run, "WORLD_SIZE=2 RANK=0 MASTER_ADDR=127.0.0.1 MASTER_PORT=29517");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("was launched with WORLD_SIZE="), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rlt
