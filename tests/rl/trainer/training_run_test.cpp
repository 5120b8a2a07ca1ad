// Training runs end to end: bit-identical resume, checkpoint files, bad numbers, run folder rules.
#include "rl/trainer/training_run.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "env/register_builtin_envs.h"
#include "rl/config/config_parser.h"
#include "rl/core/bad_numbers.h"
#include "rl/core/csv_line.h"
#include "rl/core/machine_info.h"
#include "rl/env_api/env_registry.h"
#include "rl/selfplay/self_play.h"
#include "rl/trainer/saved_run.h"
#include "tests/rl/trainer/tensorboard_reader.h"

namespace fs = std::filesystem;

namespace rlt {
namespace {

// the bytes of a file (empty when it cannot be read)
std::string file_contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// An env that counts decisions and emits a bad number at a chosen global decision.
class BadNumberEnv : public Env {
 public:
  BadNumberEnv() {
    spec_.name = "BadNumberEnv";
    spec_.max_episode_steps = 20;
    BehaviorSpec b;
    b.name = "Agent";
    b.observations.push_back({"state", {2}, ObservationKind::kVector, -10.f, 10.f});
    b.action.discrete_branches = {2};
    spec_.behaviors.push_back(b);
    spec_.default_parameters = {{"bad_step", 1e9f}, {"what", 0.f}};  // what: 0 obs, 1 reward, 2 huge reward
  }
  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t s) override { engine_.seed(s); }
  void reset(StepView& out) override {
    t_ = 0;
    out[0].step_type(0) = StepType::kFirst;
    out[0].agent_id(0) = 0;
    write(out, 0.f);
  }
  void step(StepView& io) override {
    ++t_;
    ++global_;
    const bool bad = global_ == int64_t(parameter("bad_step"));
    const int what = int(parameter("what"));
    const int a = io[0].discrete_action(0)[0];
    io[0].reward(0) = bad && what == 1 ? NAN : (bad && what == 2 ? 3e38f : float(a));
    io[0].step_type(0) = t_ >= spec_.max_episode_steps ? StepType::kLast : StepType::kMid;
    write(io, bad && what == 0 ? NAN : 0.f);
  }

 private:
  void write(StepView& v, float extra) {
    float* o = v[0].observation(0);
    o[0] = float(uniform01(engine_)) + extra;
    o[1] = float(t_) / spec_.max_episode_steps;
  }
  EnvSpec spec_;
  std::mt19937_64 engine_;
  int t_ = 0;
  static inline int64_t global_ = 0;

 public:
  static void restart_count() { global_ = 0; }
};

// One agent whose episodes last 3, 4 or 5 steps (by instance seed) and report the value of
// parameter x, and whether it is below one half, as episode metrics.
class LessonEchoEnv : public Env {
 public:
  // with_strategies (registered as StrategyEchoEnv): the env also declares two strategies, low_x
  // (two episodes in a row played with x < 0.5) and high_x (two with x above 1.5)
  explicit LessonEchoEnv(bool with_strategies = false) {
    spec_.name = with_strategies ? "StrategyEchoEnv" : "LessonEchoEnv";
    if (with_strategies)
      spec_.strategies = {{"low_x", "below_half", "Echo", 0.5f, 2, {}},
                          {"high_x", "value", "Echo", 1.5f, 2, {}}};
    spec_.max_episode_steps = 5;
    BehaviorSpec b;
    b.name = "Echo";
    b.observations.push_back({"x", {1}, ObservationKind::kVector, -10.f, 10.f});
    b.action.discrete_branches = {2};
    spec_.behaviors.push_back(b);
    spec_.default_parameters = {{"x", 0.f}};
  }
  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t s) override { length_ = 3 + int(s % 3); }
  void reset(StepView& out) override {
    if (parameter("x") > 10.f)
      throw std::invalid_argument("LessonEchoEnv: x must be at most 10, got " +
                                  std::to_string(int(parameter("x"))));
    t_ = 0;
    out[0].step_type(0) = StepType::kFirst;
    out[0].agent_id(0) = 0;
    out[0].observation(0)[0] = parameter("x");
  }
  void step(StepView& io) override {
    ++t_;
    io[0].reward(0) = 0.f;
    io[0].step_type(0) = t_ >= length_ ? StepType::kLast : StepType::kMid;
    io[0].observation(0)[0] = parameter("x");
  }
  EpisodeMetrics episode_metrics() const override {
    return {{"value", parameter("x")}, {"below_half", parameter("x") < 0.5f ? 1.f : 0.f}};
  }

 private:
  EnvSpec spec_;
  int length_ = 3;
  int t_ = 0;
};

// Two behaviors, Red and Blue, one agent each, in episodes of 4 steps that report the value of
// parameter x they were played with: which setting each self-play turn used.
class TurnEchoEnv : public Env {
 public:
  TurnEchoEnv() {
    spec_.name = "TurnEchoEnv";
    spec_.max_episode_steps = 4;
    for (const char* name : {"Blue", "Red"}) {
      BehaviorSpec b;
      b.name = name;
      b.observations.push_back({"t", {1}, ObservationKind::kVector, 0.f, 1.f});
      b.action.discrete_branches = {2};
      spec_.behaviors.push_back(b);
    }
    spec_.default_parameters = {{"x", 0.f}, {"level", 0.f}};  // level: for curricula only
  }
  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t) override {}
  void reset(StepView& out) override {
    t_ = 0;
    played_x_ = parameter("x");
    write(out, StepType::kFirst);
  }
  void step(StepView& io) override {
    ++t_;
    write(io, t_ >= spec_.max_episode_steps ? StepType::kLast : StepType::kMid);
  }
  EpisodeMetrics episode_metrics() const override { return {{"x", played_x_}}; }

 private:
  void write(StepView& v, StepType type) {
    for (int b = 0; b < 2; ++b) {
      v[b].step_type(0) = type;
      v[b].agent_id(0) = 0;
      v[b].reward(0) = 0.f;
      v[b].observation(0)[0] = float(t_) / spec_.max_episode_steps;
    }
  }
  EnvSpec spec_;
  int t_ = 0;
  float played_x_ = 0.f;
};

class TrainingRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    register_builtin_envs();
    if (!EnvRegistry::instance().contains("LessonEchoEnv"))
      EnvRegistry::instance().add(
          "LessonEchoEnv", [](const Parameters&) { return std::make_unique<LessonEchoEnv>(); });
    if (!EnvRegistry::instance().contains("StrategyEchoEnv"))
      EnvRegistry::instance().add("StrategyEchoEnv", [](const Parameters&) {
        return std::make_unique<LessonEchoEnv>(/*with_strategies=*/true);
      });
    if (!EnvRegistry::instance().contains("TurnEchoEnv"))
      EnvRegistry::instance().add("TurnEchoEnv",
                                  [](const Parameters&) { return std::make_unique<TurnEchoEnv>(); });
    if (!EnvRegistry::instance().contains("BadNumberEnv"))
      EnvRegistry::instance().add("BadNumberEnv", [](const Parameters&) { return std::make_unique<BadNumberEnv>(); });
    dir_ = fs::temp_directory_path() / ("rlt_training_run_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // a small, fast config for `env_id`
  RunConfig small_config(const std::string& env_id, const std::string& behavior, int64_t max_steps,
                         int64_t checkpoint_interval, bool normalize = false) {
    std::ostringstream y;
    y << "behaviors:\n  " << behavior << ":\n    trainer_type: ppo\n"
      << "    hyperparameters: {batch_size: 64, buffer_size: 256, learning_rate: 3.0e-4, num_epoch: 2}\n"
      << "    network_settings: {hidden_units: 16, num_layers: 2, normalize: " << (normalize ? "true" : "false") << "}\n"
      << "    time_horizon: 32\n    max_steps: " << max_steps << "\n    summary_freq: 500\n"
      << "    checkpoint_interval: " << checkpoint_interval << "\n    keep_checkpoints: 3\n"
      << "env_settings: {env_id: " << env_id << ", num_envs: 3, seed: 5}\n";
    return load_run_config_from_string(y.str(), "test.yaml");
  }

  TrainOptions options(const std::string& run_id) {
    TrainOptions o;
    o.run_id = run_id;
    o.results_dir = dir_.string();
    o.log = &log_;
    o.progress = false;
    o.threads = 2;
    return o;
  }

  // building a run from `config` with `opt` throws std::invalid_argument saying `says`, before
  // the run's folder is written
  void expect_rejected_before_writing(const RunConfig& config, const TrainOptions& opt,
                                      const std::string& says) {
    try {
      TrainingRun run(config, opt);
      ADD_FAILURE() << "accepted; expected an error saying " << says;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir_ / opt.run_id)) << opt.run_id << " was written";
  }

  static std::vector<torch::Tensor> parameters(TrainingRun& run) {
    std::vector<torch::Tensor> out;
    for (auto& p : run.trainer(0).network()->parameters()) out.push_back(p.detach().clone());
    return out;
  }

  // every TensorBoard point of a run folder's behavior, from all its event files (one per start
  // or resume): step -> tag -> value
  static std::map<int64_t, std::map<std::string, float>> tensorboard_points(const fs::path& dir) {
    std::map<int64_t, std::map<std::string, float>> points;
    for (const auto& entry : fs::directory_iterator(dir))
      for (const auto& event : tensorboard_reader::read_events(entry.path().string()))
        if (!event.scalars.empty()) points[event.step] = event.scalars;
    return points;
  }

  // metrics rows without the elapsed-time column
  static std::vector<std::string> metrics_without_time(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> rows;
    std::string line;
    while (std::getline(in, line)) {
      auto first = line.find(','), second = line.find(',', first + 1);
      rows.push_back(line.substr(0, first) + line.substr(second));
    }
    return rows;
  }

  fs::path dir_;
  std::ostringstream log_;
};

struct ResumeCase {
  const char* env_id;
  const char* behavior;
  bool normalize;
};

