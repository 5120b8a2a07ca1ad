// The `rlt` command line, run as a separate process: help and usage errors (exit 2), configuration
// errors naming the file and key path without creating the results dir, run-folder protection
// (existing run, missing resume), and a short real train -> eval -> export -> bench sequence.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#ifndef RLT_BINARY
#error "RLT_BINARY must name the rlt executable"
#endif
#ifndef RLT_SOURCE_DIR
#error "RLT_SOURCE_DIR must name the source tree"
#endif

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code = -1;
  std::string out, err;
};

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

// text of configs/cartpole_ppo.yaml with `from` replaced by `to` (which must occur)
std::string cartpole_config(const std::string& from = "", const std::string& to = "") {
  std::string text = read_file(fs::path(RLT_SOURCE_DIR) / "configs/cartpole_ppo.yaml");
  if (!from.empty()) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  return text;
}

class RltCliTest : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("rlt_cli_test_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }

  // runs `rlt ARGS` (ARGS already quoted as needed) in `cwd` (default: the current directory),
  // capturing stdout and stderr
  static Result rlt(const std::string& args, const fs::path& cwd = {}) {
    static int counter = 0;
    const fs::path out = root_ / ("out" + std::to_string(counter) + ".txt");
    const fs::path err = root_ / ("err" + std::to_string(counter++) + ".txt");
    const std::string cd = cwd.empty() ? "" : "cd " + quote(cwd.string()) + " && ";
    const std::string command =
        cd + RLT_BINARY + " " + args + " > " + quote(out.string()) + " 2> " + quote(err.string());
    const int status = std::system(command.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_file(out);
    r.err = read_file(err);
    return r;
  }

  static std::string config_file(const std::string& name, const std::string& text) {
    const fs::path path = root_ / name;
    write_file(path, text);
    return path.string();
  }

  // a run trained once for the tests that need one: 2000 CartPole steps
  static const fs::path& trained_run() {
    static fs::path run;
    if (!run.empty()) return run;
    std::string text = cartpole_config("summary_freq: 50000", "summary_freq: 500");
    const auto at = text.find("checkpoint_interval: 100000");
    text.replace(at, 27, "checkpoint_interval: 1000");
    const std::string config = config_file("short.yaml", text);
    const fs::path results = root_ / "results";
    Result r = rlt("train " + quote(config) + " --max-steps 2000 --threads 1 --run-id short" +
                   " --results-dir " + quote(results.string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    run = results / "short";
    return run;
  }

  static fs::path root_;
};

fs::path RltCliTest::root_;

TEST_F(RltCliTest, HelpListsCommands) {
  Result r = rlt("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* command : {"train", "eval", "export", "envs", "bench"})
    EXPECT_NE(r.out.find(std::string("  ") + command), std::string::npos) << command;
}

TEST_F(RltCliTest, EachCommandHasHelp) {
  for (const char* command : {"train", "eval", "export", "envs", "bench"}) {
    Result r = rlt(std::string(command) + " --help");
    EXPECT_EQ(r.exit_code, 0) << command;
    EXPECT_NE(r.out.find("Usage:"), std::string::npos) << command << ": " << r.out;
    EXPECT_NE(r.out.find(std::string("rlt ") + command), std::string::npos) << command;
  }
}

TEST_F(RltCliTest, UnknownCommandOrFlagIsAUsageError) {
  Result r = rlt("frobnicate");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown command 'frobnicate'"), std::string::npos) << r.err;
  r = rlt("train x.yaml --bogus-flag 3");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown option --bogus-flag"), std::string::npos) << r.err;
  r = rlt("eval somewhere --episodes");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--episodes needs a value"), std::string::npos) << r.err;
  r = rlt("envs --verbose");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown option --verbose"), std::string::npos) << r.err;
}

TEST_F(RltCliTest, ConfigErrorsNameFileAndKeyAndWriteNothing) {
  struct Bad {
    std::string name, from, to, key_path, problem;
  };
  const std::vector<Bad> cases = {
      {"unknown_key", "    max_steps: 500000", "    max_steps: 500000\n    max_stpes: 3",
       "behaviors.CartPole", "unknown key 'max_stpes'"},
      {"wrong_type", "num_epoch: 4", "num_epoch: four",
       "behaviors.CartPole.hyperparameters.num_epoch", "four"},
      {"out_of_range", "epsilon: 0.2", "epsilon: 1.5", "behaviors.CartPole.hyperparameters.epsilon",
       "1.5"},
      {"unknown_env", "env_id: CartPole", "env_id: CartPol", "env_settings.env_id", "CartPol"},
      {"unknown_behavior", "  CartPole:\n", "  CartPoles:\n", "behaviors.CartPoles", "CartPoles"},
  };
  for (const Bad& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string config = config_file(c.name + ".yaml", cartpole_config(c.from, c.to));
    const fs::path results = root_ / ("results_" + c.name);
    Result r = rlt("train " + quote(config) + " --results-dir " + quote(results.string()));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(config), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.key_path + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.problem), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(results)) << results;
  }
}

TEST_F(RltCliTest, EnvsListsBuiltinEnvironments) {
  Result r = rlt("envs");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* env : {"CartPole", "Pendulum", "HybridReach", "MaskedChoice"})
    EXPECT_NE(r.out.find(std::string(env) + " (at most "), std::string::npos) << env << r.out;
}

TEST_F(RltCliTest, TrainWritesTheRunFolder) {
  const fs::path& run = trained_run();
  EXPECT_TRUE(fs::is_regular_file(run / "configuration.yaml"));
  EXPECT_TRUE(fs::is_regular_file(run / "training_status.json"));
  EXPECT_TRUE(fs::is_regular_file(run / "CartPole.pt"));
  EXPECT_GT(fs::file_size(run / "CartPole.pt"), 0u);
  int checkpoints = 0;
  for (const auto& entry : fs::directory_iterator(run / "checkpoints"))
    checkpoints += entry.path().extension() == ".pt";
  EXPECT_GE(checkpoints, 1);
  const std::string status = read_file(run / "training_status.json");
  EXPECT_NE(status.find("\"finished\": true"), std::string::npos) << status;
  EXPECT_NE(status.find("checkpoints/"), std::string::npos) << status;
  // the resolved configuration records the overrides
  const std::string config = read_file(run / "configuration.yaml");
  EXPECT_NE(config.find("max_steps: 2000"), std::string::npos) << config;
  // metrics: a header and at least one row per update
  std::ifstream metrics(run / "metrics/CartPole.csv");
  std::string header, row;
  ASSERT_TRUE(std::getline(metrics, header));
  EXPECT_EQ(header.rfind("step,", 0), 0u) << header;
  int rows = 0;
  while (std::getline(metrics, row)) rows += !row.empty();
  EXPECT_GE(rows, 1);
}

TEST_F(RltCliTest, PrintConfigShowsTheLayeredConfigurationAndTrainsNothing) {
  const fs::path folder = root_ / "print_config";
  fs::create_directories(folder);
  write_file(folder / "base.yaml", cartpole_config());
  write_file(folder / "child.yaml",
             "base_config: base.yaml\nbehaviors:\n  CartPole:\n    max_steps: 777\n");
  Result r = rlt("train child.yaml --print-config", folder);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("max_steps: 777"), std::string::npos) << r.out;  // the child's
  EXPECT_NE(r.out.find("env_id: CartPole"), std::string::npos) << r.out;  // the base's
  EXPECT_EQ(r.out.find("base_config"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(folder / "results"));  // nothing trained
  // what it prints is a configuration of its own, read back to the same text
  write_file(folder / "printed.yaml", r.out);
  EXPECT_EQ(rlt("train printed.yaml --print-config", folder).out, r.out);
  // options it would not apply are an error naming them
  r = rlt("train child.yaml --print-config --seed 3", folder);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--print-config takes CONFIG alone, not --seed"), std::string::npos) << r.err;
  r = rlt("train missing.yaml --print-config", folder);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("missing.yaml"), std::string::npos) << r.err;
}

