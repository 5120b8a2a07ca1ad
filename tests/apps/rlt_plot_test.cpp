// `rlt plot`, run as a process on run folders whose metrics the test writes itself: the expected
// figures are drawn, the pictures show each series in its colour (and not a series that has no
// points: the negative control), the points and their smoothing are the files' values, several
// runs share a figure, and bad input is a clear error.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/learning_curves.h"
#include "rl/trainer/run_folder.h"
#include "tests/apps/png_reader.h"
#include "tests/apps/shell_command.h"

#ifndef RLT_BINARY
#error "RLT_BINARY must name the rlt executable"
#endif

namespace fs = std::filesystem;

namespace rlt {
namespace {

using test::read_text;
using Result = test::CommandResult;

// the first two colours of `rlt plot`'s palette: the first and second run-and-behavior
constexpr uint32_t kFirst = 0x1f77b4, kSecond = 0xd62728;

class RltPlotTest : public testing::Test {
 protected:
  void SetUp() override {
    root_ =
        fs::temp_directory_path() / ("rlt_plot_test_" + std::to_string(::getpid()) + "_" +
                                     testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  Result rlt(const std::string& args, const std::string& env = "") {
    return test::run_shell(env + " " + RLT_BINARY + " " + args, root_);
  }

  // A run folder like rlt train's for a self-play hide-and-seek run: 40 updates per behavior
  // (the hiders' reward rises, the seekers' falls, or has no episodes at all when
  // `seeker_rewards` is false), ELO, a curriculum lesson and a strategy rate.
  fs::path make_run(const std::string& name, bool seeker_rewards = true) {
    const fs::path dir = root_ / name;
    fs::create_directories(dir / "metrics");
    const char* header =
        "step,elapsed_s,episodes,mean_return,std_return,mean_length,policy_loss,value_loss,"
        "baseline_loss,entropy,learning_rate,epsilon,beta,elo\n";
    std::ofstream hider(dir / "metrics/Hider.csv"), seeker(dir / "metrics/Seeker.csv"),
        episodes(dir / "metrics/episodes.csv");
    hider << header;
    seeker << header;
    episodes << "total_steps,elapsed_s,episodes,Hider_step,Seeker_step,lesson_level,tag_rate,"
                "smoothed_tag_rate_running_and_chasing\n";
    for (int i = 1; i <= 40; ++i) {
      const int step = 1000 * i;
      // every fifth row without episodes, as when an update ends before any episode does
      const bool no_episodes = i % 5 == 0;
      hider << step << ',' << i << ",4," << (no_episodes ? "nan" : std::to_string(0.1 * i))
            << ",0.1," << (no_episodes ? "nan" : "500") << ",-0.01,0.5,0,7.0,0.0003,0.2,0.005,"
            << 1200 + 5 * i << '\n';
      seeker << step << ',' << i << ",4,"
             << (seeker_rewards && !no_episodes ? std::to_string(4.0 - 0.1 * i) : "nan")
             << ",0.1,500,-0.02,0.4,0.05,6.0,0.0003,0.2,0.005," << 1200 - 5 * i << '\n';
      episodes << 2 * step << ',' << i << ",8," << step << ',' << step << ',' << (i > 20) << ','
               << 0.02 * i << ',' << 0.015 * i << '\n';
    }
    RunFolder folder(root_.string(), name);
    TrainingStatus status;
    status.run_id = name;
    Emergence chasing;
    chasing.strategy = "running_and_chasing";
    chasing.metric = "tag_rate";
    chasing.behavior = "Seeker";
    status.strategies.push_back(chasing);
    folder.write_status(status);
    return dir;
  }

  fs::path root_;
};

TEST_F(RltPlotTest, DrawsEveryFigureOfASelfPlayRunWithItsSeries) {
  const fs::path run = make_run("run");
  Result r = rlt("plot '" + run.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* figure : {"reward", "episode_length", "losses", "policy", "elo", "lessons",
                             "strategies", "episode_metrics"}) {
    SCOPED_TRACE(figure);
    const fs::path png = run / "plots" / (std::string(figure) + ".png");
    EXPECT_NE(r.out.find(png.string()), std::string::npos) << r.out;
    test::Image image = test::read_png(png.string());
    EXPECT_GE(image.width, 800);
    EXPECT_GE(image.height, 300);
  }
  // the reward figure shows both behaviors in their own colours
  test::Image reward = test::read_png((run / "plots/reward.png").string());
  EXPECT_GT(test::count_colour(reward, kFirst), 300);
  EXPECT_GT(test::count_colour(reward, kSecond), 300);
  EXPECT_TRUE(fs::exists(run / "plots/plots.gp"));
}

TEST_F(RltPlotTest, ASeriesWithoutPointsIsNotDrawn) {
  // negative control for the colour count above: the seekers finished no episode
  const fs::path run = make_run("run", false);
  Result r = rlt("plot '" + run.string() + "' --out '" + (root_ / "out").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  test::Image reward = test::read_png((root_ / "out/reward.png").string());
  EXPECT_GT(test::count_colour(reward, kFirst), 300);
  EXPECT_LT(test::count_colour(reward, kSecond), 20);
  // the seekers still have losses
  test::Image losses = test::read_png((root_ / "out/losses.png").string());
  EXPECT_GT(test::count_colour(losses, kSecond), 300);
}

TEST_F(RltPlotTest, ThePolicyFigureShowsHowFarTheUpdatesMovedThePolicyWhenTheRunLoggedIt) {
  // a run written before approx_kl and clip_fraction were logged has no such panels
  const fs::path old_run = make_run("old");
  ASSERT_EQ(rlt("plot '" + old_run.string() + "'").exit_code, 0);
  const std::string old_script = read_text(old_run / "plots/plots.gp");
  EXPECT_NE(old_script.find("Policy entropy"), std::string::npos);
  EXPECT_EQ(old_script.find("Approximate KL"), std::string::npos);
  EXPECT_EQ(old_script.find("Clip fraction"), std::string::npos);
  // the same run with the two columns (the hiders' only; the seekers' left empty)
  const fs::path run = make_run("new");
  for (const char* behavior : {"Hider", "Seeker"}) {
    const fs::path file = run / "metrics" / (std::string(behavior) + ".csv");
    std::istringstream in(read_text(file));
    std::ostringstream out;
    std::string line;
    std::getline(in, line);
    out << line << ",approx_kl,clip_fraction\n";
    for (int i = 1; std::getline(in, line); ++i)
      out << line << (behavior == std::string("Hider") ? "," + std::to_string(0.001 * i) + ",0.2" : ",,")
          << '\n';
    std::ofstream(file) << out.str();
  }
  Result r = rlt("plot '" + run.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string script = read_text(run / "plots/plots.gp");
  EXPECT_NE(script.find("Approximate KL"), std::string::npos);
  EXPECT_NE(script.find("Clip fraction"), std::string::npos);
  test::Image policy = test::read_png((run / "plots/policy.png").string());
  EXPECT_GT(test::count_colour(policy, kFirst), 300);
}

TEST_F(RltPlotTest, PlottedPointsAreTheFilesFiniteValuesSmoothedLikeTensorBoard) {
  const fs::path run = make_run("run");
  Result r = rlt("plot '" + run.string() + "' --smoothing 0.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // first block of reward.dat: the hiders' 32 rows with episodes
  std::istringstream data(read_text(run / "plots/data/reward.dat"));
  std::vector<double> x, y, smoothed;
  std::string line;
  while (std::getline(data, line) && !line.empty()) {
    std::istringstream row(line);
    double a, b, c;
    row >> a >> b >> c;
    x.push_back(a);
    y.push_back(b);
    smoothed.push_back(c);
  }
  ASSERT_EQ(x.size(), 32u);
  EXPECT_EQ(x[0], 1000);
  EXPECT_EQ(x[4], 6000);  // step 5000 had no episode
  EXPECT_NEAR(y[4], 0.6, 1e-9);
  // debiased: the first smoothed point is the first point; then the weighted means
  EXPECT_NEAR(smoothed[0], 0.1, 1e-9);
  EXPECT_NEAR(smoothed[1], (0.5 * 0.5 * 0.1 + 0.5 * 0.2) / (0.5 * 0.5 + 0.5), 1e-9);
}

TEST(SmoothLikeTensorBoardTest, KeepsAConstantAndFollowsAStep) {
  for (double v : smooth_like_tensorboard({3, 3, 3}, 0.9)) EXPECT_NEAR(v, 3, 1e-12);
  std::vector<double> step(200, 0.0);
  for (size_t i = 100; i < step.size(); ++i) step[i] = 1;
  const auto s = smooth_like_tensorboard(step, 0.9);
  EXPECT_EQ(s[99], 0);
  // the first 1 weighs 0.1 of the 101 debiased weights
  EXPECT_NEAR(s[100], 0.1 / (1 - std::pow(0.9, 101)), 1e-12);
  EXPECT_GT(s[199], 0.99);
  EXPECT_EQ(smooth_like_tensorboard({1, 5}, 0), (std::vector<double>{1, 5}));
}

TEST_F(RltPlotTest, SeveralRunsShareTheFiguresAndAreNamedByFolder) {
  const fs::path a = make_run("seed1"), b = make_run("seed2");
  Result r = rlt("plot '" + a.string() + "' '" + b.string() + "' --out '" +
                 (root_ / "both").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string script = read_text(root_ / "both/plots.gp");
  for (const char* title : {"'seed1 Hider'", "'seed1 Seeker'", "'seed2 Hider'", "'seed2 Seeker'"})
    EXPECT_NE(script.find(title), std::string::npos) << title;
  // the second run's hiders have the third colour
  test::Image reward = test::read_png((root_ / "both/reward.png").string());
  EXPECT_GT(test::count_colour(reward, 0x2ca02c), 300);
}

TEST_F(RltPlotTest, BadInputIsAClearError) {
  Result r = rlt("plot '" + root_.string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("has no metrics/ folder"), std::string::npos) << r.err;

  r = rlt("plot");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("expected at least one RUN_DIR"), std::string::npos) << r.err;

  const fs::path run = make_run("run");
  r = rlt("plot '" + run.string() + "' --smoothing 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--smoothing: must be at least 0 and below 1, got 1"), std::string::npos)
      << r.err;

  // without gnuplot on PATH: named, with the package, and nothing drawn
  r = rlt("plot '" + run.string() + "'", "PATH=/nonexistent");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("gnuplot-nox"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(run / "plots/reward.png"));
}

}  // namespace
}  // namespace rlt