class ResumeTest : public TrainingRunTest, public ::testing::WithParamInterface<ResumeCase> {};

TEST_P(ResumeTest, StoppedAndResumedRunEndsBitIdenticalToUninterruptedRun) {
  const auto c = GetParam();
  // uninterrupted
  TrainingRun whole(small_config(c.env_id, c.behavior, 3000, 1000, c.normalize), options("whole"));
  whole.train();
  auto expected = parameters(whole);
  // stopped after its first checkpoint, then resumed in a new TrainingRun
  {
    TrainingRun first(small_config(c.env_id, c.behavior, 3000, 1000, c.normalize), options("split"));
    first.train(/*stop_after_boundaries=*/1);
    EXPECT_LT(first.trainer(0).step(), 3000);
  }
  auto opt = options("split");
  opt.resume = true;
  TrainingRun resumed(small_config(c.env_id, c.behavior, 3000, 1000, c.normalize), opt);
  EXPECT_GE(resumed.trainer(0).step(), 1000);
  resumed.train();
  auto actual = parameters(resumed);
  ASSERT_EQ(expected.size(), actual.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_TRUE(torch::equal(expected[i], actual[i])) << "parameter " << i;
  EXPECT_EQ(whole.trainer(0).step(), resumed.trainer(0).step());
  EXPECT_EQ(whole.trainer(0).updates(), resumed.trainer(0).updates());
  const std::string metrics = std::string("metrics/") + c.behavior + ".csv";
  EXPECT_EQ(metrics_without_time((dir_ / "whole" / metrics).string()),
            metrics_without_time((dir_ / "split" / metrics).string()));
}

TEST_P(ResumeTest, DifferentSeedGivesDifferentWeights) {
  // the comparison above can fail: another seed leads elsewhere
  const auto c = GetParam();
  TrainingRun a(small_config(c.env_id, c.behavior, 1500, 1000, c.normalize), options("a"));
  a.train();
  auto opt = options("b");
  opt.seed = 6;
  TrainingRun b(small_config(c.env_id, c.behavior, 1500, 1000, c.normalize), opt);
  b.train();
  auto pa = parameters(a), pb = parameters(b);
  bool all_equal = true;
  for (size_t i = 0; i < pa.size(); ++i) all_equal &= torch::equal(pa[i], pb[i]);
  EXPECT_FALSE(all_equal);
}

// A run begun with --seed and resumed without it keeps its own seed, not the config file's (5):
// the boundaries reseed the env instances from it. The control resumes with the file's seed given
// on purpose, which parts from the run and says so.
TEST_F(TrainingRunTest, AResumeWithoutSeedKeepsTheRunsOwnSeed) {
  auto seeded = [&](const std::string& run_id, int64_t seed, bool resume) {
    TrainOptions o = options(run_id);
    o.seed = seed;
    o.resume = resume;
    return o;
  };
  TrainingRun whole(small_config("CartPole", "CartPole", 3000, 1000), seeded("whole", 9, false));
  whole.train();
  const auto expected = parameters(whole);
  for (const std::string run_id : {"own_seed", "file_seed"}) {
    TrainingRun first(small_config("CartPole", "CartPole", 3000, 1000), seeded(run_id, 9, false));
    first.train(/*stop_after_boundaries=*/1);
  }
  log_.str("");
  TrainingRun own(small_config("CartPole", "CartPole", 3000, 1000), seeded("own_seed", -1, true));
  own.train();
  const auto actual = parameters(own);
  for (size_t i = 0; i < expected.size(); ++i)
    EXPECT_TRUE(torch::equal(expected[i], actual[i])) << i;
  EXPECT_EQ(log_.str().find("Note: resuming with --seed"), std::string::npos) << log_.str();
  const std::string text = file_contents(dir_ / "own_seed" / "configuration.yaml");
  EXPECT_NE(text.find("seed: 9"), std::string::npos) << text;  // the run's seed, stored again

  TrainingRun other(small_config("CartPole", "CartPole", 3000, 1000), seeded("file_seed", 5, true));
  other.train();
  const auto parted = parameters(other);
  bool all_equal = true;
  for (size_t i = 0; i < expected.size(); ++i) all_equal &= torch::equal(expected[i], parted[i]);
  EXPECT_FALSE(all_equal);
  EXPECT_NE(log_.str().find("Note: resuming with --seed 5 where the run began with seed 9"),
            std::string::npos)
      << log_.str();
}

INSTANTIATE_TEST_SUITE_P(Envs, ResumeTest,
                         ::testing::Values(ResumeCase{"CartPole", "CartPole", false},
                                           ResumeCase{"Pendulum", "Pendulum", true},
                                           ResumeCase{"HybridReach", "HybridReach", true},
                                           ResumeCase{"MaskedChoice", "MaskedChoice", false}));

TEST_F(TrainingRunTest, SelfPlayPoolEloAndLearningTeamSurviveResume) {
  auto config = [&] {
    RunConfig c = small_config("Duel", "Duelist", 4000, 1000);
    SelfPlaySettings sp;
    sp.save_steps = 300;
    sp.team_change = 700;
    sp.swap_steps = 200;
    sp.window = 3;
    c.behaviors.at("Duelist").self_play = sp;
    return c;
  };
  TrainingRun whole(config(), options("sp_whole"));
  whole.train();
  {
    TrainingRun first(config(), options("sp_split"));
    first.train(/*stop_after_boundaries=*/2);
  }
  auto opt = options("sp_split");
  opt.resume = true;
  TrainingRun resumed(config(), opt);
  resumed.train();
  auto expected = parameters(whole), actual = parameters(resumed);
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_TRUE(torch::equal(expected[i], actual[i])) << i;
  EXPECT_EQ(whole.self_play().elo(0), resumed.self_play().elo(0));
  EXPECT_NE(whole.self_play().elo(0), 1200.0);  // games were played and rated
  EXPECT_EQ(whole.self_play().learning_team_name(), resumed.self_play().learning_team_name());
  // the status file reports the rating
  auto status = RunFolder(dir_.string(), "sp_split").read_status();
  EXPECT_NEAR(status.elo.at("Duelist"), resumed.self_play().elo(0), 1e-6);  // 10 digits in JSON
}

// a two-lesson curriculum on Pursuit's `level`, advanced by the Seeker's progress, with self-play
RunConfig pursuit_curriculum_config(int64_t max_steps, int64_t summary_freq = 100000) {
  std::ostringstream y;
  y << "default_settings:\n"
    << "  hyperparameters: {batch_size: 64, buffer_size: 256, num_epoch: 1}\n"
    << "  network_settings: {hidden_units: 16, num_layers: 1}\n"
    << "  time_horizon: 32\n  max_steps: " << max_steps << "\n  summary_freq: " << summary_freq
    << "\n"
    << "  checkpoint_interval: 1000\n"
    << "  self_play: {save_steps: 300, team_change: 500, swap_steps: 200, window: 3}\n"
    << "behaviors:\n  Seeker: {trainer_type: poca}\n  Hider: {trainer_type: ppo}\n"
    << "environment_parameters:\n  level:\n    curriculum:\n"
    << "      - name: easy\n        value: 1\n"
    << "        completion_criteria: {measure: progress, behavior: Seeker, threshold: 0.5}\n"
    << "      - name: hard\n        value: 3\n"
    << "env_settings: {env_id: Pursuit, num_envs: 2, seed: 4}\n";
  return load_run_config_from_string(y.str(), "curriculum.yaml");
}

TEST_F(TrainingRunTest, CurriculumCountsTheLearningBehaviorsStepsAndSurvivesResume) {
  // Seeker steps advance only while seekers learn (self-play alternates with hiders every 500),
  // and the lesson changes exactly when the Seeker's progress passes 0.5
  TrainingRun whole(pursuit_curriculum_config(2000), options("cur_whole"));
  const int seeker = whole.trainer(0).behavior() == "Seeker" ? 0 : 1;
  whole.train(/*stop_after_boundaries=*/1);
  const int64_t seeker_steps = whole.trainer(seeker).step();
  EXPECT_LT(seeker_steps, whole.trainer(1 - seeker).step() + 1000);
  EXPECT_EQ(whole.parameters().lessons().at("level"), seeker_steps > 1000 ? 1 : 0);
  whole.train();
  EXPECT_EQ(whole.parameters().lessons().at("level"), 1);
  // the same run stopped after its first checkpoint and resumed
  {
    TrainingRun first(pursuit_curriculum_config(2000), options("cur_split"));
    first.train(/*stop_after_boundaries=*/2);
  }
  auto resume = options("cur_split");
  resume.resume = true;
  TrainingRun resumed(pursuit_curriculum_config(2000), resume);
  EXPECT_EQ(resumed.parameters().serialize().empty(), false);
  resumed.train();
  EXPECT_EQ(resumed.parameters().lessons().at("level"), 1);
  EXPECT_EQ(resumed.parameters().serialize(), whole.parameters().serialize());
  EXPECT_EQ(RunFolder(dir_.string(), "cur_split").read_status().lessons.at("level"), 1);
  auto a = parameters(whole), b = parameters(resumed);
  for (size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(torch::equal(a[i], b[i])) << i;
  // the one lesson change is logged once, at the same steps (the time aside)
  const auto change = [&](const std::string& run_id) {
    std::istringstream lines(file_contents(dir_ / run_id / "metrics" / "lessons.csv"));
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(lines, line);) {
      rows.push_back(split_csv_line(line));
      rows.back().erase(rows.back().begin() + 1);  // elapsed_s
    }
    return rows;
  };
  const auto logged = change("cur_whole");
  ASSERT_EQ(logged.size(), 2u);
  // the Seeker's progress fraction, just past the threshold
  EXPECT_GT(std::stod(logged[1].back()), 0.5);
  EXPECT_LT(std::stod(logged[1].back()), 0.6);
  EXPECT_EQ(change("cur_split"), logged);
}

// metrics/episodes.csv of a run begun by a build whose env had fewer metrics: resumed, the file
// gets today's header and its kept rows keep their values under it, empty where the new column
// falls (here between the lesson and the other metrics); a column nobody writes any more is an
// error naming the file and the column, and the file stays as it was
TEST_F(TrainingRunTest, AResumeMovesEpisodeMetricsUnderAHeaderWithANewColumn) {
  {
    TrainingRun first(pursuit_curriculum_config(2000, 500), options("ep_old"));
    first.train(/*stop_after_boundaries=*/2);
  }
  const fs::path episodes = dir_ / "ep_old" / "metrics" / "episodes.csv";
  std::vector<std::vector<std::string>> rows;
  {
    std::istringstream lines(file_contents(episodes));
    for (std::string line; std::getline(lines, line);) {
      std::vector<std::string> fields;
      std::istringstream in(line);
      for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
      rows.push_back(fields);
    }
  }
  ASSERT_GE(rows.size(), 2u) << "a header and a row before the checkpoint";
  const std::vector<std::string> header = rows[0];
  const auto column = std::find(header.begin(), header.end(), "seen_fraction") - header.begin();
  ASSERT_LT(column, int(header.size()) - 1) << "seen_fraction is not the last column";
  ASSERT_GT(column, 0);
  // the file as the older build wrote it: no seen_fraction
  std::string old_file;
  for (auto row : rows) {
    row.erase(row.begin() + column);
    for (size_t i = 0; i < row.size(); ++i) old_file += (i ? "," : "") + row[i];
    old_file += "\n";
  }
  write_text(episodes, old_file);
  auto opt = options("ep_old");
  opt.resume = true;
  { TrainingRun(pursuit_curriculum_config(2000, 500), opt).train(); }
  std::istringstream after(file_contents(episodes));
  std::string line;
  std::getline(after, line);
  std::string joined;
  for (size_t i = 0; i < header.size(); ++i) joined += (i ? "," : "") + header[i];
  EXPECT_EQ(line, joined);
  int kept = 0, measured = 0;
  for (size_t r = 1; std::getline(after, line); ++r) {
    std::vector<std::string> fields;
    std::istringstream in(line);
    for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    ASSERT_EQ(fields.size(), header.size()) << "row " << r << ": " << line;
    if (fields[column].empty()) {
      ++kept;
      ASSERT_LT(r, rows.size()) << "an empty seen_fraction in a row written after the resume";
      for (size_t i = 0; i < fields.size(); ++i)
        if (int(i) != column) EXPECT_EQ(fields[i], rows[r][i]) << "row " << r << ", column " << i;
    } else {
      ++measured;
      EXPECT_GE(std::stod(fields[column]), 0.0);
    }
  }
  EXPECT_GT(kept, 0);
  EXPECT_GT(measured, 0);
  // a column the run does not write
  const std::string other = "total_steps,elapsed_s,episodes,retired_metric\n1,2,3,4\n";
  write_text(episodes, other);
  try {
    TrainingRun again(pursuit_curriculum_config(2000, 500), opt);
    ADD_FAILURE() << "resumed over an episodes file with a column nobody writes";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("episodes.csv:1:"), std::string::npos) << what;
    EXPECT_NE(what.find("column 'retired_metric' is not written any more"), std::string::npos)
        << what;
  }
  EXPECT_EQ(file_contents(episodes), other);
}