TEST_F(RltCliTest, ExistingRunIdWithoutResumeOrForceTouchesNothing) {
  const fs::path& run = trained_run();
  auto snapshot = [&] {
    std::map<std::string, std::pair<fs::file_time_type, std::string>> files;
    for (const auto& e : fs::recursive_directory_iterator(run))
      if (e.is_regular_file())
        files[e.path().string()] = {fs::last_write_time(e.path()), read_file(e.path())};
    return files;
  };
  const auto before = snapshot();
  ASSERT_FALSE(before.empty());
  const std::string config = config_file("again.yaml", cartpole_config());
  Result r = rlt("train " + quote(config) + " --max-steps 2000 --threads 1 --run-id short" +
                 " --results-dir " + quote(run.parent_path().string()));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("already exists"), std::string::npos) << r.err;
  EXPECT_TRUE(before == snapshot()) << "the existing run changed";
}

TEST_F(RltCliTest, ResumeOfAMissingRunIsAnError) {
  const std::string config = config_file("resume.yaml", cartpole_config());
  const fs::path results = root_ / "results_resume";
  Result r = rlt("train " + quote(config) + " --resume --run-id nothing --results-dir " +
                 quote(results.string()));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("cannot resume"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(results / "nothing"));
}

TEST_F(RltCliTest, EvalPrintsOneJsonLine) {
  const fs::path& run = trained_run();
  Result r = rlt("eval " + quote(run.string()) + " --episodes 3 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_FALSE(r.out.empty());
  EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << r.out;
  const std::string number = R"((-?[0-9][0-9.eE+-]*))";
  std::smatch m;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(^\{"behavior":"CartPole",)")));
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"("episodes":3[,}])")));
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"mean_return\":" + number))) << r.out;
  // CartPole pays 1 per step, so any episode returns at least 1
  EXPECT_GE(std::stod(m[1]), 1.0);
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"std_return\":" + number))) << r.out;
  EXPECT_GE(std::stod(m[1]), 0.0);
  EXPECT_EQ(r.out.back(), '\n');
  EXPECT_EQ(r.out[r.out.size() - 2], '}');
}