// Pursuit as the hide-and-seek run plays it, small: Hider on PPO and Seeker on MA-POCA take turns
// of different lengths, opponents are drawn from windows of snapshots or the latest policy, the
// seekers' turns play their turn_parameters, `level` advances on an episode metric and falls back
// when it collapses, and the seekers stop at their max_steps while the hiders go on.
RunConfig pursuit_self_play_config() {
  std::ostringstream y;
  y << "default_settings:\n"
    << "  hyperparameters: {batch_size: 32, buffer_size: 128, num_epoch: 1}\n"
    << "  network_settings: {hidden_units: 8, num_layers: 1, normalize: true}\n"
    << "  time_horizon: 16\n  summary_freq: 400\n  checkpoint_interval: 1000\n"
    << "behaviors:\n"
    << "  Hider:\n    trainer_type: ppo\n    max_steps: 6000\n"
    << "    self_play: {save_steps: 250, team_change: 700, swap_steps: 90, window: 3,\n"
    << "                play_against_latest_model_ratio: 0.5}\n"
    << "  Seeker:\n    trainer_type: poca\n    max_steps: 2500\n"
    << "    self_play: {save_steps: 300, team_change: 1300, swap_steps: 110, window: 2,\n"
    << "                play_against_latest_model_ratio: 0.5,\n"
    << "                turn_parameters: {prep_fraction: 0.1}}\n"
    << "environment_parameters:\n  level:\n    curriculum:\n"
    << "      - name: one\n        value: 1\n"
    << "        completion_criteria: {measure: metric, metric: seen_fraction, threshold: 0.3,"
       " min_lesson_length: 8, fallback_threshold: 0.2, fallback_length: 4}\n"
    << "      - name: two\n        value: 2\n"
    << "        completion_criteria: {measure: metric, metric: seen_fraction, threshold: 0.95,"
       " min_lesson_length: 8, fallback_threshold: 0.5, fallback_length: 6}\n"
    << "      - name: three\n        value: 3\n"
    << "env_settings: {env_id: Pursuit, num_envs: 3, seed: 3, params: {episode_length: 30}}\n";
  return load_run_config_from_string(y.str(), "pursuit_self_play.yaml");
}

TEST_F(TrainingRunTest, SelfPlayWithTwoBehaviorsAndACurriculumResumesBitIdentically) {
  TrainingRun whole(pursuit_self_play_config(), options("hs_whole"));
  whole.train();
  const int seeker = whole.trainer(0).behavior() == "Seeker" ? 0 : 1, hider = 1 - seeker;
  // the run exercised what a resume must carry: the seekers stopped while the hiders went on,
  // and the lessons moved
  ASSERT_GE(whole.trainer(seeker).step(), 2500);
  ASSERT_GE(whole.trainer(hider).step(), 6000);
  EXPECT_NE(log_.str().find("Curriculum level: back from"), std::string::npos) << log_.str();
  // stopped at the second boundary (Hider 1002, Seeker 1302): in the hiders' second turn (702 to
  // 1402), with snapshots in both pools, before the seekers stop, and in the middle of a row of
  // metrics/episodes.csv (every 400 steps of either behavior, boundaries every 1000)
  int64_t stopped_hider = 0, stopped_seeker = 0;
  std::string stopped_team;
  {
    TrainingRun first(pursuit_self_play_config(), options("hs_split"));
    first.train(/*stop_after_boundaries=*/2);
    stopped_hider = first.trainer(hider).step();
    stopped_seeker = first.trainer(seeker).step();
    stopped_team = first.self_play().learning_team_name();
    EXPECT_EQ(stopped_team, "Hider:0");
    EXPECT_GT(stopped_hider, 700);
    EXPECT_LT(stopped_hider, 1400);
    EXPECT_FALSE(first.trainer(seeker).finished());
  }
  auto resume = options("hs_split");
  resume.resume = true;
  TrainingRun resumed(pursuit_self_play_config(), resume);
  EXPECT_EQ(resumed.trainer(hider).step(), stopped_hider);
  EXPECT_EQ(resumed.trainer(seeker).step(), stopped_seeker);
  EXPECT_EQ(resumed.self_play().learning_team_name(), stopped_team);
  resumed.train();

  for (int b = 0; b < 2; ++b) {
    const std::string behavior = whole.trainer(b).behavior();
    EXPECT_EQ(whole.trainer(b).step(), resumed.trainer(b).step()) << behavior;
    EXPECT_EQ(whole.trainer(b).updates(), resumed.trainer(b).updates()) << behavior;
    auto expected = whole.trainer(b).network()->parameters();
    auto actual = resumed.trainer(b).network()->parameters();
    ASSERT_EQ(expected.size(), actual.size());
    for (size_t i = 0; i < expected.size(); ++i)
      EXPECT_TRUE(torch::equal(expected[i], actual[i])) << behavior << " parameter " << i;
    EXPECT_EQ(whole.self_play().elo(b), resumed.self_play().elo(b)) << behavior;
  }
  EXPECT_EQ(whole.self_play().learning_team_name(), resumed.self_play().learning_team_name());
  EXPECT_EQ(whole.parameters().serialize(), resumed.parameters().serialize());
  for (const std::string file : {"metrics/Hider.csv", "metrics/Seeker.csv", "metrics/episodes.csv"})
    EXPECT_EQ(metrics_without_time((dir_ / "hs_whole" / file).string()),
              metrics_without_time((dir_ / "hs_split" / file).string()))
        << file;
  // the summaries after the resume average what the uninterrupted run's do, the episodes and
  // updates since the last summary before the checkpoint too (lengths, losses, env metrics)
  for (const std::string behavior : {"Hider", "Seeker"}) {
    const auto expected = tensorboard_points(dir_ / "hs_whole" / behavior);
    const auto actual = tensorboard_points(dir_ / "hs_split" / behavior);
    ASSERT_GT(expected.size(), 4u) << behavior;
    ASSERT_EQ(expected.size(), actual.size()) << behavior;
    for (auto e = expected.begin(), a = actual.begin(); e != expected.end(); ++e, ++a) {
      EXPECT_EQ(e->first, a->first) << behavior;
      EXPECT_EQ(e->second, a->second) << behavior << " step " << e->first;
    }
  }
}

// The Echo behavior and lesson A of x (x = 0, ending after two episodes), to which the configs
// below add lessons B and C.
std::string echo_lesson_a() {
  return "behaviors:\n  Echo:\n    trainer_type: ppo\n"
         "    hyperparameters: {batch_size: 16, buffer_size: 64, num_epoch: 1}\n"
         "    network_settings: {hidden_units: 8, num_layers: 1}\n"
         "    max_steps: 400\n    summary_freq: 100000\n    checkpoint_interval: 100000\n"
         "environment_parameters:\n  x:\n    curriculum:\n"
         "      - name: A\n        value: 0\n"
         "        completion_criteria: {measure: metric, metric: value, threshold: -1, "
         "min_lesson_length: 2}\n";
}

// LessonEchoEnv with a curriculum on x measured by its episode metrics: lesson A ends after two
// episodes (any value), lesson B when an episode played in it reports x < 0.5, which only an
// episode begun in lesson A (x = 0) can.
RunConfig echo_curriculum_config(const std::string& second_metric,
                                  const std::string& second_extra = "",
                                  const std::string& second_threshold = "0",
                                  const std::string& last_value = "2") {
  std::ostringstream y;
  y << echo_lesson_a()
    << "      - name: B\n        value: 1\n"
    << "        completion_criteria: {measure: metric, metric: " << second_metric
    << ", threshold: " << second_threshold
    << ", min_lesson_length: 1, signal_smoothing: false" << second_extra << "}\n"
    << "      - name: C\n        value: " << last_value << "\n"
    << "env_settings: {env_id: LessonEchoEnv, num_envs: 3, seed: 0}\n";
  return load_run_config_from_string(y.str(), "echo.yaml");
}

TEST_F(TrainingRunTest, MetricLessonsCountOnlyEpisodesPlayedInTheLesson) {
  TrainingRun run(echo_curriculum_config("below_half"), options("echo"));
  run.train();
  // lesson A ended on its own episodes' metrics; when it did, episodes begun with x = 0 were
  // still running (instances last 3, 4 and 5 steps) and would have ended lesson B at once
  EXPECT_EQ(run.parameters().lesson_names().at("x"), "B");
  // only episodes with x = 1 were counted since
  EXPECT_FALSE(run.parameters().metric_buffer("below_half").empty());
  for (double v : run.parameters().metric_buffer("below_half")) EXPECT_EQ(v, 0.0);
  EXPECT_FALSE(run.parameters().metric_buffer("value").empty());
  for (double v : run.parameters().metric_buffer("value")) EXPECT_EQ(v, 1.0);
}

TEST_F(TrainingRunTest, ACollapsedLessonFallsBackAndTheLogSaysSo) {
  // lesson B's episodes report value 1; with threshold 5 B never ends
  const auto config = [](const std::string& extra) {
    return echo_curriculum_config("value", extra, "5");
  };
  // the control: without a fallback the run stays in B
  TrainingRun plain(config(""), options("echo_plain"));
  plain.train();
  EXPECT_EQ(plain.parameters().lesson_names().at("x"), "B");
  EXPECT_EQ(log_.str().find("back from"), std::string::npos) << log_.str();
  // a fallback at 1 over 2 episodes sends B back to A, which its own criteria end again
  TrainingRun run(config(", fallback_threshold: 1, fallback_length: 2"), options("echo_fallback"));
  run.train();
  EXPECT_NE(log_.str().find("Curriculum x: back from lesson 1 (B) to 0 (A): mean value 1 over "
                            "the last 2 episodes, at or below fallback_threshold 1"),
            std::string::npos)
      << log_.str();
  EXPECT_EQ(run.parameters().furthest_lessons().at("x"), 1);
  // metrics/lessons.csv has each change at its steps: the control's one completion, and here A's
  // completion, B's fallback at the mean 1, and so on, the steps never going back
  const auto changes = [&](const std::string& run_id) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream lines(file_contents(dir_ / run_id / "metrics" / "lessons.csv"));
    for (std::string line; std::getline(lines, line);) rows.push_back(split_csv_line(line));
    return rows;
  };
  const auto plain_rows = changes("echo_plain");
  ASSERT_EQ(plain_rows.size(), 2u);
  const std::vector<std::string> header = plain_rows[0];
  ASSERT_GE(header.size(), 8u);
  EXPECT_EQ(header[0], "total_steps");
  EXPECT_EQ(header[1], "elapsed_s");
  const std::vector<std::string> tail(header.end() - 5, header.end());
  EXPECT_EQ(tail, (std::vector<std::string>{"parameter", "from_lesson", "to_lesson", "change",
                                            "measure"}));
  const size_t p = header.size() - 5;
  EXPECT_EQ(std::vector<std::string>(plain_rows[1].begin() + p, plain_rows[1].end() - 1),
            (std::vector<std::string>{"x", "0", "1", "completed"}));
  const auto rows = changes("echo_fallback");
  ASSERT_GE(rows.size(), 3u);
  EXPECT_EQ(std::vector<std::string>(rows[2].begin() + p, rows[2].end()),
            (std::vector<std::string>{"x", "1", "0", "fell_back", "1"}));
  for (size_t r = 2; r < rows.size(); ++r)
    EXPECT_GE(std::stoll(rows[r][0]), std::stoll(rows[r - 1][0])) << r;
}

// StrategyEchoEnv's lessons A (x = 0), B (x = 1) and C (x = 2) as in echo_curriculum_config,
// lesson A also waiting for `strategy` to emerge.
RunConfig echo_after_emerged_config(const std::string& strategy) {
  std::string a = echo_lesson_a();
  a.replace(a.find("min_lesson_length: 2}"), 21,
            "min_lesson_length: 2, after_emerged: [" + strategy + "]}");
  std::ostringstream y;
  y << a << "      - name: B\n        value: 1\n"
    << "        completion_criteria: {measure: metric, metric: value, threshold: 0, "
    << "min_lesson_length: 1, signal_smoothing: false}\n"
    << "      - name: C\n        value: 2\n"
    << "env_settings: {env_id: StrategyEchoEnv, num_envs: 3, seed: 0}\n";
  return load_run_config_from_string(y.str(), "echo.yaml");
}

TEST_F(TrainingRunTest, ALessonAfterAStrategyWaitsUntilItEmerges) {
  // low_x emerges in lesson A's own episodes: A ends, and B and C follow
  TrainingRun run(echo_after_emerged_config("low_x"), options("echo_after_low"));
  run.train();
  EXPECT_EQ(run.parameters().lesson_names().at("x"), "C");
  EXPECT_NE(log_.str().find("Strategy low_x emerged"), std::string::npos) << log_.str();
  // high_x needs x = 2, which only lesson C plays: A met its threshold and never ends
  log_.str("");
  TrainingRun held(echo_after_emerged_config("high_x"), options("echo_after_high"));
  held.train();
  EXPECT_EQ(held.parameters().lesson_names().at("x"), "A");
  const std::string wait =
      "Curriculum x: lesson 0 (A) met its threshold and goes on until the strategy high_x has "
      "emerged (after_emerged)";
  const std::string log = log_.str();
  ASSERT_NE(log.find(wait), std::string::npos) << log;
  EXPECT_EQ(log.find(wait, log.find(wait) + 1), std::string::npos) << "said once: " << log;
}

TEST_F(TrainingRunTest, AnUnknownStrategyToWaitForIsAnErrorBeforeWriting) {
  expect_rejected_before_writing(
      echo_after_emerged_config("chasing"), options("echo_bad_strategy"),
      "echo.yaml: environment_parameters.x, lesson 'A': completion_criteria.after_emerged names "
      "the strategy 'chasing', which the environment does not declare (it declares: low_x, "
      "high_x)");
}

TEST_F(TrainingRunTest, UntilEmergedStopsOnceEveryNamedStrategyHasEmerged) {
  // low_x emerges within lesson A's first episodes (x = 0 from the start), long before the 400
  // steps of max_steps: the run stops there, with a last checkpoint and the policy exported
  TrainOptions opt = options("echo_until_low");
  opt.until_emerged = {"low_x"};
  TrainingRun run(echo_after_emerged_config("low_x"), opt);
  run.train();
  const Emergence& low = run.strategies().emergences().at(0);
  ASSERT_EQ(low.strategy, "low_x");
  ASSERT_GE(low.step, 0);
  EXPECT_LT(run.trainer(0).step(), 400);
  EXPECT_GE(run.trainer(0).step(), low.step);
  EXPECT_NE(log_.str().find("Stopping: low_x emerged (--until-emerged)."), std::string::npos)
      << log_.str();
  EXPECT_TRUE(fs::exists(dir_ / "echo_until_low" / "Echo.pt"));
  const TrainingStatus status = RunFolder(dir_.string(), "echo_until_low").read_status();
  EXPECT_TRUE(status.finished);
  EXPECT_FALSE(status.checkpoints.empty());
  // with high_x too, which lesson A (held there until high_x emerges) never plays, the run goes
  // on to max_steps
  log_.str("");
  TrainOptions both = options("echo_until_both");
  both.until_emerged = {"low_x", "high_x"};
  TrainingRun held(echo_after_emerged_config("high_x"), both);
  held.train();
  EXPECT_GE(held.strategies().emergences().at(0).step, 0);
  EXPECT_LT(held.strategies().emergences().at(1).step, 0);
  EXPECT_GE(held.trainer(0).step(), 400);
  EXPECT_EQ(log_.str().find("Stopping:"), std::string::npos) << log_.str();
}

TEST_F(TrainingRunTest, UntilEmergedNamingAStrategyTheEnvLacksIsAnErrorBeforeWriting) {
  TrainOptions opt = options("echo_until_bad");
  opt.until_emerged = {"shelter"};
  expect_rejected_before_writing(echo_after_emerged_config("low_x"), opt,
                                 "--until-emerged shelter: environment StrategyEchoEnv declares no "
                                 "strategy 'shelter' (it declares: low_x, high_x)");
}

TEST_F(TrainingRunTest, ALessonValueTheEnvRejectsIsAnErrorBeforeWriting) {
  // lesson C, reached only when A and B have ended, sets x = 99, which LessonEchoEnv rejects
  expect_rejected_before_writing(echo_curriculum_config("value", "", "0", "99"),
                                 options("echo_bad_lesson"),
                                 "echo.yaml: environment_parameters.x, lesson 'C': "
                                 "LessonEchoEnv: x must be at most 10, got 99");
}