TEST_F(RltCliTest, EvalPlaysTheCheckpointItIsTold) {
  const fs::path& run = trained_run();
  Result r = rlt("eval " + quote(run.string()) + " --checkpoint 1 --episodes 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(^\{"behavior":"CartPole",.*"episodes":2[,}])")))
      << r.out;
  // a number the run does not keep names the ones it does
  r = rlt("eval " + quote(run.string()) + " --checkpoint 99 --episodes 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("has no checkpoint 99; it keeps 1 (CartPole "), std::string::npos) << r.err;
  r = rlt("eval " + quote(run.string()) + " --checkpoint last --episodes 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--checkpoint: expected an integer, got 'last'"), std::string::npos) << r.err;
  r = rlt("eval --env CartPole --checkpoint 1 --episodes 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--checkpoint N picks a checkpoint of RUN_DIR"), std::string::npos) << r.err;
}

TEST_F(RltCliTest, ExportRewritesThePolicy) {
  const fs::path& run = trained_run();
  const fs::path policy = run / "CartPole.pt";
  ASSERT_TRUE(fs::exists(policy));
  const auto old_time = fs::file_time_type::clock::now() - std::chrono::hours(24 * 365);
  fs::last_write_time(policy, old_time);
  const std::string before = read_file(policy);
  Result r = rlt("export " + quote(run.string()));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("CartPole.pt"), std::string::npos) << r.out;
  EXPECT_GT(fs::last_write_time(policy), old_time);
  EXPECT_GT(fs::file_size(policy), 0u);
  EXPECT_FALSE(fs::exists(policy.string() + ".tmp"));
}