// Lesson B of x moves x from 1 toward `end` by a staircase judged on the episodes' `value` (x
// itself, which LessonEchoEnv accepts up to 10) against `threshold`; lesson C sets x = 2.
RunConfig echo_staircase_config(const std::string& end, const std::string& threshold) {
  std::ostringstream y;
  y << echo_lesson_a()
    << "      - name: B\n        value: 1\n"
    << "        completion_criteria: {measure: metric, metric: value, threshold: " << threshold
    << ", min_lesson_length: 1}\n"
    << "        staircase: {parameter: x, end: " << end << ", step_up: 1, step_down: 1}\n"
    << "      - name: C\n        value: 2\n"
    << "env_settings: {env_id: LessonEchoEnv, num_envs: 3, seed: 0}\n";
  return load_run_config_from_string(y.str(), "echo.yaml");
}

TEST_F(TrainingRunTest, AStaircaseClimbsThroughItsLessonInARun) {
  // every episode in B reports its x (>= 1) above 0.5: x climbs 1, 2, ... to 4 and B ends
  TrainingRun run(echo_staircase_config("4", "0.5"), options("echo_staircase"));
  run.train();
  EXPECT_EQ(run.parameters().lesson_names().at("x"), "C");
  EXPECT_TRUE(run.parameters().staircase_values().empty());
  // the control: judged against 100 every episode steps back, x stays at its start and B goes on
  TrainingRun held(echo_staircase_config("4", "100"), options("echo_staircase_held"));
  held.train();
  EXPECT_EQ(held.parameters().lesson_names().at("x"), "B");
  EXPECT_EQ(held.parameters().staircase_values().at("x"), 1.0);
}

TEST_F(TrainingRunTest, AStaircaseEndTheEnvRejectsIsAnErrorBeforeWriting) {
  expect_rejected_before_writing(echo_staircase_config("99", "0.5"), options("echo_bad_staircase"),
                                 "echo.yaml: environment_parameters.x, lesson 'B': "
                                 "LessonEchoEnv: x must be at most 10, got 99");
}

TEST_F(TrainingRunTest, UnknownCurriculumMetricIsAnErrorBeforeWriting) {
  expect_rejected_before_writing(
      echo_curriculum_config("fort_rate"), options("echo_bad"),
      "echo.yaml: environment_parameters.x, lesson 'B': completion_criteria measures the episode "
      "metric 'fort_rate', which the environment does not report (it reports: below_half, value)");
}

TEST_F(TrainingRunTest, WritesTheRunFolder) {
  TrainingRun run(small_config("CartPole", "CartPole", 2500, 1000), options("folder"));
  run.train();
  const fs::path r = dir_ / "folder";
  EXPECT_TRUE(fs::exists(r / "configuration.yaml"));
  EXPECT_TRUE(fs::exists(r / "CartPole.pt"));
  EXPECT_TRUE(fs::exists(r / "metrics/CartPole.csv"));
  RunFolder folder(dir_.string(), "folder");
  auto status = folder.read_status();
  EXPECT_TRUE(status.finished);
  ASSERT_EQ(status.checkpoints.size(), 3u);  // boundaries at 1000, 2000 and the end
  for (const auto& c : status.checkpoints) EXPECT_TRUE(fs::exists(r / c.file)) << c.file;
  EXPECT_EQ(status.checkpoints.back().steps.at("CartPole"), run.trainer(0).step());
  // the resolved configuration reads back
  RunConfig saved = load_run_config((r / "configuration.yaml").string());
  EXPECT_EQ(saved.behaviors.at("CartPole").max_steps, 2500);
  // summaries were printed
  EXPECT_TRUE(std::regex_search(log_.str(), std::regex(R"(\[CartPole\] Step: 50[0-9]\. Time Elapsed: )")))
      << log_.str();
  EXPECT_NE(log_.str().find("Mean Reward:"), std::string::npos);
}

TEST_F(TrainingRunTest, ASavedRunLoadsTheCheckpointItIsToldOrTheNewest) {
  TrainingRun run(small_config("CartPole", "CartPole", 2500, 1000), options("pick"));
  run.train();
  const std::string path = (dir_ / "pick").string();
  SavedRun newest = load_saved_run(path);
  SavedRun first = load_saved_run(path, 1);
  EXPECT_EQ(fs::path(newest.checkpoint).filename(), "checkpoint-3.pt");
  EXPECT_EQ(fs::path(first.checkpoint).filename(), "checkpoint-1.pt");
  EXPECT_EQ(fs::path(load_saved_run(path, 3).checkpoint).filename(), "checkpoint-3.pt");
  // 1500 more steps of training moved the weights: the two are different networks
  const auto a = first.trainers[0]->network()->parameters();
  const auto b = newest.trainers[0]->network()->parameters();
  ASSERT_EQ(a.size(), b.size());
  bool differ = false;
  for (size_t i = 0; i < a.size(); ++i) differ = differ || !torch::equal(a[i], b[i]);
  EXPECT_TRUE(differ);
  // the newest is the one the run ended with
  const auto trained = parameters(run);
  for (size_t i = 0; i < b.size(); ++i) EXPECT_TRUE(torch::equal(b[i], trained[i])) << i;
  try {
    load_saved_run(path, 7);
    ADD_FAILURE() << "loaded a checkpoint the run does not have";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("has no checkpoint 7; it keeps 1 (CartPole 1"), std::string::npos) << what;
    EXPECT_NE(what.find(", 3 (CartPole 2"), std::string::npos) << what;
  }
}

TEST_F(TrainingRunTest, WritesTensorBoardEventsWithMlAgentsTags) {
  // self-play (ELO) and a curriculum (lesson) on Pursuit, whose episodes report metrics and
  // whose seekers train with MA-POCA (group reward, baseline loss)
  TrainingRun run(pursuit_curriculum_config(2000, 500), options("tb"));
  run.train();
  for (const std::string behavior : {"Seeker", "Hider"}) {
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(dir_ / "tb" / behavior))
      files.push_back(e.path().string());
    ASSERT_EQ(files.size(), 1u) << behavior;
    const auto events = tensorboard_reader::read_events(files[0]);
    ASSERT_GE(events.size(), 3u) << behavior;  // the version and at least two summaries
    EXPECT_EQ(events[0].file_version, "brain.Event:2");
    std::set<std::string> tags;
    int64_t last_step = 0;
    for (size_t i = 1; i < events.size(); ++i) {
      EXPECT_GT(events[i].step, last_step);
      last_step = events[i].step;
      for (const auto& [tag, value] : events[i].scalars) {
        tags.insert(tag);
        EXPECT_TRUE(std::isfinite(value)) << tag;
      }
    }
    const int b = run.trainer(0).behavior() == behavior ? 0 : 1;
    EXPECT_EQ(last_step, run.trainer(b).step());
    for (const char* tag :
         {"Environment/Cumulative Reward", "Environment/Episode Length", "Losses/Policy Loss",
          "Losses/Value Loss", "Policy/Entropy", "Policy/Learning Rate", "Self-play/ELO",
          "Environment/Lesson Number/level", "Environment/tag_rate"})
      EXPECT_TRUE(tags.count(tag)) << behavior << " " << tag;
    const bool poca = behavior == "Seeker";
    EXPECT_EQ(tags.count("Losses/Baseline Loss"), poca ? 1u : 0u) << behavior;
    EXPECT_EQ(tags.count("Environment/Group Cumulative Reward"), poca ? 1u : 0u) << behavior;
    // the last ELO written is the learner's rating at its last summary
    EXPECT_NEAR(events.back().scalars.at("Self-play/ELO"), run.self_play().elo(b), 1e-2);
  }
  // the table printed at the end names every behavior with its steps, the lesson and the files
  const std::string table = run.summary_table();
  for (int b = 0; b < 2; ++b) {
    std::string steps = std::to_string(run.trainer(b).step());
    if (steps.size() > 3) steps.insert(steps.size() - 3, ",");  // below 1,000,000
    EXPECT_TRUE(std::regex_search(
        table, std::regex("\\n  " + run.trainer(b).behavior() + " +(ppo|poca) +" + steps + " ")))
        << table;
  }
  EXPECT_NE(table.find("Lesson level: 1 (hard)"), std::string::npos) << table;
  EXPECT_NE(table.find("Policies: "), std::string::npos) << table;
  for (const char* file : {"Hider.pt", "Seeker.pt"})
    EXPECT_NE(table.find(" " + (dir_ / "tb" / file).string()), std::string::npos) << table;
  EXPECT_NE(table.find("TensorBoard: tensorboard --logdir " + dir_.string()), std::string::npos)
      << table;
}

TEST_F(TrainingRunTest, KeepsOnlyTheNewestCheckpoints) {
  TrainingRun run(small_config("CartPole", "CartPole", 5500, 1000), options("keep"));
  run.train();
  auto status = RunFolder(dir_.string(), "keep").read_status();
  ASSERT_EQ(status.checkpoints.size(), 3u);
  EXPECT_EQ(status.checkpoints.front().index, 4);
  int files = 0;
  for (auto& e : fs::directory_iterator(dir_ / "keep" / "checkpoints")) files += e.path().extension() == ".pt";
  EXPECT_EQ(files, 3);
}

// Files written while it lives may grow to `bytes` at most (as on a nearly full disk: a write past
// the limit fails with EFBIG instead of ending the process).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit saved_{};
  void (*old_handler_)(int) = nullptr;
};

TEST_F(TrainingRunTest, ACheckpointThatCannotBeWrittenStopsTrainingWithAnErrorAndLosesNothing) {
  {
    TrainingRun first(small_config("CartPole", "CartPole", 3000, 1000), options("full"));
    first.train(/*stop_after_boundaries=*/1);
  }
  const fs::path checkpoints = dir_ / "full" / "checkpoints";
  const auto first_size = fs::file_size(checkpoints / "checkpoint-1.pt");
  const std::string first_bytes = file_contents(checkpoints / "checkpoint-1.pt");
  auto opt = options("full");
  opt.resume = true;
  {
    TrainingRun resumed(small_config("CartPole", "CartPole", 3000, 1000), opt);
    FileSizeLimit limit(first_size / 2);
    try {
      resumed.train();
      ADD_FAILURE() << "training went on without its checkpoint";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("cannot write"), std::string::npos) << what;
      EXPECT_NE(what.find("checkpoint-2.pt"), std::string::npos) << what;
    }
  }
  // the first checkpoint is as it was, no partial file is left, and the run resumes from it
  EXPECT_EQ(file_contents(checkpoints / "checkpoint-1.pt"), first_bytes);
  EXPECT_FALSE(fs::exists(checkpoints / "checkpoint-2.pt.tmp"));
  EXPECT_FALSE(fs::exists(checkpoints / "checkpoint-2.pt"));
  ASSERT_EQ(RunFolder(dir_.string(), "full").read_status().checkpoints.size(), 1u);
  TrainingRun finished(small_config("CartPole", "CartPole", 3000, 1000), opt);
  finished.train();
  EXPECT_GE(finished.trainer(0).step(), 3000);
}

TEST_F(TrainingRunTest, AMetricsRowThatCannotBeWrittenStopsTrainingWithAnErrorAndLosesNothing) {
  {
    TrainingRun first(small_config("CartPole", "CartPole", 3000, 1000), options("rows"));
    first.train(/*stop_after_boundaries=*/1);
  }
  const fs::path metrics = dir_ / "rows" / "metrics" / "CartPole.csv";
  auto opt = options("rows");
  opt.resume = true;
  {
    TrainingRun resumed(small_config("CartPole", "CartPole", 3000, 1000), opt);
    const std::string before = file_contents(metrics);
    ASSERT_FALSE(before.empty());
    {
      // room for a few bytes, not for the next row (about 100): its write is cut off part way
      FileSizeLimit limit(fs::file_size(metrics) + 20);
      try {
        resumed.train();
        ADD_FAILURE() << "training went on without its metrics row";
      } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("cannot append to"), std::string::npos) << what;
        EXPECT_NE(what.find("CartPole.csv"), std::string::npos) << what;
      }
    }
    // no partial row is left behind
    EXPECT_EQ(file_contents(metrics), before);
  }
  TrainingRun finished(small_config("CartPole", "CartPole", 3000, 1000), opt);
  finished.train();
  EXPECT_GE(finished.trainer(0).step(), 3000);
}

TEST_F(TrainingRunTest, AResumeDropsAMetricsRowWhoseWriteWasCutOff) {
  {
    TrainingRun first(small_config("CartPole", "CartPole", 3000, 1000), options("cut"));
    first.train(/*stop_after_boundaries=*/1);
  }
  const fs::path metrics = dir_ / "cut" / "metrics" / "CartPole.csv";
  const std::string whole = file_contents(metrics);
  // as after a kill in the middle of writing the row of step 1024: its first two characters
  { std::ofstream(metrics, std::ios::app) << "10"; }
  auto opt = options("cut");
  opt.resume = true;
  { TrainingRun(small_config("CartPole", "CartPole", 3000, 1000), opt).train(1); }
  const std::string after = file_contents(metrics);
  ASSERT_EQ(after.substr(0, whole.size()), whole);
  std::istringstream lines(after);
  std::string line;
  std::getline(lines, line);
  const auto fields = std::count(line.begin(), line.end(), ',');
  int rows = 0;
  while (std::getline(lines, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), fields) << "row " << rows + 2 << ": " << line;
    ++rows;
  }
  EXPECT_GT(rows, int(std::count(whole.begin(), whole.end(), '\n')) - 1);  // rows were added

  // a row whose step is not a number is an error naming the file and line, and nothing changes
  { std::ofstream(metrics, std::ios::app) << "x1,2,3\n"; }
  const std::string garbled = file_contents(metrics);
  try {
    TrainingRun again(small_config("CartPole", "CartPole", 3000, 1000), opt);
    ADD_FAILURE() << "resumed over a garbled metrics file";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("CartPole.csv:"), std::string::npos) << what;
    EXPECT_NE(what.find("expected a step, got 'x1'"), std::string::npos) << what;
  }
  EXPECT_EQ(file_contents(metrics), garbled);
}

TEST_F(TrainingRunTest, AResumeKeepsTheRowsOfAMetricsFileWrittenBeforeColumnsWereAdded) {
  {
    TrainingRun first(small_config("CartPole", "CartPole", 3000, 1000), options("old"));
    first.train(/*stop_after_boundaries=*/1);
  }
  const fs::path metrics = dir_ / "old" / "metrics" / "CartPole.csv";
  // the file as a build before approx_kl and clip_fraction wrote it: their columns cut off
  auto drop_last_two = [](const std::string& line) {
    return line.substr(0, line.rfind(',', line.rfind(',') - 1));
  };
  std::istringstream lines(file_contents(metrics));
  std::string line, old_file;
  std::getline(lines, line);
  const std::string header = line;
  ASSERT_EQ(header.substr(header.size() - 24), ",approx_kl,clip_fraction");
  old_file += drop_last_two(line) + "\n";
  int old_rows = 0;
  while (std::getline(lines, line)) {
    old_file += drop_last_two(line) + "\n";
    ++old_rows;
  }
  ASSERT_GT(old_rows, 0);
  write_text(metrics, old_file);
  auto opt = options("old");
  opt.resume = true;
  { TrainingRun(small_config("CartPole", "CartPole", 3000, 1000), opt).train(); }
  std::istringstream after(file_contents(metrics));
  std::getline(after, line);
  EXPECT_EQ(line, header);
  // the kept rows first, padded with two empty fields, then the new rows with both measured
  int row = 0, padded = 0, measured = 0;
  while (std::getline(after, line)) {
    ++row;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), std::count(header.begin(), header.end(), ','))
        << "row " << row << ": " << line;
    if (line.substr(line.size() - 2) == ",,") {
      EXPECT_EQ(padded, row - 1) << "a padded row after a new one, row " << row << ": " << line;
      ++padded;
    } else {
      // approx_kl, the second field from the end: the second pass over a buffer moves the policy
      const size_t last = line.rfind(',');
      const size_t kl = line.rfind(',', last - 1) + 1;
      if (std::stod(line.substr(kl, last - kl)) > 0) ++measured;
      EXPECT_GE(std::stod(line.substr(last + 1)), 0.0) << "row " << row << ": " << line;
    }
  }
  EXPECT_GT(padded, 0);
  EXPECT_LE(padded, old_rows);
  EXPECT_GT(row, padded);
  EXPECT_GT(measured, 0);

  // a header that is not an older one is an error naming the file, and nothing changes
  write_text(metrics, "step,something_else\n1,2\n");
  try {
    TrainingRun again(small_config("CartPole", "CartPole", 3000, 1000), opt);
    ADD_FAILURE() << "resumed over a metrics file of another layout";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("CartPole.csv:1: the header is 'step,something_else'"), std::string::npos)
        << what;
  }
  EXPECT_EQ(file_contents(metrics), "step,something_else\n1,2\n");
}

TEST_F(TrainingRunTest, ExistingRunWithoutResumeOrForceTouchesNothing) {
  { TrainingRun(small_config("CartPole", "CartPole", 600, 1000), options("exists")).train(); }
  const auto status_file = dir_ / "exists" / "training_status.json";
  const auto before = fs::last_write_time(status_file);
  const std::string content = file_contents(status_file);
  EXPECT_THROW(TrainingRun(small_config("CartPole", "CartPole", 600, 1000), options("exists")), std::runtime_error);
  EXPECT_EQ(fs::last_write_time(status_file), before);
  EXPECT_EQ(file_contents(status_file), content);
  // --force starts over
  auto opt = options("exists");
  opt.force = true;
  TrainingRun forced(small_config("CartPole", "CartPole", 600, 1000), opt);
  EXPECT_EQ(RunFolder(dir_.string(), "exists").read_status().checkpoints.size(), 0u);
}

TEST_F(TrainingRunTest, EachSessionRecordsItsMachineAndAResumeElsewhereSaysSo) {
  const RunFolder folder(dir_.string(), "machine");
  {
    TrainingRun first(small_config("CartPole", "CartPole", 3000, 1000), options("machine"));
    first.train(/*stop_after_boundaries=*/1);
  }
  TrainingStatus status = folder.read_status();
  ASSERT_EQ(status.sessions.size(), 1u);
  EXPECT_EQ(status.sessions[0].steps.at("CartPole"), 0);
  EXPECT_TRUE(std::regex_match(status.sessions[0].started,
                               std::regex("\\d{4}-\\d{2}-\\d{2}T\\d{2}:\\d{2}:\\d{2}Z")));
  EXPECT_EQ(machine_difference(status.sessions[0].machine, current_machine()), "");
  const int64_t checkpoint_steps = status.checkpoints.back().steps.at("CartPole");
  // resumed on the same machine and build: a second session, and no note
  auto opt = options("machine");
  opt.resume = true;
  { TrainingRun(small_config("CartPole", "CartPole", 3000, 1000), opt).train(1); }
  EXPECT_EQ(log_.str().find("another machine"), std::string::npos);
  status = folder.read_status();
  ASSERT_EQ(status.sessions.size(), 2u);
  EXPECT_EQ(status.sessions[1].steps.at("CartPole"), checkpoint_steps);
  // as if the last session had run on another CPU with other kernels (this process's own may
  // be Prescott: OpenBLAS's fallback on a CPU it does not know, which only rlt itself replaces)
  const std::string other_kernels =
      current_machine().blas_kernels == "Prescott" ? "Haswell" : "Prescott";
  status.sessions.back().machine.cpu = "Other CPU";
  status.sessions.back().machine.blas_kernels = other_kernels;
  folder.write_status(status);
  log_.str("");
  { TrainingRun(small_config("CartPole", "CartPole", 3000, 1000), opt); }
  const std::string said = log_.str();
  EXPECT_NE(said.find("Note: resuming on another machine or build"), std::string::npos) << said;
  EXPECT_NE(said.find("CPU Other CPU -> " + current_machine().cpu), std::string::npos) << said;
  EXPECT_NE(said.find("BLAS kernels " + other_kernels + " -> "), std::string::npos) << said;
  EXPECT_EQ(folder.read_status().sessions.size(), 3u);
}