TEST_F(RltCliTest, BenchTrainReportsRates) {
  // run in an empty folder: the config's run id and default results dir must not appear there
  const fs::path cwd = root_ / "bench_cwd";
  fs::create_directories(cwd);
  Result r = rlt("bench train " + quote(config_file("bench.yaml", cartpole_config())) +
                     " --steps 2000 --threads 1 --json",
                 cwd);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string number = R"(([0-9][0-9.eE+-]*))";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"env_steps_per_s\":" + number))) << r.out;
  EXPECT_GT(std::stod(m[1]), 0.0);
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"agent_steps_per_s\":" + number))) << r.out;
  EXPECT_GT(std::stod(m[1]), 0.0);
  // one behavior: its own update time is all of the updates' time
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"update_s\":" + number))) << r.out;
  const double update_s = std::stod(m[1]);
  EXPECT_GT(update_s, 0.0);
  const std::regex behavior_update(R"("behaviors":\{"[A-Za-z]+":\{"update_s":)" + number +
                                   R"(,"learner_gflops":)");
  ASSERT_TRUE(std::regex_search(r.out, m, behavior_update)) << r.out;
  EXPECT_DOUBLE_EQ(std::stod(m[1]), update_s) << r.out;
  EXPECT_TRUE(fs::is_empty(cwd)) << "a benchmark wrote a run folder";
}

// a number after "key": in a JSON line, or NaN
double json_value(const std::string& text, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex("\"" + key + R"(":(-?[0-9][0-9.eE+-]*))")))
    return std::nan("");
  return std::stod(m[1]);
}

// issue 4: the scripted policies prove the mechanics, through `rlt eval --env ... --json`
TEST_F(RltCliTest, ScriptedHiderClosesTheDoorwayAtLevelOne) {
  Result r = rlt("eval --env HideAndSeek --policy Hider=scripted --policy Seeker=still"
                 " --param level=1 --episodes 20 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"policy\":\"scripted\""), std::string::npos) << r.out;
  EXPECT_GE(json_value(r.out, "fort_rate"), 0.8) << r.out;
  EXPECT_GE(json_value(r.out, "openings_closed"), 0.8) << r.out;
}