TEST_F(TrainingRunTest, StatusFilesFromBeforeSessionsStillRead) {
  fs::create_directories(dir_ / "old");
  std::ofstream(dir_ / "old" / "training_status.json")
      << "{\"run_id\": \"old\", \"finished\": true, \"lessons\": {}, \"elo\": {}, "
         "\"strategies\": {}, \"checkpoints\": []}\n";
  const TrainingStatus status = RunFolder(dir_.string(), "old").read_status();
  EXPECT_TRUE(status.finished);
  EXPECT_TRUE(status.sessions.empty());
}

TEST_F(TrainingRunTest, InitializeFromStartsWithTheOtherRunsWeightsAndFreshCounters) {
  TrainingRun source(small_config("Pendulum", "Pendulum", 1500, 1000, true), options("source"));
  source.train();
  auto opt = options("target");
  opt.initialize_from = "source";
  TrainingRun target(small_config("Pendulum", "Pendulum", 1500, 1000, true), opt);
  auto expected = parameters(source), actual = parameters(target);
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_TRUE(torch::equal(expected[i], actual[i])) << i;
  EXPECT_EQ(target.trainer(0).step(), 0);
  EXPECT_DOUBLE_EQ(target.trainer(0).normalizer()->count(), source.trainer(0).normalizer()->count());
  // a fresh run with the same seed starts elsewhere
  TrainingRun fresh(small_config("Pendulum", "Pendulum", 1500, 1000, true), options("fresh"));
  EXPECT_FALSE(torch::equal(parameters(fresh)[0], expected[0]));
  // a missing source run is an error
  opt.run_id = "target2";
  opt.initialize_from = "missing";
  EXPECT_THROW(TrainingRun(small_config("Pendulum", "Pendulum", 1500, 1000, true), opt), std::runtime_error);
}

// hyperparameters.discrete_beta sets the discrete branches' entropy bonus on its own: in
// MaskedChoice (two branches, a reward for the right option) the policy sharpens with no bonus
// and stays near uniform under a large one, and sharpens again when the large one moves to 0 over
// the run's first tenth (discrete_beta_end, discrete_beta_steps); the same bonus as beta, spelled
// out, trains exactly as leaving it out
TEST_F(TrainingRunTest, TheBranchesOwnEntropyBonusReachesTheLearner) {
  auto entropy_of = [&](const std::string& run_id, const std::string& discrete_beta,
                        float end = -1.0f) {
    RunConfig config = small_config("MaskedChoice", "MaskedChoice", 20000, 10000);
    Hyperparameters& hyper = config.behaviors.at("MaskedChoice").hyperparameters;
    hyper.learning_rate = 3e-3f;
    hyper.discrete_beta.reset();  // as a config that leaves it out, before its parser fills in beta
    if (!discrete_beta.empty()) hyper.discrete_beta = std::stof(discrete_beta);
    if (end >= 0.0f) {  // moving to `end` over the first tenth of the run
      hyper.discrete_beta_end = end;
      hyper.discrete_beta_steps = 2000;
    }
    TrainingRun run(config, options(run_id));
    run.train();
    // the entropy column of the last update's row
    const auto rows = metrics_without_time((dir_ / run_id / "metrics/MaskedChoice.csv").string());
    std::istringstream last(rows.back());
    std::string cell;
    for (int column = 0; column < 9; ++column) std::getline(last, cell, ',');  // 9th: entropy
    return std::stod(cell);
  };
  const double none = entropy_of("none", "0"), large = entropy_of("large", "1.0");
  EXPECT_GT(large, none + 0.15);  // measured: 1.17 against 0.86
  // the large bonus moved to 0 over the first 2,000 steps sharpens as no bonus does
  const double faded = entropy_of("faded", "1.0", 0.0f);
  EXPECT_LT(faded, large - 0.15) << "none " << none;
  EXPECT_EQ(entropy_of("default", ""), entropy_of("spelled_out", "0.005"));  // beta's own value
  EXPECT_EQ(metrics_without_time((dir_ / "default/metrics/MaskedChoice.csv").string()),
            metrics_without_time((dir_ / "spelled_out/metrics/MaskedChoice.csv").string()));
}

// normalize: true standardizes vector observations only; grid columns keep mean 0 and variance 1,
// so they reach the network as they are (ML-Agents normalizes vector observations only), over a
// resume too; normalize_grids: true standardizes them as well
TEST_F(TrainingRunTest, NormalizationLeavesGridObservationsAsTheyAre) {
  const auto config = [](int max_steps, bool grids_too = false) {
    std::ostringstream y;
    for (const char* b : {"Hider", "Seeker"})
      y << (b[0] == 'H' ? "behaviors:\n" : "") << "  " << b << ":\n    trainer_type: ppo\n"
        << "    hyperparameters: {batch_size: 64, buffer_size: 128, num_epoch: 1}\n"
        << "    network_settings: {hidden_units: 16, num_layers: 1, normalize: true, "
        << "normalize_grids: " << (grids_too ? "true" : "false") << "}\n"
        << "    time_horizon: 32\n    max_steps: " << max_steps << "\n    summary_freq: 1000\n";
    y << "env_settings: {env_id: HideAndSeek, num_envs: 1, seed: 5, params: {level: 2}}\n";
    return load_run_config_from_string(y.str(), "grids.yaml");
  };
  // grid columns at mean 0 and variance 1, and some vector columns moved
  const auto expect_grids_pass = [](TrainingRun& run) {
    const RunningNormalizer& n = *run.trainer(0).normalizer();
    ASSERT_GT(n.count(), 0.0);
    int column = 0, vector_moved = 0;
    for (const auto& o : run.trainer(0).spec().observations) {
      for (int i = 0; i < o.size(); ++i, ++column) {
        if (o.kind == ObservationKind::kGrid) {
          ASSERT_EQ(n.mean()[column], 0.0) << o.name << " " << i;
          ASSERT_EQ(n.variance()[column], 1.0) << o.name << " " << i;
        } else {
          vector_moved += n.mean()[column] != 0.0;
        }
      }
    }
    EXPECT_GT(vector_moved, 10);
  };
  TrainingRun run(config(200), options("grids"));
  run.train();
  expect_grids_pass(run);
  // and so they stay over a resume
  auto opt = options("grids");
  opt.resume = true;
  TrainingRun resumed(config(400), opt);
  const double count = resumed.trainer(0).normalizer()->count();
  resumed.train();
  EXPECT_GT(resumed.trainer(0).normalizer()->count(), count);
  expect_grids_pass(resumed);
  // normalize_grids: true standardizes them with the rest
  TrainingRun both(config(200, true), options("grids_too"));
  both.train();
  const RunningNormalizer& n = *both.trainer(0).normalizer();
  int column = 0, grid_moved = 0;
  for (const auto& o : both.trainer(0).spec().observations)
    for (int i = 0; i < o.size(); ++i, ++column)
      grid_moved += o.kind == ObservationKind::kGrid && n.mean()[column] != 0.0;
  EXPECT_GT(grid_moved, 10);
}

TEST_F(TrainingRunTest, UnknownBehaviorOrParameterIsAnErrorBeforeWriting) {
  EXPECT_THROW(TrainingRun(small_config("CartPole", "Cartpole", 600, 1000), options("bad")), std::invalid_argument);
  auto config = small_config("CartPole", "CartPole", 600, 1000);
  config.environment_parameters["gravity"] = 3;
  EXPECT_THROW(TrainingRun(config, options("bad")), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
  // --param of a parameter that a lesson's other_parameters sets names the clash
  config = small_config("CartPole", "CartPole", 600, 1000);
  Lesson only;
  only.name = "only";
  only.other_parameters["offset"] = SamplerSettings::constant(0.f);
  config.environment_parameters["level"].curriculum = {only};
  auto opt = options("bad");
  opt.params["offset"] = 1.f;
  expect_rejected_before_writing(config, opt, "--param offset");
}

// Red and Blue take turns; Blue's turns play with x = 7, Red's with env_settings' x = 2.
// `curriculum`: an environment_parameters block, if any; `team_change`: both behaviors' turns.
RunConfig turn_config(const std::string& blue_turn, const std::string& curriculum = "",
                      int team_change = 300) {
  std::ostringstream y;
  y << "default_settings:\n"
    << "  trainer_type: ppo\n"
    << "  hyperparameters: {batch_size: 32, buffer_size: 128, num_epoch: 1}\n"
    << "  network_settings: {hidden_units: 8, num_layers: 1}\n"
    << "  time_horizon: 16\n  max_steps: 1200\n  summary_freq: 100000\n  checkpoint_interval: 100000\n"
    << "  self_play: {save_steps: 100, team_change: " << team_change << ", swap_steps: 50, window: 2}\n"
    << "behaviors:\n  Red: {}\n"
    << "  Blue:\n    self_play: {save_steps: 100, team_change: " << team_change
    << ", swap_steps: 50, window: 2,\n"
    << "                turn_parameters: {" << blue_turn << "}}\n"
    << "env_settings: {env_id: TurnEchoEnv, num_envs: 3, seed: 2, params: {x: 2}}\n"
    << curriculum;
  return load_run_config_from_string(y.str(), "turns.yaml");
}

TEST_F(TrainingRunTest, TurnParametersHoldWhileTheirBehaviorLearns) {
  auto opt = options("turns");
  TrainingRun* running = nullptr;
  std::map<std::string, std::map<float, int>> x_by_learner;  // learning team at the end -> x -> episodes
  opt.on_env_episode = [&](const EpisodeMetrics& m) {
    const std::string team = running->self_play().learning_team_name();
    ++x_by_learner[team.substr(0, team.find(':'))][m.at("x")];
  };
  TrainingRun run(turn_config("x: 7"), opt);
  running = &run;
  run.train();
  EXPECT_EQ(run.trainer(0).step() >= 1200 && run.trainer(1).step() >= 1200, true);
  // a turn's episodes play its setting; only those begun before a change (at most one per
  // instance and change, four changes in 2400 steps of turns of 300) end in the other turn
  auto& blue = x_by_learner["Blue"];
  auto& red = x_by_learner["Red"];
  EXPECT_GT(blue[7.f], 100);
  EXPECT_GT(red[2.f], 100);
  EXPECT_LE(blue[2.f] + red[7.f], 3 * 8);
  EXPECT_EQ(blue.size() + red.size(), 4u) << "x took values other than 2 and 7";
}

// A trajectory never spans two turns: when the learning team changes, the team that stops
// learning ends its running trajectories there (bootstrapped from where they stopped), rather than
// keeping them open until it learns again and appending another episode's steps to them. A turn
// of team_change 100 ends after 34 decisions in each of the 3 instances (102 in all), and an
// episode is 4 decisions: every other change falls two decisions into an episode.
TEST_F(TrainingRunTest, TheTeamThatStopsLearningEndsItsTrajectoriesAtTheChange) {
  auto opt = options("turn_trajectories");
  TrainingRun* running = nullptr;
  int checked = 0;
  opt.on_env_episode = [&](const EpisodeMetrics&) {
    const SelfPlay& sp = running->self_play();
    for (int b = 0; b < 2; ++b) {
      if (sp.learns(b)) continue;
      ASSERT_EQ(running->trainer(b).open_steps(), 0)
          << running->trainer(b).behavior() << " kept steps of its last turn open";
      ++checked;
    }
  };
  TrainingRun run(turn_config("x: 7", "", 100), opt);
  running = &run;
  run.train();
  EXPECT_GT(run.self_play().team_changes(), 10);
  EXPECT_GT(checked, 100);
}

// A lesson measured on an episode metric for one behavior counts only the episodes of that
// behavior's turns: Blue's turns play x = 7 (its turn_parameters), which says nothing of how Red
// does in its own setting (x = 2). A criterion that names no behavior counts both.
TEST_F(TrainingRunTest, MetricLessonsOfABehaviorCountOnlyItsTurns) {
  const std::string lessons =
      "environment_parameters:\n  level:\n    curriculum:\n"
      "      - name: red\n        value: 0\n"
      "        completion_criteria: {behavior: Red, measure: metric, metric: x, threshold: 100,"
      " min_lesson_length: 1000}\n"
      "      - name: anyone\n        value: 1\n"
      "        completion_criteria: {measure: metric, metric: x, threshold: 100,"
      " min_lesson_length: 1000}\n"
      "      - name: last\n        value: 2\n";
  TrainingRun run(turn_config("x: 7", lessons), options("turn_lessons"));
  run.train();
  const std::vector<double> red = run.parameters().metric_buffer("x", "Red");
  const std::vector<double> all = run.parameters().metric_buffer("x");
  EXPECT_GT(red.size(), 100u);
  for (double x : red) ASSERT_EQ(x, 2.0) << "an episode of Blue's turns was counted for Red";
  EXPECT_GT(std::count(all.begin(), all.end(), 7.0), 100);
  EXPECT_GT(std::count(all.begin(), all.end(), 2.0), 100);
  // the episodes that ended in a turn other than the one they began in, and only they, are in
  // neither turn's count
  EXPECT_LE(all.size() - red.size() - size_t(std::count(all.begin(), all.end(), 7.0)), 3u * 8u);
}

// A lesson's behavior_max_steps: Blue stops at its own 300 steps while Red goes on to 1200; the
// lesson Red's progress reaches at 0.5 gives Blue a budget of 900, and Blue takes turns again from
// then on. Without the budget Blue stays at its 300; with --max-steps the command line caps both,
// with --max-steps Blue=N Blue alone.
TEST_F(TrainingRunTest, ALessonsStepBudgetLetsAFinishedBehaviorLearnAgain) {
  auto lessons = [](const std::string& budget) {
    return "environment_parameters:\n  level:\n    curriculum:\n"
           "      - name: first\n        value: 0\n"
           "        completion_criteria: {behavior: Red, measure: progress, threshold: 0.5}\n"
           "      - name: second\n        value: 1\n" +
           budget;
  };
  auto config = [&](const std::string& budget) {
    RunConfig c = turn_config("x: 7", lessons(budget));
    c.behaviors.at("Blue").max_steps = 300;
    return c;
  };
  auto opt = options("budget");
  TrainingRun* running = nullptr;
  int64_t red_when_blue_went_on = -1;  // Red's steps when Blue was first at 400 steps
  opt.on_episode = [&](int b, int64_t steps, float) {
    if (running->trainer(b).behavior() == "Blue" && steps >= 400 && red_when_blue_went_on < 0)
      red_when_blue_went_on = running->trainer(1 - b).step();
  };
  TrainingRun run(config("        behavior_max_steps: {Blue: 900}\n"), opt);
  running = &run;
  const int blue = run.trainer(0).behavior() == "Blue" ? 0 : 1;
  EXPECT_EQ(run.trainer(blue).config().max_steps, 300);
  run.train();
  EXPECT_EQ(run.parameters().lesson_names().at("level"), "second");
  EXPECT_EQ(run.trainer(blue).config().max_steps, 900);
  EXPECT_GE(run.trainer(blue).step(), 900);
  EXPECT_LT(run.trainer(blue).step(), 900 + 300);
  EXPECT_GE(run.trainer(1 - blue).step(), 1200);
  EXPECT_GE(red_when_blue_went_on, 600) << "Blue learned past 300 before the lesson";

  TrainingRun without(config(""), options("no_budget"));
  without.train();
  EXPECT_EQ(without.parameters().lesson_names().at("level"), "second");
  EXPECT_LT(without.trainer(blue).step(), 300 + 300);

  auto capped = options("capped");
  capped.max_steps = 600;
  TrainingRun cap(config("        behavior_max_steps: {Blue: 900}\n"), capped);
  cap.train();
  EXPECT_EQ(cap.trainer(blue).config().max_steps, 600);
  EXPECT_LT(cap.trainer(blue).step(), 600 + 300);

  // --max-steps Blue=500 holds Blue to 500 over the lesson's 900 and leaves Red its own 1200
  auto named = options("named");
  named.behavior_max_steps = {{"Blue", 500}};
  TrainingRun one(config("        behavior_max_steps: {Blue: 900}\n"), named);
  one.train();
  EXPECT_EQ(one.parameters().lesson_names().at("level"), "second");
  EXPECT_EQ(one.trainer(blue).config().max_steps, 500);
  EXPECT_GE(one.trainer(blue).step(), 500);
  EXPECT_LT(one.trainer(blue).step(), 500 + 300);
  EXPECT_EQ(one.trainer(1 - blue).config().max_steps, 1200);
  EXPECT_GE(one.trainer(1 - blue).step(), 1200);
}

TEST_F(TrainingRunTest, BadTurnParametersAreErrorsBeforeWriting) {
  expect_rejected_before_writing(
      turn_config("y: 1"), options("bad_turn"),
      "behaviors.Blue.self_play.turn_parameters: environment 'TurnEchoEnv' has no parameter 'y'");
  auto opt = options("bad_turn");
  opt.params["x"] = 1.f;
  expect_rejected_before_writing(
      turn_config("x: 7"), opt,
      "--param x: turns.yaml sets it in behaviors.Blue.self_play.turn_parameters");
}

// a bad number at decision `at` of kind `what` stops training; earlier checkpoints stay loadable
void expect_bad_number(TrainingRunTest* t, RunConfig config, TrainOptions opt, int what,
                       const std::string& expected) {
  config.env_settings.num_envs = 1;
  config.env_settings.params = {{"bad_step", 2500.f}, {"what", float(what)}};
  BadNumberEnv::restart_count();
  TrainingRun run(config, opt);
  try {
    run.train();
    ADD_FAILURE() << "training went on through a bad number";
  } catch (const BadNumberError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
  RunFolder folder(opt.results_dir, opt.run_id);
  auto status = folder.read_status();
  EXPECT_FALSE(status.finished);
  ASSERT_EQ(status.checkpoints.size(), 2u);  // boundaries at 1000 and 2000
  SavedRun saved = load_saved_run(folder.path());
  for (auto& p : saved.trainers[0]->network()->parameters())
    EXPECT_TRUE(torch::isfinite(p).all().item<bool>());
}

TEST_F(TrainingRunTest, NanObservationStopsTrainingNamingItsSource) {
  expect_bad_number(this, small_config("BadNumberEnv", "Agent", 100000, 1000), options("nan_obs"), 0,
                    "environment BadNumberEnv, instance 0, behavior Agent, agent 0");
  expect_bad_number(this, small_config("BadNumberEnv", "Agent", 100000, 1000), options("nan_obs2"), 0,
                    "observation 'state'[0] is nan");
}

TEST_F(TrainingRunTest, NanRewardStopsTraining) {
  expect_bad_number(this, small_config("BadNumberEnv", "Agent", 100000, 1000), options("nan_reward"), 1,
                    "reward[0] is nan");
}

TEST_F(TrainingRunTest, InfiniteLossStopsTraining) {
  expect_bad_number(this, small_config("BadNumberEnv", "Agent", 100000, 1000), options("inf_loss"), 2,
                    "behavior Agent, update");
}

}  // namespace
}  // namespace rlt