TEST_F(RltCliTest, ScriptedSeekerTagsAStillHider) {
  Result r = rlt("eval --env HideAndSeek --policy Seeker=scripted --policy Hider=still"
                 " --param level=1 --episodes 20 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GE(json_value(r.out, "tag_rate"), 0.8) << r.out;
  // and random seekers rarely do: the scripted result is the policy's, not the env's
  Result control = rlt("eval --env HideAndSeek --policy Hider=still --param level=1"
                       " --episodes 20 --json");
  ASSERT_EQ(control.exit_code, 0) << control.err;
  EXPECT_LT(json_value(control.out, "tag_rate"), 0.3) << control.out;
}

TEST_F(RltCliTest, EvalRecordsEpisodesAsJson) {
  const fs::path file = root_ / "replay.json";
  Result r = rlt("eval --env HideAndSeek --policy Hider=scripted --policy Seeker=scripted"
                 " --param level=1 --param episode_frames=1500 --episodes 2 --num-envs 1 --record " +
                 quote(file.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_file(file);
  ASSERT_EQ(text.rfind("{\"format\":\"rlt-recording\",\"version\":2,\"episodes\":[", 0), 0u)
      << text.substr(0, 200);
  EXPECT_EQ(text.substr(text.size() - 3), "]}\n");
  // two episodes, with bodies of every kind there is at level 1, and the hider's events
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n') > 1500, true);
  size_t episodes = 0;
  for (size_t at = 0; (at = text.find("\"env\":\"HideAndSeek\"", at)) != std::string::npos; ++at)
    ++episodes;
  EXPECT_EQ(episodes, 2u);
  for (const char* kind : {"\"kind\":\"wall\"", "\"kind\":\"prop\"", "\"kind\":\"hider\"",
                           "\"kind\":\"seeker\"", "\"type\":\"grab\"", "\"type\":\"lock\"",
                           "\"type\":\"closed\"", "\"type\":\"prep_end\""})
    EXPECT_NE(text.find(kind), std::string::npos) << kind;
  // version 2: the drones' vision cones, the openings (level 1: the first doorway open), rewards
  EXPECT_NE(text.find("\"vision\":{\"cone_degrees\":"), std::string::npos);
  EXPECT_NE(text.find("\"openings\":[\n{\"kind\":\"doorway\",\"centre\":[0,"), std::string::npos);
  EXPECT_NE(text.find("\"open\":true}"), std::string::npos);
  EXPECT_NE(text.find("\"open\":false}"), std::string::npos);
  EXPECT_NE(text.find(",\"rewards\":["), std::string::npos);
  EXPECT_NE(text.find(",\"group_rewards\":["), std::string::npos);
}

TEST_F(RltCliTest, EvalNamesBadPoliciesAndParameters) {
  Result r = rlt("eval --env HideAndSeek --policy Runner=random --episodes 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no behavior 'Runner'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Hider, Seeker"), std::string::npos) << r.err;
  r = rlt("eval --env HideAndSeek --param levle=2 --episodes 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("levle"), std::string::npos) << r.err;
  r = rlt("eval --env HideAndSeek --param level=two --episodes 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("level=two"), std::string::npos) << r.err;
  r = rlt("eval --env CartPole --policy CartPole=scripted --episodes 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no scripted policy"), std::string::npos) << r.err;
  r = rlt("eval --env NoSuchEnv --episodes 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("NoSuchEnv"), std::string::npos) << r.err;
}

TEST_F(RltCliTest, EnvsListsTheDroneEnvs) {
  Result r = rlt("envs");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* line : {"HideAndSeek", "behavior Hider, 2 agent slot(s)",
                           "behavior Seeker, 4 agent slot(s)", "spatial_grid [6, 12, 5] grid",
                           "Hummingbird", "TargetDrone", "Eye", "behavior Eye, 2 agent slot(s)"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line;
}

TEST_F(RltCliTest, BenchEnvReportsPhysicsFrames) {
  Result r = rlt("bench env HideAndSeek --param level=4 --num-envs 2 --frames 3000 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(json_value(r.out, "frames_per_s"), 0.0) << r.out;
  // a step is 3 physics frames
  EXPECT_NEAR(json_value(r.out, "frames_per_s") / json_value(r.out, "env_steps_per_s"), 3.0, 0.01)
      << r.out;
}

TEST_F(RltCliTest, TrainParamErrorsNameTheParameterAndWriteNothing) {
  const std::string config = std::string(RLT_SOURCE_DIR) + "/configs/hide_and_seek.yaml";
  const fs::path results = root_ / "results_param";
  struct Case {
    std::string param, message;
  };
  for (const Case& c : {Case{"level=2", "--param level: "},  // the curriculum owns it
                        Case{"bogus=1", "no parameter 'bogus'"},
                        Case{"unseen_reward=nan", "unseen_reward must be finite"}}) {
    Result r = rlt("train " + quote(config) + " --param " + c.param + " --run-id p --results-dir " +
                   quote(results.string()));
    EXPECT_EQ(r.exit_code, 1) << c.param;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.param << ": " << r.err;
    EXPECT_FALSE(fs::exists(results / "p")) << c.param;
  }
}

// --max-steps N or NAME=N: a malformed value is a usage error (exit 2), a behavior the env does
// not have an error naming the ones it has (exit 1); so for --until-emerged's strategies; none
// writes a run folder
TEST_F(RltCliTest, TrainMaxStepsAndUntilEmergedErrorsNameTheValueAndWriteNothing) {
  const std::string config = std::string(RLT_SOURCE_DIR) + "/configs/hide_and_seek.yaml";
  const fs::path results = root_ / "results_max_steps";
  struct Case {
    std::string flags, message;
    int exit_code;
  };
  for (const Case& c :
       {Case{"--max-steps Hidr=5", "has no behavior 'Hidr' (it has: Hider, Seeker)", 1},
        Case{"--max-steps Hider=many", "--max-steps Hider=many: expected an integer, got 'many'", 2},
        Case{"--max-steps Seeker=0", "--max-steps Seeker=0: must be at least 1, got 0", 2},
        Case{"--max-steps =5", "--max-steps expects N or BEHAVIOR=N, got '=5'", 2},
        Case{"--max-steps 5 --max-steps 6", "--max-steps N given twice", 2},
        Case{"--max-steps Hider=5 --max-steps Hider=6", "--max-steps Hider given twice", 2},
        Case{"--until-emerged forts",
             "--until-emerged forts: environment HideAndSeek declares no strategy 'forts' (it "
             "declares: running_and_chasing, shelter",
             1},
        Case{"--until-emerged shelter --until-emerged shelter", "--until-emerged shelter given twice",
             2}}) {
    Result r = rlt("train " + quote(config) + " " + c.flags + " --run-id m --results-dir " +
                   quote(results.string()));
    EXPECT_EQ(r.exit_code, c.exit_code) << c.flags << ": " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.flags << ": " << r.err;
    EXPECT_FALSE(fs::exists(results / "m")) << c.flags;
  }
}

// issue 5: the main job's config trains end to end (a few thousand steps: no update yet, the
// buffer is 12,288; the first episodes end after 512 decisions) and both exported policies load
// in a fresh process and act
TEST_F(RltCliTest, HideAndSeekConfigTrainsAndExportsBothPolicies) {
  const fs::path results = root_ / "results_hs";
  Result r = rlt("train " + quote(std::string(RLT_SOURCE_DIR) + "/configs/hide_and_seek.yaml") +
                 " --max-steps 6000 --num-envs 2 --run-id hs --results-dir " + quote(results.string()));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const fs::path run = results / "hs";
  const std::string status = read_file(run / "training_status.json");
  EXPECT_NE(status.find("\"running_and_chasing\": {\"metric\": \"tag_rate\", \"behavior\": \"Seeker\""),
            std::string::npos) << status;
  EXPECT_NE(status.find("\"shelter\": {\"metric\": \"fort_rate\""), std::string::npos) << status;
  // episode metrics: a header naming the strategy metrics, a row per summary with episodes
  const std::string episodes = read_file(run / "metrics/episodes.csv");
  EXPECT_EQ(episodes.rfind("total_steps,elapsed_s,episodes,Hider_step,Seeker_step,lesson_level,", 0), 0u)
      << episodes;
  EXPECT_NE(episodes.find(",fort_rate,"), std::string::npos) << episodes;
  EXPECT_NE(episodes.find(",tag_rate,"), std::string::npos) << episodes;
  EXPECT_GE(std::count(episodes.begin(), episodes.end(), '\n'), 2) << episodes;
  // both policies load in a fresh process (LibTorch only) and return 4 continuous actions and
  // the grab and lock choices for one agent's 20 + 84 + 119 + 360 + 360 observation floats
  const fs::path input = root_ / "hs_probe_input.txt";
  {
    std::ofstream in(input);
    in << "1 5 5\n1 20\n1 84\n1 119\n3 6 12 5\n3 9 8 5\n";
    for (int i = 0; i < 943; ++i) in << (i % 7) * 0.1 << ' ';
    in << "\n1 1 1 1 1\n";
  }
  for (const char* behavior : {"Hider", "Seeker"}) {
    const fs::path policy = run / (std::string(behavior) + ".pt");
    ASSERT_TRUE(fs::is_regular_file(policy)) << policy;
    const fs::path out = root_ / (std::string(behavior) + "_probe.txt");
    const std::string command = std::string(POLICY_PROBE) + " " + quote(policy.string()) + " " +
                                quote(input.string()) + " > " + quote(out.string());
    ASSERT_EQ(std::system(command.c_str()), 0) << behavior;
    const std::string probe = read_file(out);
    EXPECT_NE(probe.find("\"name\":\"" + std::string(behavior) + "\""), std::string::npos) << probe;
    ASSERT_TRUE(std::regex_search(probe, std::regex(R"(\n\S+ \S+ \S+ \S+ \| \d \d)"))) << probe;
  }
  // and the run plays through rlt eval
  Result e = rlt("eval " + quote(run.string()) + " --episodes 1 --json");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(e.out.find("\"behavior\":\"Seeker\""), std::string::npos) << e.out;
  EXPECT_FALSE(std::isnan(json_value(e.out, "tag_rate"))) << e.out;
}

}  // namespace
