// Tests of the run-configuration parser: ML-Agents defaults, an ML-Agents-style config, the
// default_settings merge, every class of error (checked for file name, key path, line and
// problem), and the write/read round trip.
#include "rl/config/config_parser.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

namespace rlt {
namespace {

constexpr const char* kSource = "configs/test.yaml";

RunConfig parse(const std::string& yaml) { return load_run_config_from_string(yaml, kSource); }

// The ConfigError that parsing `yaml` throws (a failed expectation when it does not throw).
ConfigError parse_error(const std::string& yaml) {
  try {
    parse(yaml);
  } catch (const ConfigError& error) {
    return error;
  }
  ADD_FAILURE() << "no ConfigError for:\n" << yaml;
  return ConfigError("", "", 0, "");
}

// Checks that `yaml` fails with a message naming the file, `key_path` and `line` (0 = do not
// check) and containing `problem`.
void expect_error(const std::string& yaml, const std::string& key_path, int line,
                  const std::string& problem) {
  SCOPED_TRACE(yaml);
  const ConfigError error = parse_error(yaml);
  const std::string message = error.what();
  EXPECT_EQ(error.file(), kSource);
  EXPECT_EQ(error.key_path(), key_path) << message;
  if (line > 0) {
    EXPECT_EQ(error.line(), line) << message;
  }
  EXPECT_NE(error.problem().find(problem), std::string::npos) << message;
  EXPECT_EQ(message.rfind(kSource, 0), 0u) << message;  // starts with the file name
  if (!key_path.empty()) {
    EXPECT_NE(message.find(": " + key_path + ": "), std::string::npos) << message;
  }
}

// A behavior named CartPole with `section` (an indented block) spliced in, plus an env.
std::string cartpole_with(const std::string& section) {
  return "behaviors:\n  CartPole:\n" + section + "env_settings:\n  env_id: CartPole\n";
}

void expect_same(const BehaviorConfig& a, const BehaviorConfig& b) {
  EXPECT_EQ(a.trainer_type, b.trainer_type);
  const Hyperparameters& ha = a.hyperparameters;
  const Hyperparameters& hb = b.hyperparameters;
  EXPECT_EQ(ha.batch_size, hb.batch_size);
  EXPECT_EQ(ha.buffer_size, hb.buffer_size);
  EXPECT_EQ(ha.learning_rate, hb.learning_rate);
  EXPECT_EQ(ha.learning_rate_schedule, hb.learning_rate_schedule);
  EXPECT_EQ(ha.beta, hb.beta);
  EXPECT_EQ(ha.beta_schedule, hb.beta_schedule);
  EXPECT_EQ(ha.discrete_beta, hb.discrete_beta);
  EXPECT_EQ(ha.epsilon, hb.epsilon);
  EXPECT_EQ(ha.epsilon_schedule, hb.epsilon_schedule);
  EXPECT_EQ(ha.lambd, hb.lambd);
  EXPECT_EQ(ha.num_epoch, hb.num_epoch);
  EXPECT_EQ(ha.shared_critic, hb.shared_critic);
  EXPECT_EQ(ha.max_grad_norm, hb.max_grad_norm);
  const NetworkSettings& na = a.network_settings;
  const NetworkSettings& nb = b.network_settings;
  EXPECT_EQ(na.normalize, nb.normalize);
  EXPECT_EQ(na.hidden_units, nb.hidden_units);
  EXPECT_EQ(na.num_layers, nb.num_layers);
  EXPECT_EQ(na.vis_encode_type, nb.vis_encode_type);
  EXPECT_EQ(na.deterministic, nb.deterministic);
  EXPECT_EQ(na.activation, nb.activation);
  EXPECT_EQ(a.extrinsic.gamma, b.extrinsic.gamma);
  EXPECT_EQ(a.extrinsic.strength, b.extrinsic.strength);
  EXPECT_EQ(a.init_path, b.init_path);
  EXPECT_EQ(a.keep_checkpoints, b.keep_checkpoints);
  EXPECT_EQ(a.checkpoint_interval, b.checkpoint_interval);
  EXPECT_EQ(a.max_steps, b.max_steps);
  EXPECT_EQ(a.time_horizon, b.time_horizon);
  EXPECT_EQ(a.summary_freq, b.summary_freq);
  EXPECT_EQ(a.threaded, b.threaded);
  EXPECT_EQ(a.self_play, b.self_play);
}

// Every field except source_file.
void expect_same(const RunConfig& a, const RunConfig& b) {
  ASSERT_EQ(a.behaviors.size(), b.behaviors.size());
  for (const auto& [name, behavior] : a.behaviors) {
    SCOPED_TRACE("behavior " + name);
    ASSERT_EQ(b.behaviors.count(name), 1u);
    expect_same(behavior, b.behaviors.at(name));
  }
  ASSERT_EQ(a.default_settings.has_value(), b.default_settings.has_value());
  if (a.default_settings) {
    SCOPED_TRACE("default_settings");
    expect_same(*a.default_settings, *b.default_settings);
  }
  EXPECT_EQ(a.env_settings.env_id, b.env_settings.env_id);
  EXPECT_EQ(a.env_settings.num_envs, b.env_settings.num_envs);
  EXPECT_EQ(a.env_settings.seed, b.env_settings.seed);
  EXPECT_EQ(a.env_settings.num_threads, b.env_settings.num_threads);
  EXPECT_EQ(a.env_settings.stagger_steps, b.env_settings.stagger_steps);
  EXPECT_EQ(a.env_settings.params, b.env_settings.params);
  EXPECT_EQ(a.checkpoint_settings.run_id, b.checkpoint_settings.run_id);
  EXPECT_EQ(a.checkpoint_settings.initialize_from, b.checkpoint_settings.initialize_from);
  EXPECT_EQ(a.checkpoint_settings.resume, b.checkpoint_settings.resume);
  EXPECT_EQ(a.checkpoint_settings.force, b.checkpoint_settings.force);
  EXPECT_EQ(a.checkpoint_settings.results_dir, b.checkpoint_settings.results_dir);
  EXPECT_EQ(a.environment_parameters, b.environment_parameters);
}

// A config in the shape of ML-Agents' config/ppo/3DBall.yaml, with env_settings.env_id and the
// ML-Agents sections we accept and ignore.
const char* const k3DBall = R"(behaviors:
  3DBall:
    trainer_type: ppo
    hyperparameters:
      batch_size: 64
      buffer_size: 12000
      learning_rate: 0.0003
      beta: 0.001
      epsilon: 0.2
      lambd: 0.99
      num_epoch: 3
      learning_rate_schedule: linear
    network_settings:
      normalize: true
      hidden_units: 128
      num_layers: 2
      vis_encode_type: simple
    reward_signals:
      extrinsic:
        gamma: 0.99
        strength: 1.0
    keep_checkpoints: 5
    max_steps: 5.0e5
    time_horizon: 1000
    summary_freq: 12000
env_settings:
  env_id: Ball3D
  num_envs: 8
  seed: 42
  num_threads: 2
  stagger_steps: 500
  params:
    gravity: 9.81
  base_port: 5005
  num_areas: 1
checkpoint_settings:
  run_id: ball-1
  results_dir: out/results
  resume: false
  force: true
environment_parameters:
  mass: 1.5
  scale: 2
engine_settings:
  width: 84
  height: 84
  quality_level: 5
  time_scale: 20
  target_frame_rate: -1
  capture_frame_rate: 60
  no_graphics: true
torch_settings:
  device: cpu
debug: false
)";

// ---------------------------------------------------------------------------------------------
// Accepted configurations.

TEST(ConfigParserTest, EmptyBehaviorGetsMlAgentsDefaults) {
  const RunConfig config = parse("behaviors:\n  CartPole:\nenv_settings:\n  env_id: CartPole\n");
  EXPECT_EQ(config.source_file, kSource);
  ASSERT_EQ(config.behaviors.count("CartPole"), 1u);
  BehaviorConfig expected;  // the struct defaults are ML-Agents' defaults
  expected.hyperparameters.beta_schedule = Schedule::kLinear;     // follows learning_rate_schedule
  expected.hyperparameters.epsilon_schedule = Schedule::kLinear;  // likewise
  expected.hyperparameters.discrete_beta = expected.hyperparameters.beta;  // follows beta
  expect_same(config.behaviors.at("CartPole"), expected);
  const BehaviorConfig& cartpole = config.behaviors.at("CartPole");
  EXPECT_EQ(cartpole.trainer_type, "ppo");
  EXPECT_EQ(cartpole.hyperparameters.batch_size, 1024);
  EXPECT_EQ(cartpole.hyperparameters.buffer_size, 10240);
  EXPECT_FLOAT_EQ(cartpole.hyperparameters.learning_rate, 3e-4f);
  EXPECT_EQ(cartpole.hyperparameters.learning_rate_schedule, Schedule::kLinear);
  EXPECT_EQ(cartpole.network_settings.hidden_units, 128);
  EXPECT_EQ(cartpole.network_settings.activation, Activation::kSwish);
  EXPECT_FLOAT_EQ(cartpole.extrinsic.gamma, 0.99f);
  EXPECT_EQ(cartpole.max_steps, 500000);
  EXPECT_FALSE(config.default_settings.has_value());
  EXPECT_EQ(config.env_settings.env_id, "CartPole");
  EXPECT_EQ(config.env_settings.num_envs, 1);
  EXPECT_EQ(config.env_settings.seed, -1);
  EXPECT_EQ(config.env_settings.num_threads, 0);
  EXPECT_EQ(config.env_settings.stagger_steps, 0);
  EXPECT_TRUE(config.env_settings.params.empty());
  EXPECT_EQ(config.checkpoint_settings.run_id, "ppo");
  EXPECT_EQ(config.checkpoint_settings.results_dir, "results");
  EXPECT_EQ(config.checkpoint_settings.initialize_from, "");
  EXPECT_FALSE(config.checkpoint_settings.resume);
  EXPECT_FALSE(config.checkpoint_settings.force);
  EXPECT_TRUE(config.environment_parameters.empty());
}

TEST(ConfigParserTest, ReadsMlAgents3DBallConfig) {
  const RunConfig config = parse(k3DBall);
  ASSERT_EQ(config.behaviors.size(), 1u);
  const BehaviorConfig& ball = config.behaviors.at("3DBall");
  EXPECT_EQ(ball.trainer_type, "ppo");
  EXPECT_EQ(ball.hyperparameters.batch_size, 64);
  EXPECT_EQ(ball.hyperparameters.buffer_size, 12000);
  EXPECT_EQ(ball.hyperparameters.learning_rate, 0.0003f);
  EXPECT_EQ(ball.hyperparameters.beta, 0.001f);
  EXPECT_EQ(ball.hyperparameters.epsilon, 0.2f);
  EXPECT_EQ(ball.hyperparameters.lambd, 0.99f);
  EXPECT_EQ(ball.hyperparameters.num_epoch, 3);
  EXPECT_EQ(ball.hyperparameters.learning_rate_schedule, Schedule::kLinear);
  EXPECT_EQ(ball.hyperparameters.beta_schedule, Schedule::kLinear);
  EXPECT_EQ(ball.hyperparameters.epsilon_schedule, Schedule::kLinear);
  EXPECT_TRUE(ball.network_settings.normalize);
  EXPECT_EQ(ball.network_settings.hidden_units, 128);
  EXPECT_EQ(ball.network_settings.num_layers, 2);
  EXPECT_EQ(ball.network_settings.vis_encode_type, "simple");
  EXPECT_EQ(ball.extrinsic.gamma, 0.99f);
  EXPECT_EQ(ball.extrinsic.strength, 1.0f);
  EXPECT_EQ(ball.keep_checkpoints, 5);
  EXPECT_EQ(ball.max_steps, 500000);  // written 5.0e5, as some ML-Agents configs do
  EXPECT_EQ(ball.time_horizon, 1000);
  EXPECT_EQ(ball.summary_freq, 12000);
  EXPECT_EQ(config.env_settings.env_id, "Ball3D");
  EXPECT_EQ(config.env_settings.num_envs, 8);
  EXPECT_EQ(config.env_settings.seed, 42);
  EXPECT_EQ(config.env_settings.num_threads, 2);
  EXPECT_EQ(config.env_settings.stagger_steps, 500);
  EXPECT_EQ(config.env_settings.params, (std::map<std::string, float>{{"gravity", 9.81f}}));
  EXPECT_EQ(config.checkpoint_settings.run_id, "ball-1");
  EXPECT_EQ(config.checkpoint_settings.results_dir, "out/results");
  EXPECT_TRUE(config.checkpoint_settings.force);
  EXPECT_EQ(config.environment_parameters,
            (std::map<std::string, EnvironmentParameterSettings>{{"mass", 1.5f}, {"scale", 2.0f}}));
  EXPECT_EQ(config.environment_parameters.at("mass").sampler.type, SamplerType::kConstant);
  EXPECT_FALSE(config.environment_parameters.at("mass").is_curriculum());
}

// The configuration.yaml that mlagents-learn writes into its results folder spells out every
// optional section as null; it must read as-is once env_path is replaced by env_id.
TEST(ConfigParserTest, ReadsMlAgentsResolvedConfigurationWithNulls) {
  const RunConfig config = parse(R"(default_settings: null
behaviors:
  Walker:
    trainer_type: poca
    hyperparameters:
      batch_size: 2048
      buffer_size: 20480
      learning_rate: 3.0e-4
      beta: 5.0e-3
      epsilon: 0.2
      lambd: 0.95
      num_epoch: 3
      shared_critic: false
      learning_rate_schedule: constant
      beta_schedule: linear
      epsilon_schedule: constant
    checkpoint_interval: 500000
    network_settings:
      normalize: true
      hidden_units: 256
      num_layers: 3
      vis_encode_type: nature_cnn
      memory: null
      goal_conditioning_type: hyper
      deterministic: false
    reward_signals:
      extrinsic:
        gamma: 0.995
        strength: 1.0
        network_settings:
          normalize: false
          hidden_units: 128
          num_layers: 2
          vis_encode_type: simple
          memory: null
          goal_conditioning_type: hyper
          deterministic: false
    init_path: null
    keep_checkpoints: 5
    even_checkpoints: false
    max_steps: 30000000
    time_horizon: 1000
    summary_freq: 30000
    threaded: false
    self_play: null
    behavioral_cloning: null
env_settings:
  env_id: Walker
  env_path: null
  env_args: null
  base_port: 5005
  num_envs: 1
  num_areas: 1
  timeout_wait: 60
  seed: -1
  max_lifetime_restarts: 10
  restarts_rate_limit_n: 1
  restarts_rate_limit_period_s: 60
engine_settings:
  width: 84
  height: 84
  quality_level: 5
  time_scale: 20
  target_frame_rate: -1
  capture_frame_rate: 60
  no_graphics: false
environment_parameters: null
checkpoint_settings:
  run_id: walker
  initialize_from: null
  load_model: false
  resume: false
  force: false
  train_model: false
  inference: false
  results_dir: results
torch_settings:
  device: null
debug: false
)");
  const BehaviorConfig& walker = config.behaviors.at("Walker");
  EXPECT_EQ(walker.trainer_type, "poca");
  EXPECT_EQ(walker.hyperparameters.learning_rate_schedule, Schedule::kConstant);
  EXPECT_EQ(walker.hyperparameters.beta_schedule, Schedule::kLinear);
  EXPECT_EQ(walker.hyperparameters.epsilon_schedule, Schedule::kConstant);
  EXPECT_EQ(walker.network_settings.hidden_units, 256);
  EXPECT_EQ(walker.network_settings.vis_encode_type, "nature_cnn");
  EXPECT_EQ(walker.extrinsic.gamma, 0.995f);
  EXPECT_EQ(walker.init_path, "");
  EXPECT_EQ(walker.max_steps, 30000000);
  EXPECT_FALSE(config.default_settings.has_value());
  EXPECT_EQ(config.checkpoint_settings.run_id, "walker");
  EXPECT_EQ(config.checkpoint_settings.initialize_from, "");
  EXPECT_TRUE(config.environment_parameters.empty());
}

TEST(ConfigParserTest, ReadsExtensionsAndOptionalStrings) {
  const RunConfig config = parse(cartpole_with(R"(    hyperparameters:
      max_grad_norm: 0.5
      learning_rate: 1e-3
    network_settings:
      activation: tanh
      deterministic: yes
    init_path: results/old/CartPole.pt
    threaded: true
)") + "checkpoint_settings:\n  initialize_from: old\n");
  const BehaviorConfig& cartpole = config.behaviors.at("CartPole");
  EXPECT_EQ(cartpole.hyperparameters.max_grad_norm, 0.5f);
  EXPECT_EQ(cartpole.hyperparameters.learning_rate, 1e-3f);
  EXPECT_EQ(cartpole.network_settings.activation, Activation::kTanh);
  EXPECT_TRUE(cartpole.network_settings.deterministic);
  EXPECT_EQ(cartpole.init_path, "results/old/CartPole.pt");
  EXPECT_TRUE(cartpole.threaded);
  EXPECT_EQ(config.checkpoint_settings.initialize_from, "old");
  // the branches' entropy bonus is beta's unless given
  EXPECT_EQ(cartpole.hyperparameters.discrete_beta, cartpole.hyperparameters.beta);
  const RunConfig own = parse(cartpole_with("    hyperparameters:\n      discrete_beta: 0.05\n"));
  EXPECT_EQ(own.behaviors.at("CartPole").hyperparameters.discrete_beta, 0.05f);
  EXPECT_EQ(own.behaviors.at("CartPole").hyperparameters.discrete_beta_steps, 0);
  // ... and moves to discrete_beta_end over discrete_beta_steps, the two together
  const RunConfig moving = parse(cartpole_with(
      "    hyperparameters:\n      discrete_beta: 0.05\n      discrete_beta_end: 0.005\n"
      "      discrete_beta_steps: 1600000\n"));
  const Hyperparameters& m = moving.behaviors.at("CartPole").hyperparameters;
  EXPECT_EQ(m.discrete_beta_end, 0.005f);
  EXPECT_EQ(m.discrete_beta_steps, 1600000);
  try {
    parse(cartpole_with("    hyperparameters:\n      discrete_beta_steps: 1000\n"));
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("discrete_beta_end and discrete_beta_steps go together"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("only discrete_beta_steps is given"), std::string::npos)
        << e.what();
  }
}

TEST(ConfigParserTest, EvenCheckpointsSpreadsCheckpointsOverMaxSteps) {
  const RunConfig config = parse(cartpole_with(R"(    even_checkpoints: true
    checkpoint_interval: 7
    max_steps: 1000000
    keep_checkpoints: 4
)"));
  EXPECT_EQ(config.behaviors.at("CartPole").checkpoint_interval, 250000);
}

// ---------------------------------------------------------------------------------------------
// self_play.

TEST(ConfigParserTest, SelfPlayWithMlAgentsDefaults) {
  const RunConfig config = parse(cartpole_with("    self_play:\n      window: 12\n"));
  const BehaviorConfig& cartpole = config.behaviors.at("CartPole");
  ASSERT_TRUE(cartpole.self_play.has_value());
  const SelfPlaySettings& self_play = *cartpole.self_play;
  EXPECT_EQ(self_play.window, 12);
  EXPECT_EQ(self_play.save_steps, 20000);
  EXPECT_EQ(self_play.team_change, 100000);
  EXPECT_EQ(self_play.swap_steps, 2000);
  EXPECT_EQ(self_play.play_against_latest_model_ratio, 0.5f);
  EXPECT_EQ(self_play.initial_elo, 1200.0);
  // An empty mapping turns self-play on with every default; null or no key leaves it off.
  EXPECT_EQ(parse(cartpole_with("    self_play: {}\n")).behaviors.at("CartPole").self_play,
            SelfPlaySettings{});
  EXPECT_FALSE(parse(cartpole_with("    self_play:\n")).behaviors.at("CartPole").self_play);
  EXPECT_FALSE(parse(cartpole_with("")).behaviors.at("CartPole").self_play);
}

TEST(ConfigParserTest, SelfPlayMlAgentsSoccerStyle) {
  const RunConfig config = parse(cartpole_with(R"(    self_play:
      save_steps: 50000
      team_change: 200000
      swap_steps: 2000
      window: 10
      play_against_latest_model_ratio: 0.5
      initial_elo: 1200.0
)"));
  const SelfPlaySettings& self_play = *config.behaviors.at("CartPole").self_play;
  EXPECT_EQ(self_play.save_steps, 50000);
  EXPECT_EQ(self_play.team_change, 200000);
}

TEST(ConfigParserTest, SelfPlayTeamChangeFollowsSaveSteps) {
  // ML-Agents' team_change default is 5 * save_steps.
  EXPECT_EQ(parse(cartpole_with("    self_play:\n      save_steps: 3000\n"))
                .behaviors.at("CartPole")
                .self_play->team_change,
            15000);
  EXPECT_EQ(parse(cartpole_with("    self_play:\n      save_steps: 3000\n      team_change: 7\n"))
                .behaviors.at("CartPole")
                .self_play->team_change,
            7);
}

TEST(ConfigParserTest, SelfPlayMergesWithDefaultSettings) {
  const RunConfig config = parse(R"(default_settings:
  self_play:
    save_steps: 1000
    window: 4
behaviors:
  Striker:
    self_play:
      window: 6
      save_steps: 9
  Goalie:
  Referee:
    self_play: null
env_settings:
  env_id: Soccer
)");
  EXPECT_EQ(config.default_settings->self_play->team_change, 5000);
  const SelfPlaySettings& striker = *config.behaviors.at("Striker").self_play;
  EXPECT_EQ(striker.window, 6);
  EXPECT_EQ(striker.save_steps, 9);
  EXPECT_EQ(striker.team_change, 5000);  // resolved in default_settings, as ML-Agents merges
  EXPECT_EQ(config.behaviors.at("Goalie").self_play, config.default_settings->self_play);
  EXPECT_FALSE(config.behaviors.at("Referee").self_play.has_value());  // switched off
}

TEST(ConfigParserErrorTest, SelfPlayErrors) {
  expect_error(cartpole_with("    self_play:\n      window: 0\n"),
               "behaviors.CartPole.self_play.window", 4, "expected a positive integer, got '0'");
  expect_error(cartpole_with("    self_play:\n      save_steps: -5\n"),
               "behaviors.CartPole.self_play.save_steps", 4, "expected a positive integer");
  expect_error(cartpole_with("    self_play:\n      swap_steps: 2.5\n"),
               "behaviors.CartPole.self_play.swap_steps", 4, "expected a positive integer");
  expect_error(cartpole_with("    self_play:\n      team_change: 0\n"),
               "behaviors.CartPole.self_play.team_change", 4, "expected a positive integer");
  expect_error(cartpole_with("    self_play:\n      play_against_latest_model_ratio: 1.5\n"),
               "behaviors.CartPole.self_play.play_against_latest_model_ratio", 4,
               "expected a number in [0, 1], got '1.5'");
  expect_error(cartpole_with("    self_play:\n      initial_elo: high\n"),
               "behaviors.CartPole.self_play.initial_elo", 4, "expected a finite number");
  expect_error(cartpole_with("    self_play:\n      windw: 3\n"), "behaviors.CartPole.self_play", 4,
               "unknown key 'windw' (did you mean 'window'?)");
  expect_error(cartpole_with("    self_play:\n      turn_parameters: {level: two}\n"),
               "behaviors.CartPole.self_play.turn_parameters.level", 4, "expected a finite number");
  expect_error(cartpole_with("    self_play:\n      turn_parameters: [1, 2]\n"),
               "behaviors.CartPole.self_play.turn_parameters", 4, "expected a mapping");
  expect_error(cartpole_with("    self_play: true\n"), "behaviors.CartPole.self_play", 3,
               "expected a mapping, got 'true'");
  expect_error("default_settings:\n  self_play:\n    window: -1\n",
               "default_settings.self_play.window", 3, "expected a positive integer");
}

// ---------------------------------------------------------------------------------------------
// environment_parameters: samplers and curricula.

// In the shape of ML-Agents' config/ppo/WallJump_curriculum.yaml (two behaviors, progress-based
// lessons whose values are samplers or constants), with a reward-measured parameter added.
const char* const kWallJumpCurriculum = R"(behaviors:
  BigWallJump:
    trainer_type: ppo
    max_steps: 20000000
  SmallWallJump:
    trainer_type: ppo
    max_steps: 5000000
env_settings:
  env_id: WallJump
environment_parameters:
  big_wall_height:
    curriculum:
      - name: Lesson0 # the '-' starts a lesson
        completion_criteria:
          measure: progress
          behavior: BigWallJump
          signal_smoothing: true
          min_lesson_length: 100
          threshold: 0.1
        value:
          sampler_type: uniform
          sampler_parameters:
            min_value: 0.0
            max_value: 4.0
      - name: Lesson1
        completion_criteria:
          measure: progress
          behavior: BigWallJump
          signal_smoothing: true
          min_lesson_length: 100
          threshold: 0.3
        value:
          sampler_type: uniform
          sampler_parameters:
            min_value: 4.0
            max_value: 7.0
      - name: Lesson2
        value: 8.0
  small_wall_height:
    curriculum:
      - name: Lesson0
        completion_criteria:
          behavior: SmallWallJump
          threshold: 0.7
          require_reset: true
        value: 1.5
      - name: Lesson1
        value: 4.0
  gravity:
    sampler_type: gaussian
    sampler_parameters:
      mean: 9.8
      st_dev: 0.5
  block_offset:
    sampler_type: multirangeuniform
    sampler_parameters:
      intervals: [[-2.0, -1.0], [1.0, 2.0]]
  friction:
    sampler_type: constant
    sampler_parameters:
      value: 0.25
      seed: 1337
  goal_size: 3
)";

TEST(ConfigParserTest, ReadsMlAgentsWallJumpCurriculum) {
  const RunConfig config = parse(kWallJumpCurriculum);
  const auto& parameters = config.environment_parameters;
  ASSERT_EQ(parameters.size(), 6u);

  const EnvironmentParameterSettings& big = parameters.at("big_wall_height");
  ASSERT_TRUE(big.is_curriculum());
  ASSERT_EQ(big.curriculum.size(), 3u);
  EXPECT_EQ(big.curriculum[0].name, "Lesson0");
  EXPECT_EQ(big.curriculum[0].value, SamplerSettings::uniform(0.f, 4.f));
  ASSERT_TRUE(big.curriculum[0].completion_criteria.has_value());
  const CompletionCriteria& first = *big.curriculum[0].completion_criteria;
  EXPECT_EQ(first.measure, CompletionMeasure::kProgress);
  EXPECT_EQ(first.behavior, "BigWallJump");
  EXPECT_TRUE(first.signal_smoothing);
  EXPECT_EQ(first.min_lesson_length, 100);
  EXPECT_EQ(first.threshold, 0.1);
  EXPECT_FALSE(first.require_reset);
  EXPECT_EQ(big.curriculum[1].value, SamplerSettings::uniform(4.f, 7.f));
  EXPECT_EQ(big.curriculum[1].completion_criteria->threshold, 0.3);
  EXPECT_EQ(big.curriculum[2].name, "Lesson2");
  EXPECT_EQ(big.curriculum[2].value, SamplerSettings::constant(8.f));
  EXPECT_FALSE(big.curriculum[2].completion_criteria.has_value());

  // ML-Agents' completion_criteria defaults.
  const CompletionCriteria& small =
      *parameters.at("small_wall_height").curriculum[0].completion_criteria;
  EXPECT_EQ(small.measure, CompletionMeasure::kReward);
  EXPECT_EQ(small.min_lesson_length, 0);
  EXPECT_TRUE(small.signal_smoothing);
  EXPECT_TRUE(small.require_reset);
  EXPECT_EQ(small.threshold, 0.7);

  EXPECT_EQ(parameters.at("gravity").sampler, SamplerSettings::gaussian(9.8f, 0.5f));
  EXPECT_FALSE(parameters.at("gravity").is_curriculum());
  EXPECT_EQ(parameters.at("block_offset").sampler,
            SamplerSettings::multi_range_uniform({{-2.f, -1.f}, {1.f, 2.f}}));
  EXPECT_EQ(parameters.at("friction").sampler, SamplerSettings::constant(0.25f));
  EXPECT_EQ(parameters.at("goal_size"), EnvironmentParameterSettings(3.f));
}

TEST(ConfigParserTest, SamplerDefaultsAreMlAgents) {
  const RunConfig config = parse(cartpole_with("") + R"(environment_parameters:
  u: {sampler_type: uniform, sampler_parameters: {}}
  g: {sampler_type: gaussian, sampler_parameters: {}}
  m: {sampler_type: multirangeuniform, sampler_parameters: {}}
  c: {sampler_type: constant, sampler_parameters: {}}
)");
  const auto& parameters = config.environment_parameters;
  EXPECT_EQ(parameters.at("u").sampler, SamplerSettings::uniform(0.f, 1.f));
  EXPECT_EQ(parameters.at("g").sampler, SamplerSettings::gaussian(1.f, 1.f));
  EXPECT_EQ(parameters.at("m").sampler, SamplerSettings::multi_range_uniform({{0.f, 1.f}}));
  EXPECT_EQ(parameters.at("c").sampler, SamplerSettings::constant(0.f));
}

TEST(ConfigParserTest, CurriculumBehaviorMayComeFromDefaultSettings) {
  const RunConfig config = parse(R"(default_settings:
  max_steps: 100
env_settings:
  env_id: WallJump
environment_parameters:
  height:
    curriculum:
      - {name: Low, value: 1, completion_criteria: {behavior: AnyBehavior, threshold: 0.5}}
      - {name: High, value: 2, completion_criteria: {behavior: AnyBehavior}}
)");
  const auto& lessons = config.environment_parameters.at("height").curriculum;
  ASSERT_EQ(lessons.size(), 2u);
  EXPECT_EQ(lessons[0].completion_criteria->behavior, "AnyBehavior");
  // A completion_criteria on the last lesson is accepted (ML-Agents warns) and kept.
  EXPECT_TRUE(lessons[1].completion_criteria.has_value());
}

// `block` (lines from 6 on) as the environment_parameters of a CartPole config.
std::string with_parameters(const std::string& block) {
  return cartpole_with("") + "environment_parameters:\n" + block;
}

// A two-lesson curriculum of parameter `h` with `criteria` (lines from 11 on) as the first
// lesson's completion_criteria.
std::string with_criteria(const std::string& criteria) {
  return with_parameters(R"(  h:
    curriculum:
      - name: A
        value: 1
        completion_criteria:
)" + criteria + R"(      - name: B
        value: 2
)");
}

TEST(ConfigParserErrorTest, CompletionCriteriaErrors) {
  const std::string path = "environment_parameters.h.curriculum[0].completion_criteria";
  expect_error(with_criteria("          behavior: CartPol\n"), path + ".behavior", 11,
               "behavior 'CartPol' is not configured (configured: CartPole) (did you mean "
               "'CartPole'?)");
  expect_error(with_criteria("          behavior: \"\"\n"), path + ".behavior", 11,
               "must not be empty");
  expect_error(with_criteria("          threshold: 0.5\n"), path + ".behavior", 10,
               "missing: the behavior");
  expect_error(with_criteria("          behavior: CartPole\n          measure: rewrd\n"),
               path + ".measure", 12,
               "expected one of reward, progress, metric, got 'rewrd' (did you "
               "mean 'reward'?)");
  // measure: metric (our extension) needs the metric and no behavior; the others the reverse
  expect_error(with_criteria("          measure: metric\n          threshold: 0.5\n"),
               path + ".metric", 10, "missing: with measure: metric, the env's episode metric");
  expect_error(with_criteria("          measure: metric\n          metric: \"\"\n"),
               path + ".metric", 12, "must not be empty");
  expect_error(with_criteria("          behavior: CartPole\n          metric: fort_rate\n"),
               path + ".metric", 12, "is only read with measure: metric");
  expect_error(with_criteria("          behavior: CartPole\n          threshold: 1.5\n"
                             "          measure: progress\n"),
               path + ".threshold", 12, "with measure: progress, expected a number in [0, 1]");
  expect_error(with_criteria("          behavior: CartPole\n          min_lesson_length: -1\n"),
               path + ".min_lesson_length", 12, "expected a non-negative integer");
  expect_error(with_criteria("          behavior: CartPole\n          signal_smoothing: 1\n"),
               path + ".signal_smoothing", 12, "expected true or false");
  expect_error(with_criteria("          behavior: CartPole\n          treshold: 1\n"), path, 12,
               "unknown key 'treshold' (did you mean 'threshold'?)");
  expect_error(
      with_parameters("  h:\n    curriculum:\n      - name: A\n        value: 1\n"
                      "        completion_criteria: 5\n      - name: B\n        value: 2\n"),
      path, 10, "expected a mapping, got '5'");
  // fallback_threshold (our extension): reward or metric, below threshold; its length needs it
  expect_error(with_criteria("          behavior: CartPole\n          measure: progress\n"
                             "          threshold: 0.5\n          fallback_threshold: 0.1\n"),
               path + ".fallback_threshold", 14, "is only read with measure: reward or metric");
  expect_error(with_criteria("          behavior: CartPole\n          threshold: 0.5\n"
                             "          fallback_threshold: 0.5\n"),
               path + ".fallback_threshold", 13,
               "expected a number below threshold (0.5), got '0.5': a lesson that falls back at "
               "its own threshold would never end");
  expect_error(with_criteria("          behavior: CartPole\n          threshold: 0.5\n"
                             "          fallback_length: 10\n"),
               path + ".fallback_length", 13, "is only read with fallback_threshold");
  expect_error(with_criteria("          behavior: CartPole\n          threshold: 0.5\n"
                             "          fallback_threshold: 0.1\n          fallback_length: 0\n"),
               path + ".fallback_length", 14, "expected a positive integer");
  // after_emerged (our extension): a list of strategy names, none empty or twice
  expect_error(with_criteria("          behavior: CartPole\n          after_emerged: chasing\n"),
               path + ".after_emerged", 12,
               "expected a list of strategy names (e.g. [running_and_chasing]), got 'chasing'");
  expect_error(with_criteria("          behavior: CartPole\n          after_emerged: [\"\"]\n"),
               path + ".after_emerged[0]", 12, "must not be empty");
  expect_error(
      with_criteria("          behavior: CartPole\n          after_emerged: [chasing, chasing]\n"),
      path + ".after_emerged[1]", 12, "names the strategy 'chasing' twice");
  // A reward threshold may be any number.
  EXPECT_EQ(parse(with_criteria("          behavior: CartPole\n          threshold: -3\n"))
                .environment_parameters.at("h")
                .curriculum[0]
                .completion_criteria->threshold,
            -3.0);
}

TEST(ConfigParserTest, MetricMeasuredLessonRoundTrips) {
  const RunConfig config = parse(with_criteria(
      "          measure: metric\n          metric: fort_rate\n          threshold: 0.6\n"
      "          min_lesson_length: 50\n"));
  const CompletionCriteria& criteria =
      *config.environment_parameters.at("h").curriculum[0].completion_criteria;
  EXPECT_EQ(criteria.measure, CompletionMeasure::kMetric);
  EXPECT_EQ(criteria.metric, "fort_rate");
  EXPECT_EQ(criteria.behavior, "");
  EXPECT_EQ(criteria.threshold, 0.6);
  EXPECT_EQ(criteria.min_lesson_length, 50);
  const std::string yaml = run_config_to_yaml(config);
  EXPECT_NE(yaml.find("measure: metric"), std::string::npos) << yaml;
  const RunConfig again = parse(yaml);
  EXPECT_EQ(again.environment_parameters.at("h").curriculum[0].completion_criteria, criteria);
  EXPECT_EQ(run_config_to_yaml(again), yaml);
}

// Lesson A of parameter h sets offset 0, is judged on the fort rate (or `criteria`) and has the
// staircase `staircase`; lesson B follows.
std::string with_staircase(const std::string& staircase,
                           const std::string& criteria = "          measure: metric\n"
                                                         "          metric: fort_rate\n"
                                                         "          threshold: 0.5\n") {
  return with_parameters(R"(  h:
    curriculum:
      - name: A
        value: 1
        other_parameters: {offset: 0}
        completion_criteria:
)" + criteria + "        staircase:\n" + staircase + R"(      - name: B
        value: 2
        other_parameters: {offset: 1}
)");
}

TEST(ConfigParserTest, StaircaseLessonRoundTrips) {
  const RunConfig config = parse(with_staircase(
      "          parameter: offset\n          end: 1\n          step_up: 0.015\n"
      "          step_down: 0.005\n"));
  const Lesson& lesson = config.environment_parameters.at("h").curriculum[0];
  ASSERT_TRUE(lesson.staircase.has_value());
  EXPECT_EQ(*lesson.staircase, (Staircase{"offset", 1.0, 0.015, 0.005}));
  EXPECT_FALSE(config.environment_parameters.at("h").curriculum[1].staircase.has_value());
  const std::string yaml = run_config_to_yaml(config);
  EXPECT_NE(yaml.find("staircase:"), std::string::npos) << yaml;
  const RunConfig again = parse(yaml);
  EXPECT_EQ(again.environment_parameters.at("h").curriculum, config.environment_parameters.at("h").curriculum);
  EXPECT_EQ(run_config_to_yaml(again), yaml);
  // the curriculum's own value may be the one that moves, downward too
  EXPECT_EQ(parse(with_staircase("          parameter: h\n          end: 0.5\n"
                                 "          step_up: 0.1\n          step_down: 0\n"))
                .environment_parameters.at("h")
                .curriculum[0]
                .staircase,
            (Staircase{"h", 0.5, 0.1, 0.0}));
}

TEST(ConfigParserErrorTest, StaircaseErrors) {
  const std::string path = "environment_parameters.h.curriculum[0].staircase";
  const std::string steps = "          step_up: 0.1\n          step_down: 0.1\n";
  expect_error(with_staircase("          parameter: ofset\n          end: 1\n" + steps),
               path + ".parameter", 15, "'ofset' is not a parameter of lesson 'A' (it sets: h, offset)");
  expect_error(with_staircase("          parameter: offset\n          end: 0\n" + steps),
               path + ".end", 15, "equals the start (0.0, lesson 'A''s value of offset)");
  expect_error(with_staircase("          parameter: offset\n          end: 1\n"
                              "          step_up: 0\n          step_down: 0.1\n"),
               path + ".step_up", 18, "expected a number > 0, got '0'");
  expect_error(with_staircase("          parameter: offset\n          end: 1\n"
                              "          step_up: 0.1\n          step_down: -1\n"),
               path + ".step_down", 19, "expected a number >= 0, got '-1'");
  expect_error(with_staircase("          parameter: offset\n          step_up: 0.1\n"
                              "          step_down: 0.1\n"),
               path + ".end", 15, "missing: the value at which the lesson completes");
  expect_error(with_staircase("          parameter: offset\n          end: 1\n" + steps,
                              "          behavior: CartPole\n          measure: progress\n"
                              "          threshold: 0.5\n"),
               path, 15, "needs the lesson's completion_criteria with measure: reward or metric");
  expect_error(with_staircase("          parameter: offset\n          end: 1\n          stepup: 0.1\n"),
               path, 18, "unknown key 'stepup' (did you mean 'step_up'?)");
  expect_error(with_staircase("          3\n"), path, 15, "expected a mapping of parameter, end");
  // the start as the env gets it: 0.3 as a float is the end 0.3
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n        value: 0.3\n"
                               "        completion_criteria: {behavior: CartPole, threshold: 1}\n"
                               "        staircase: {parameter: h, end: 0.3, step_up: 1, step_down: 1}\n"
                               "      - name: B\n        value: 2\n"),
               path + ".end", 11, "equals the start (0.3, lesson 'A''s value of h)");
}

TEST(ConfigParserTest, FallbackCriteriaRoundTrip) {
  for (const std::string length : {"", "          fallback_length: 200\n"}) {
    const RunConfig config = parse(with_criteria(
        "          measure: metric\n          metric: fort_rate\n          threshold: 0.5\n"
        "          min_lesson_length: 50\n          fallback_threshold: 0.02\n" +
        length));
    const CompletionCriteria& criteria =
        *config.environment_parameters.at("h").curriculum[0].completion_criteria;
    EXPECT_EQ(criteria.fallback_threshold, std::optional<double>(0.02));
    EXPECT_EQ(criteria.fallback_episodes(), length.empty() ? 50 : 200);
    const std::string yaml = run_config_to_yaml(config);
    EXPECT_NE(yaml.find("fallback_threshold: 0.02"), std::string::npos) << yaml;
    const RunConfig again = parse(yaml);
    EXPECT_EQ(again.environment_parameters.at("h").curriculum[0].completion_criteria, criteria);
    EXPECT_EQ(run_config_to_yaml(again), yaml);
  }
  // without it nothing is written
  const std::string plain = run_config_to_yaml(
      parse(with_criteria("          behavior: CartPole\n          threshold: 0.5\n")));
  EXPECT_EQ(plain.find("fallback"), std::string::npos) << plain;
}

TEST(ConfigParserTest, AfterEmergedRoundTrip) {
  const RunConfig config = parse(with_criteria(
      "          behavior: CartPole\n          threshold: 0.5\n"
      "          after_emerged: [running_and_chasing, shelter]\n"));
  const CompletionCriteria& criteria =
      *config.environment_parameters.at("h").curriculum[0].completion_criteria;
  EXPECT_EQ(criteria.after_emerged, (std::vector<std::string>{"running_and_chasing", "shelter"}));
  const std::string yaml = run_config_to_yaml(config);
  EXPECT_NE(yaml.find("after_emerged: [running_and_chasing, shelter]"), std::string::npos) << yaml;
  const RunConfig again = parse(yaml);
  EXPECT_EQ(again.environment_parameters.at("h").curriculum[0].completion_criteria, criteria);
  EXPECT_EQ(run_config_to_yaml(again), yaml);
  // without it nothing is written
  const std::string plain = run_config_to_yaml(
      parse(with_criteria("          behavior: CartPole\n          threshold: 0.5\n")));
  EXPECT_EQ(plain.find("after_emerged"), std::string::npos) << plain;
}

// other_parameters: a lesson may set further env parameters; every lesson names the same ones and
// no other entry sets them
TEST(ConfigParserTest, LessonsMaySetOtherParameters) {
  const RunConfig config = parse(with_parameters(R"(  h:
    curriculum:
      - name: A
        value: 1
        other_parameters: {g: 0.5, k: 3}
        completion_criteria: {behavior: CartPole, threshold: 1}
      - name: B
        value: 2
        other_parameters: {g: 0, k: 4}
)"));
  const auto& lessons = config.environment_parameters.at("h").curriculum;
  EXPECT_EQ(lessons[0].other_parameters.at("g"), SamplerSettings::constant(0.5f));
  EXPECT_EQ(lessons[1].other_parameters.at("k"), SamplerSettings::constant(4.f));
  const std::string yaml = run_config_to_yaml(config);
  const RunConfig again = parse(yaml);
  EXPECT_EQ(again.environment_parameters, config.environment_parameters);
  EXPECT_EQ(run_config_to_yaml(again), yaml);
  const std::string two = "  h:\n    curriculum:\n      - name: A\n        value: 1\n"
                          "        other_parameters: {g: 1}\n"
                          "        completion_criteria: {behavior: CartPole, threshold: 1}\n"
                          "      - name: B\n        value: 2\n";
  expect_error(with_parameters(two + "        other_parameters: {k: 1}\n"),
               "environment_parameters.h.curriculum[1].other_parameters", 12,
               "lesson 'B' sets k, the first lesson sets g: every lesson must set the same");
  expect_error(with_parameters(two), "environment_parameters.h.curriculum[1].other_parameters", 12,
               "lesson 'B' sets none");
  expect_error(with_parameters(two + "        other_parameters: {g: 2}\n  g: 3\n"),
               "environment_parameters.h", 6,
               "the lessons of h set g (other_parameters), but it has its own entry");
  const std::string other = "  k:\n    curriculum:\n      - name: C\n        value: 1\n"
                            "        other_parameters: {g: 3}\n";
  expect_error(with_parameters(two + "        other_parameters: {g: 2}\n" + other),
               "environment_parameters.k", 15, "the lessons of h set it too");
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n        value: 1\n"
                               "        other_parameters: 5\n"),
               "environment_parameters.h.curriculum[0].other_parameters", 10,
               "expected a mapping of env parameter names to values");
}

// behavior_max_steps: a lesson may raise the step budget of behaviors the run trains
TEST(ConfigParserTest, LessonsMayRaiseABehaviorsStepBudget) {
  const std::string two = "  h:\n    curriculum:\n      - name: A\n        value: 1\n"
                          "        completion_criteria: {behavior: CartPole, threshold: 1}\n"
                          "      - name: B\n        value: 2\n";
  const RunConfig config = parse(with_parameters(two + "        behavior_max_steps: {CartPole: 90000}\n"));
  const auto& lessons = config.environment_parameters.at("h").curriculum;
  EXPECT_TRUE(lessons[0].behavior_max_steps.empty());
  EXPECT_EQ(lessons[1].behavior_max_steps, (std::map<std::string, int64_t>{{"CartPole", 90000}}));
  const std::string yaml = run_config_to_yaml(config);
  const RunConfig again = parse(yaml);
  EXPECT_EQ(again.environment_parameters, config.environment_parameters);
  EXPECT_EQ(run_config_to_yaml(again), yaml);
  expect_error(with_parameters(two + "        behavior_max_steps: {CartPol: 90000}\n"),
               "environment_parameters.h.curriculum[1].behavior_max_steps.CartPol", 13,
               "behavior 'CartPol' is not configured (configured: CartPole) (did you mean "
               "'CartPole'?)");
  expect_error(with_parameters(two + "        behavior_max_steps: {CartPole: 0}\n"),
               "environment_parameters.h.curriculum[1].behavior_max_steps.CartPole", 13,
               "expected a positive integer");
  expect_error(with_parameters(two + "        behavior_max_steps: 90000\n"),
               "environment_parameters.h.curriculum[1].behavior_max_steps", 13,
               "expected a mapping of behavior names to step totals");
}

// every shipped configuration reads (ctest runs in the source tree)
TEST(ConfigParserTest, EveryShippedConfigReads) {
  int read = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator("configs")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(load_run_config(entry.path().string()));
    ++read;
  }
  EXPECT_GE(read, 10);
}

// RQ1's control arm must differ from the default hide-and-seek config by its curriculum alone:
// the default with each parameter set to its curriculum's last lesson must read as the control.
TEST(ConfigParserTest, Rq1ControlIsTheDefaultWithoutCurriculum) {
  RunConfig expected = load_run_config("configs/hide_and_seek.yaml");
  const RunConfig control = load_run_config("configs/experiments/rq1_no_curriculum.yaml");
  ASSERT_EQ(expected.environment_parameters.count("level"), 1u);
  std::map<std::string, EnvironmentParameterSettings> frozen;
  for (const auto& [name, settings] : expected.environment_parameters) {
    if (!settings.is_curriculum()) {
      frozen[name] = settings;
      continue;
    }
    const Lesson& last = settings.curriculum.back();
    frozen[name].sampler = last.value;
    for (const auto& [other, sampler] : last.other_parameters) frozen[other].sampler = sampler;
  }
  EXPECT_EQ(frozen.at("level").sampler.value, 4.f);
  expected.environment_parameters = frozen;
  expected.checkpoint_settings.run_id = control.checkpoint_settings.run_id;
  EXPECT_EQ(run_config_to_yaml(control), run_config_to_yaml(expected));
}

TEST(ConfigParserErrorTest, CurriculumErrors) {
  expect_error(with_parameters("  h:\n    curriculum: []\n"), "environment_parameters.h.curriculum",
               7, "expected a non-empty list of lessons");
  expect_error(with_parameters("  h:\n    curriculum:\n"), "environment_parameters.h.curriculum", 7,
               "expected a non-empty list of lessons");
  // Every lesson but the last needs a completion_criteria.
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n        value: 1\n"
                               "      - name: B\n        value: 2\n"),
               "environment_parameters.h.curriculum[0].completion_criteria", 8,
               "missing: lesson 'A' is not the last lesson, so it needs a completion_criteria");
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n        value: 1\n"
                               "        completion_criteria: null\n"
                               "      - name: B\n        value: 2\n"),
               "environment_parameters.h.curriculum[0].completion_criteria", 8, "lesson 'A'");
  expect_error(with_parameters("  h:\n    curriculum:\n      - value: 1\n"),
               "environment_parameters.h.curriculum[0].name", 8, "missing: the lesson's name");
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n"),
               "environment_parameters.h.curriculum[0].value", 8, "missing: the parameter's value");
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n        value: 1\n"
                               "      - 5\n"),
               "environment_parameters.h.curriculum[1]", 10, "expected a lesson");
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n        valu: 1\n"),
               "environment_parameters.h.curriculum[0]", 9,
               "unknown key 'valu' (did you mean 'value'?)");
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n        value: [1]\n"),
               "environment_parameters.h.curriculum[0].value", 9,
               "expected a number or a sampler (sampler_type, sampler_parameters), got a list");
  expect_error(with_parameters("  h:\n    curriculum:\n      - name: A\n        value: 1\n"
                               "    sampler_type: uniform\n"),
               "environment_parameters.h.sampler_type", 10, "does not go with curriculum");
  expect_error(with_parameters("  h:\n    curiculum: []\n"), "environment_parameters.h", 7,
               "unknown key 'curiculum' (did you mean 'curriculum'?)");
}

TEST(ConfigParserErrorTest, SamplerErrors) {
  const std::string p = "environment_parameters.m";
  expect_error(with_parameters("  m:\n    sampler_type: uniform\n    sampler_parameters:\n"
                               "      min_value: 5\n      max_value: 1\n"),
               p + ".sampler_parameters", 8,
               "min_value (5.0) must not be greater than max_value (1.0)");
  expect_error(with_parameters("  m:\n    sampler_type: uniform\n    sampler_parameters:\n"
                               "      min_value: 2\n"),
               p + ".sampler_parameters", 8, "min_value (2.0) must not be greater than max_value");
  expect_error(with_parameters("  m:\n    sampler_type: gaussian\n    sampler_parameters:\n"
                               "      mean: 0\n      st_dev: -1\n"),
               p + ".sampler_parameters.st_dev", 10, "expected a number >= 0, got '-1'");
  expect_error(with_parameters("  m:\n    sampler_type: multirangeuniform\n"
                               "    sampler_parameters:\n      intervals: [[0, 1], [3, 2]]\n"),
               p + ".sampler_parameters.intervals[1]", 9, "min (3.0) must not be greater than max");
  expect_error(with_parameters("  m:\n    sampler_type: multirangeuniform\n"
                               "    sampler_parameters:\n      intervals: [[0, 1, 2]]\n"),
               p + ".sampler_parameters.intervals[0]", 9, "expected an interval [min, max]");
  expect_error(with_parameters("  m:\n    sampler_type: multirangeuniform\n"
                               "    sampler_parameters:\n      intervals: []\n"),
               p + ".sampler_parameters.intervals", 9, "expected a non-empty list of intervals");
  expect_error(with_parameters("  m:\n    sampler_type: multirangeuniform\n"
                               "    sampler_parameters:\n      intervals: [[0, x]]\n"),
               p + ".sampler_parameters.intervals[0][1]", 9, "expected a finite number, got 'x'");
  expect_error(with_parameters("  m:\n    sampler_type: normal\n    sampler_parameters: {}\n"),
               p + ".sampler_type", 7,
               "expected one of uniform, gaussian, multirangeuniform, constant, got 'normal'");
  expect_error(with_parameters("  m:\n    sampler_type: uniform\n"), p + ".sampler_parameters", 6,
               "missing: the settings of the uniform sampler");
  expect_error(with_parameters("  m:\n    sampler_parameters: {}\n"), p + ".sampler_type", 6,
               "missing: the sampler");
  expect_error(with_parameters("  m:\n    sampler_type: uniform\n    sampler_parameters: null\n"),
               p + ".sampler_parameters", 8, "expected a mapping, got null");
  expect_error(with_parameters("  m:\n    sampler_type: uniform\n    sampler_parameters:\n"
                               "      min: 0\n"),
               p + ".sampler_parameters", 9, "unknown key 'min'");
  expect_error(with_parameters("  m:\n    sampler_type: gaussian\n    sampler_parameters:\n"
                               "      min_value: 0\n"),
               p + ".sampler_parameters", 9, "unknown key 'min_value'");
  expect_error(with_parameters("  m:\n    value: 3\n"), p, 7,
               "unknown key 'value' (expected one of: curriculum, sampler_type, "
               "sampler_parameters)");
  expect_error(with_parameters("  m: [1, 2]\n"), p, 6,
               "expected a number, a sampler (sampler_type, sampler_parameters) or a curriculum");
  expect_error(with_parameters("  m:\n"), p, 6, "expected a number, a sampler");
}

// ---------------------------------------------------------------------------------------------
// default_settings.

TEST(ConfigParserTest, DefaultSettingsMergeKeyByKey) {
  const RunConfig config = parse(R"(default_settings:
  trainer_type: ppo
  hyperparameters:
    batch_size: 256
    buffer_size: 2560
    learning_rate: 1.0e-3
    learning_rate_schedule: constant
  network_settings:
    hidden_units: 64
    normalize: true
  reward_signals:
    extrinsic:
      gamma: 0.9
  max_steps: 1000
behaviors:
  Seeker:
    hyperparameters:
      batch_size: 128
    network_settings:
      num_layers: 3
  Hider:
    trainer_type: poca
    hyperparameters:
      learning_rate_schedule: linear
    reward_signals:
      extrinsic:
        strength: 0.5
    max_steps: 2000
env_settings:
  env_id: HideAndSeek
)");
  ASSERT_TRUE(config.default_settings.has_value());
  const BehaviorConfig& defaults = *config.default_settings;
  EXPECT_EQ(defaults.hyperparameters.batch_size, 256);
  EXPECT_EQ(defaults.hyperparameters.beta_schedule, Schedule::kConstant);
  EXPECT_EQ(defaults.max_steps, 1000);

  const BehaviorConfig& seeker = config.behaviors.at("Seeker");
  EXPECT_EQ(seeker.hyperparameters.batch_size, 128);    // own key
  EXPECT_EQ(seeker.hyperparameters.buffer_size, 2560);  // from default_settings
  EXPECT_EQ(seeker.hyperparameters.learning_rate, 1e-3f);
  EXPECT_EQ(seeker.hyperparameters.learning_rate_schedule, Schedule::kConstant);
  EXPECT_EQ(seeker.hyperparameters.beta_schedule, Schedule::kConstant);
  EXPECT_EQ(seeker.hyperparameters.num_epoch, 3);       // ML-Agents default
  EXPECT_EQ(seeker.network_settings.num_layers, 3);     // own key
  EXPECT_EQ(seeker.network_settings.hidden_units, 64);  // from default_settings
  EXPECT_TRUE(seeker.network_settings.normalize);       // from default_settings
  EXPECT_EQ(seeker.extrinsic.gamma, 0.9f);
  EXPECT_EQ(seeker.max_steps, 1000);

  const BehaviorConfig& hider = config.behaviors.at("Hider");
  EXPECT_EQ(hider.trainer_type, "poca");
  EXPECT_EQ(hider.hyperparameters.batch_size, 256);
  EXPECT_EQ(hider.hyperparameters.learning_rate_schedule, Schedule::kLinear);
  // Schedules not given anywhere follow the behavior's own learning_rate_schedule.
  EXPECT_EQ(hider.hyperparameters.beta_schedule, Schedule::kLinear);
  EXPECT_EQ(hider.hyperparameters.epsilon_schedule, Schedule::kLinear);
  EXPECT_EQ(hider.extrinsic.gamma, 0.9f);     // from default_settings
  EXPECT_EQ(hider.extrinsic.strength, 0.5f);  // own key
  EXPECT_EQ(hider.max_steps, 2000);
  EXPECT_EQ(hider.network_settings.hidden_units, 64);

  // Behaviors the file does not list get default_settings.
  EXPECT_EQ(&behavior_config(config, "Seeker"), &config.behaviors.at("Seeker"));
  EXPECT_EQ(&behavior_config(config, "Referee"), &*config.default_settings);
}

TEST(ConfigParserTest, DefaultSettingsAloneIsEnough) {
  const RunConfig config =
      parse("default_settings:\n  max_steps: 10\nenv_settings:\n  env_id: CartPole\n");
  EXPECT_TRUE(config.behaviors.empty());
  EXPECT_EQ(behavior_config(config, "Anything").max_steps, 10);
}

TEST(ConfigParserTest, UnknownBehaviorWithoutDefaultSettingsIsAnError) {
  const RunConfig config = parse(k3DBall);
  try {
    behavior_config(config, "3DBal");
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.file(), kSource);
    EXPECT_EQ(error.key_path(), "behaviors.3DBal");
    EXPECT_NE(error.problem().find("behavior '3DBal' is not configured"), std::string::npos);
    EXPECT_NE(error.problem().find("did you mean '3DBall'?"), std::string::npos);
  }
}

// ---------------------------------------------------------------------------------------------
// Errors: unknown keys.

TEST(ConfigParserErrorTest, UnknownKeySuggestsTheClosestName) {
  expect_error(cartpole_with("    hyperparameters:\n      learning_rat: 0.1\n"),
               "behaviors.CartPole.hyperparameters", 4,
               "unknown key 'learning_rat' (did you mean 'learning_rate'?)");
  expect_error("behaviours:\n  CartPole:\n", "", 1,
               "unknown key 'behaviours' (did you mean 'behaviors'?)");
  expect_error(cartpole_with("    reward_signals:\n      extrinsic:\n        gama: 0.9\n"),
               "behaviors.CartPole.reward_signals.extrinsic", 5,
               "unknown key 'gama' (did you mean 'gamma'?)");
  expect_error(cartpole_with("") + "  num_env: 4\n", "env_settings", 5,
               "unknown key 'num_env' (did you mean 'num_envs'?)");
  expect_error(cartpole_with("") + "checkpoint_settings:\n  run-id: x\n", "checkpoint_settings", 6,
               "did you mean 'run_id'?");
  expect_error(cartpole_with("") + "engine_settings:\n  widht: 84\n", "engine_settings", 6,
               "did you mean 'width'?");
}

TEST(ConfigParserErrorTest, UnknownKeyWithoutCloseNameListsTheKeys) {
  expect_error(cartpole_with("    network_settings:\n      colour: red\n"),
               "behaviors.CartPole.network_settings", 4,
               "unknown key 'colour' (expected one of: normalize, normalize_grids, hidden_units");
  // SAC hyperparameters are unknown to the PPO schema.
  expect_error(cartpole_with("    hyperparameters:\n      tau: 0.005\n"),
               "behaviors.CartPole.hyperparameters", 4, "unknown key 'tau'");
}

TEST(ConfigParserErrorTest, RepeatedKey) {
  expect_error(cartpole_with("    max_steps: 10\n    max_steps: 20\n"), "behaviors.CartPole", 4,
               "key 'max_steps' appears twice");
}

// ---------------------------------------------------------------------------------------------
// Errors: wrong types.

TEST(ConfigParserErrorTest, StringWhereNumber) {
  const std::string yaml = cartpole_with("    hyperparameters:\n      batch_size: abc\n");
  expect_error(yaml, "behaviors.CartPole.hyperparameters.batch_size", 4,
               "expected a positive integer, got 'abc'");
  EXPECT_STREQ(parse_error(yaml).what(),
               "configs/test.yaml:4: behaviors.CartPole.hyperparameters.batch_size: expected a "
               "positive integer, got 'abc'");
  expect_error(cartpole_with("    hyperparameters:\n      learning_rate: fast\n"),
               "behaviors.CartPole.hyperparameters.learning_rate", 4,
               "expected a number > 0, got 'fast'");
  // Quoted numbers are strings.
  expect_error(cartpole_with("    hyperparameters:\n      batch_size: \"64\"\n"),
               "behaviors.CartPole.hyperparameters.batch_size", 4,
               "expected a positive integer, got the string \"64\"");
  expect_error(cartpole_with("") + "  params:\n    gravity: strong\n",
               "env_settings.params.gravity", 6, "expected a finite number, got 'strong'");
  expect_error(cartpole_with("") + "environment_parameters:\n  mass: heavy\n",
               "environment_parameters.mass", 6, "expected a finite number, got 'heavy'");
  expect_error(cartpole_with("    reward_signals:\n      extrinsic:\n        strength: .nan\n"),
               "behaviors.CartPole.reward_signals.extrinsic.strength", 5,
               "expected a finite number, got '.nan'");
}

TEST(ConfigParserErrorTest, FloatWhereInteger) {
  expect_error(cartpole_with("    hyperparameters:\n      batch_size: 64.5\n"),
               "behaviors.CartPole.hyperparameters.batch_size", 4,
               "expected a positive integer, got '64.5'");
  expect_error(cartpole_with("    time_horizon: 1.0e-2\n"), "behaviors.CartPole.time_horizon", 3,
               "expected a positive integer, got '1.0e-2'");
  expect_error(cartpole_with("    hyperparameters:\n      num_epoch: 1e10\n"),
               "behaviors.CartPole.hyperparameters.num_epoch", 4,
               "expected a positive integer no larger than 2147483647, got '1e10'");
}

TEST(ConfigParserErrorTest, ListOrScalarWhereMapping) {
  expect_error(cartpole_with("    hyperparameters: [64, 640]\n"),
               "behaviors.CartPole.hyperparameters", 3, "expected a mapping, got a list");
  expect_error(cartpole_with("    network_settings: big\n"), "behaviors.CartPole.network_settings",
               3, "expected a mapping, got 'big'");
  expect_error("behaviors:\n  - CartPole\nenv_settings:\n  env_id: CartPole\n", "behaviors", 1,
               "expected a mapping, got a list");
  expect_error("behaviors:\n  CartPole: 3\nenv_settings:\n  env_id: CartPole\n",
               "behaviors.CartPole", 2, "expected a mapping, got '3'");
}

TEST(ConfigParserErrorTest, WrongScalarKinds) {
  expect_error(cartpole_with("    network_settings:\n      normalize: maybe\n"),
               "behaviors.CartPole.network_settings.normalize", 4,
               "expected true or false, got 'maybe'");
  expect_error(cartpole_with("    network_settings:\n      normalize: \"true\"\n"),
               "behaviors.CartPole.network_settings.normalize", 4,
               "expected true or false, got the string \"true\"");
  expect_error(cartpole_with("    hyperparameters:\n      max_grad_norm: [1]\n"),
               "behaviors.CartPole.hyperparameters.max_grad_norm", 4,
               "expected a number >= 0, got a list");
  expect_error("behaviors:\n  CartPole:\nenv_settings:\n  env_id: [CartPole]\n",
               "env_settings.env_id", 4, "expected a string, got a list");
  expect_error(cartpole_with("    hyperparameters:\n      learning_rate_schedule: lineal\n"),
               "behaviors.CartPole.hyperparameters.learning_rate_schedule", 4,
               "expected one of linear, constant, got 'lineal' (did you mean 'linear'?)");
  expect_error(cartpole_with("    network_settings:\n      activation: gelu\n"),
               "behaviors.CartPole.network_settings.activation", 4,
               "expected one of swish, tanh, relu, got 'gelu'");
  expect_error(cartpole_with("    network_settings:\n      vis_encode_type: nature\n"),
               "behaviors.CartPole.network_settings.vis_encode_type", 4,
               "expected one of simple, nature_cnn, resnet, match3, fully_connected");
  expect_error(cartpole_with("    network_settings:\n      goal_conditioning_type: film\n"),
               "behaviors.CartPole.network_settings.goal_conditioning_type", 4,
               "expected one of hyper, none, got 'film'");
  expect_error(cartpole_with("") + "debug: 1\n", "debug", 5, "expected true or false, got '1'");
}

// ---------------------------------------------------------------------------------------------
// Errors: out-of-range values.

TEST(ConfigParserErrorTest, OutOfRangeValues) {
  struct Case {
    std::string section;  // lines spliced into behaviors.CartPole
    std::string key_path;
    std::string problem;
  };
  const std::string h = "    hyperparameters:\n      ";
  const std::string n = "    network_settings:\n      ";
  const std::string r = "    reward_signals:\n      extrinsic:\n        ";
  const std::string hp = "behaviors.CartPole.hyperparameters.";
  const std::string np = "behaviors.CartPole.network_settings.";
  const std::string rp = "behaviors.CartPole.reward_signals.extrinsic.";
  const Case cases[] = {
      {h + "batch_size: 0\n", hp + "batch_size", "expected a positive integer, got '0'"},
      {h + "buffer_size: -5\n", hp + "buffer_size", "expected a positive integer, got '-5'"},
      {h + "learning_rate: 0\n", hp + "learning_rate", "expected a number > 0, got '0'"},
      {h + "beta: -0.1\n", hp + "beta", "expected a number >= 0, got '-0.1'"},
      {h + "epsilon: 1\n", hp + "epsilon", "expected a number in (0, 1), got '1'"},
      {h + "epsilon: 0\n", hp + "epsilon", "expected a number in (0, 1), got '0'"},
      {h + "lambd: 1.5\n", hp + "lambd", "expected a number in [0, 1], got '1.5'"},
      {h + "num_epoch: 0\n", hp + "num_epoch", "expected a positive integer, got '0'"},
      {h + "max_grad_norm: -1\n", hp + "max_grad_norm", "expected a number >= 0, got '-1'"},
      {h + "discrete_beta: -0.5\n", hp + "discrete_beta", "expected a number >= 0, got '-0.5'"},
      {h + "discrete_beta_end: -1\n", hp + "discrete_beta_end", "expected a number >= 0, got '-1'"},
      {h + "discrete_beta_steps: 0\n", hp + "discrete_beta_steps",
       "expected a positive integer, got '0'"},
      {h + "learning_rate: 1e50\n", hp + "learning_rate", "out of the range of a 32-bit float"},
      {n + "hidden_units: 0\n", np + "hidden_units", "expected a positive integer, got '0'"},
      {n + "num_layers: 0\n", np + "num_layers", "expected a positive integer, got '0'"},
      {r + "gamma: 0\n", rp + "gamma", "expected a number in (0, 1], got '0'"},
      {r + "gamma: 1.01\n", rp + "gamma", "expected a number in (0, 1], got '1.01'"},
      {"    time_horizon: 0\n", "behaviors.CartPole.time_horizon", "expected a positive integer"},
      {"    max_steps: 0\n", "behaviors.CartPole.max_steps", "expected a positive integer"},
      {"    summary_freq: -1\n", "behaviors.CartPole.summary_freq", "expected a positive integer"},
      {"    checkpoint_interval: 0\n", "behaviors.CartPole.checkpoint_interval",
       "expected a positive integer"},
      {"    keep_checkpoints: 0\n", "behaviors.CartPole.keep_checkpoints",
       "expected a positive integer"},
      {"    max_steps: 99999999999999999999\n", "behaviors.CartPole.max_steps",
       "no larger than 9223372036854775807"},
  };
  for (const Case& c : cases) expect_error(cartpole_with(c.section), c.key_path, 0, c.problem);

  const std::string env = "behaviors:\n  CartPole:\nenv_settings:\n  env_id: CartPole\n  ";
  expect_error(env + "num_envs: 0\n", "env_settings.num_envs", 5,
               "expected a positive integer, got '0'");
  expect_error(env + "num_threads: -1\n", "env_settings.num_threads", 5,
               "expected a non-negative integer, got '-1'");
  expect_error(env + "seed: -2\n", "env_settings.seed", 5, "expected an integer >= -1, got '-2'");
  expect_error(env + "stagger_steps: -5\n", "env_settings.stagger_steps", 5,
               "expected a non-negative integer, got '-5'");
  expect_error("behaviors:\n  CartPole:\nenv_settings:\n  env_id: \"\"\n", "env_settings.env_id", 4,
               "must not be empty");
  expect_error(cartpole_with("") + "checkpoint_settings:\n  run_id: a/b\n",
               "checkpoint_settings.run_id", 6, "expected a folder name without '/'");
  expect_error(cartpole_with("") + "checkpoint_settings:\n  results_dir: \"\"\n",
               "checkpoint_settings.results_dir", 6, "must not be empty");
}

TEST(ConfigParserErrorTest, BufferSmallerThanBatch) {
  expect_error(
      cartpole_with("    hyperparameters:\n      batch_size: 512\n      buffer_size: 256\n"),
      "behaviors.CartPole.hyperparameters.buffer_size", 5,
      "buffer_size (256) must be at least batch_size (512)");
  // The buffer comes from default_settings; the behavior's batch_size breaks it.
  expect_error(R"(default_settings:
  hyperparameters:
    batch_size: 64
    buffer_size: 640
behaviors:
  CartPole:
    hyperparameters:
      batch_size: 1024
env_settings:
  env_id: CartPole
)",
               "behaviors.CartPole.hyperparameters.batch_size", 8,
               "buffer_size (640) must be at least batch_size (1024)");
  // A buffer that is not a multiple of the batch is accepted (ML-Agents only warns).
  EXPECT_EQ(parse(cartpole_with("    hyperparameters:\n      batch_size: 100\n      buffer_size: "
                                "250\n"))
                .behaviors.at("CartPole")
                .hyperparameters.buffer_size,
            250);
}

// ---------------------------------------------------------------------------------------------
// Errors: ML-Agents features we do not have.

TEST(ConfigParserErrorTest, UnsupportedTrainers) {
  expect_error(cartpole_with("    trainer_type: sac\n    hyperparameters:\n      tau: 0.01\n"),
               "behaviors.CartPole.trainer_type", 3,
               "trainer_type 'sac' is not supported (supported: ppo, poca)");
  expect_error(cartpole_with("    trainer_type: coma\n"), "behaviors.CartPole.trainer_type", 3,
               "'coma' is not supported");
  expect_error(cartpole_with("    trainer_type: ppx\n"), "behaviors.CartPole.trainer_type", 3,
               "expected one of ppo, poca, got 'ppx' (did you mean 'ppo'?)");
}

TEST(ConfigParserErrorTest, UnsupportedBehaviorFeatures) {
  expect_error(cartpole_with("    network_settings:\n      memory:\n        memory_size: 128\n"),
               "behaviors.CartPole.network_settings.memory", 4, "memory (LSTM) is not supported");
  for (const std::string signal : {"curiosity", "gail", "rnd"}) {
    expect_error(
        cartpole_with("    reward_signals:\n      " + signal + ":\n        strength: 0.02\n"),
        "behaviors.CartPole.reward_signals." + signal, 4,
        "the " + signal + " reward signal is not supported (only extrinsic)");
  }
  expect_error(cartpole_with("    behavioral_cloning:\n      demo_path: x.demo\n"),
               "behaviors.CartPole.behavioral_cloning", 3, "behavioral_cloning is not supported");
}

TEST(ConfigParserErrorTest, UnsupportedRunSettings) {
  expect_error("behaviors:\n  CartPole:\nenv_settings:\n  env_path: Builds/3DBall.x86_64\n",
               "env_settings.env_path", 4,
               "ML-Agents' env_path (a Unity build) is not supported: name a registered "
               "environment with env_settings.env_id");
  expect_error(cartpole_with("") + "torch_settings:\n  device: cuda\n", "torch_settings.device", 6,
               "only 'cpu' is supported, got 'cuda'");
  expect_error(cartpole_with("") + "checkpoint_settings:\n  load_model: true\n",
               "checkpoint_settings.load_model", 6, "use resume: true");
  expect_error(cartpole_with("") + "checkpoint_settings:\n  inference: true\n",
               "checkpoint_settings.inference", 6, "use `rlt eval`");
}

TEST(ConfigParserErrorTest, MissingEnvId) {
  expect_error("behaviors:\n  CartPole:\n", "env_settings.env_id", 0,
               "missing: name a registered environment with env_settings.env_id");
  expect_error("behaviors:\n  CartPole:\nenv_settings:\n  num_envs: 2\n", "env_settings.env_id", 3,
               "missing");
  expect_error("behaviors:\n  CartPole:\nenv_settings:\n  env_id:\n", "env_settings.env_id", 4,
               "expected a string, got null");
}

// ---------------------------------------------------------------------------------------------
// Errors: the file as a whole.

TEST(ConfigParserErrorTest, NoBehaviors) {
  expect_error("env_settings:\n  env_id: CartPole\n", "", 0,
               "no behaviors configured: give `behaviors`");
  expect_error("behaviors: {}\nenv_settings:\n  env_id: CartPole\n", "behaviors", 1,
               "no behaviors configured");
  expect_error("behaviors:\ndefault_settings:\nenv_settings:\n  env_id: CartPole\n", "behaviors", 1,
               "no behaviors configured");
}

TEST(ConfigParserErrorTest, EmptyOrMalformedDocument) {
  expect_error("", "", 0, "the configuration is empty");
  expect_error("# only a comment\n\n", "", 0, "the configuration is empty");
  expect_error("---\n...\n", "", 0, "the configuration is empty");
  expect_error("- behaviors\n", "", 1, "expected a mapping of sections");
  expect_error("behaviors:\n  A:\n---\nbehaviors:\n  B:\n", "", 0,
               "expected one YAML document, found 2");
}

TEST(ConfigParserErrorTest, YamlSyntaxErrorHasTheLine) {
  const ConfigError error =
      parse_error("behaviors:\n  CartPole:\n    hyperparameters: {batch_size: 64\n");
  EXPECT_EQ(error.file(), kSource);
  EXPECT_EQ(error.key_path(), "");
  EXPECT_GT(error.line(), 0);
  EXPECT_NE(error.problem().find("YAML syntax error"), std::string::npos) << error.what();
  const ConfigError tab = parse_error("behaviors:\n  CartPole:\n\t max_steps: 3\n");
  EXPECT_EQ(tab.line(), 3) << tab.what();
  EXPECT_NE(std::string(tab.what()).find("configs/test.yaml:3: YAML syntax error"),
            std::string::npos)
      << tab.what();
}

// A temporary file that is removed at the end of the test.
class TempFile {
 public:
  explicit TempFile(const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("rlt_config_test_" + std::to_string(::getpid()) + ".yaml")) {
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

TEST(ConfigParserFileTest, LoadsAFileAndNamesItInErrors) {
  {
    TempFile file(k3DBall);
    const RunConfig config = load_run_config(file.path());
    EXPECT_EQ(config.source_file, file.path());
    EXPECT_EQ(config.behaviors.at("3DBall").hyperparameters.batch_size, 64);
  }
  {
    TempFile file(cartpole_with("    max_steps: lots\n"));
    try {
      load_run_config(file.path());
      FAIL() << "no ConfigError";
    } catch (const ConfigError& error) {
      EXPECT_EQ(error.file(), file.path());
      EXPECT_EQ(
          std::string(error.what()).rfind(file.path() + ":3: behaviors.CartPole.max_steps: ", 0),
          0u)
          << error.what();
    }
  }
}

TEST(ConfigParserFileTest, MissingFileAndDirectory) {
  const std::string missing = "configs/does_not_exist_42.yaml";
  try {
    load_run_config(missing);
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.file(), missing);
    EXPECT_NE(std::string(error.what()).find(missing + ": cannot read the configuration"),
              std::string::npos)
        << error.what();
    EXPECT_NE(error.problem().find("No such file"), std::string::npos) << error.what();
  }
  const std::string directory = std::filesystem::temp_directory_path().string();
  try {
    load_run_config(directory);
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.file(), directory);
    EXPECT_NE(error.problem().find("it is a directory"), std::string::npos) << error.what();
  }
}

TEST(ConfigParserFileTest, EmptyFile) {
  TempFile file("");
  try {
    load_run_config(file.path());
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.file(), file.path());
    EXPECT_NE(error.problem().find("empty"), std::string::npos) << error.what();
  }
}

TEST(ConfigParserTest, ConfigErrorIsARuntimeError) {
  try {
    parse("");
    FAIL() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(kSource), std::string::npos);
  }
}

// ---------------------------------------------------------------------------------------------
// Writing.

TEST(ConfigWriterTest, RoundTripOfAnMlAgentsConfig) {
  const RunConfig config = parse(k3DBall);
  const std::string yaml = run_config_to_yaml(config);
  const RunConfig again = load_run_config_from_string(yaml, "resolved.yaml");
  expect_same(config, again);
  EXPECT_EQ(run_config_to_yaml(again), yaml);
  // Every field is spelled out, in the ML-Agents schema.
  for (const char* key : {"trainer_type:",
                          "batch_size:",
                          "buffer_size:",
                          "learning_rate:",
                          "learning_rate_schedule:",
                          "beta:",
                          "beta_schedule:",
                          "discrete_beta:",
                          "epsilon:",
                          "epsilon_schedule:",
                          "lambd:",
                          "num_epoch:",
                          "shared_critic:",
                          "max_grad_norm:",
                          "normalize:",
                          "hidden_units:",
                          "num_layers:",
                          "vis_encode_type:",
                          "deterministic:",
                          "activation:",
                          "extrinsic:",
                          "gamma:",
                          "strength:",
                          "init_path:",
                          "keep_checkpoints:",
                          "checkpoint_interval:",
                          "max_steps:",
                          "time_horizon:",
                          "summary_freq:",
                          "threaded:",
                          "self_play:",
                          "env_id:",
                          "num_envs:",
                          "seed:",
                          "num_threads:",
                          "params:",
                          "run_id:",
                          "initialize_from:",
                          "resume:",
                          "force:",
                          "results_dir:",
                          "environment_parameters:",
                          "device: cpu"}) {
    EXPECT_NE(yaml.find(key), std::string::npos) << key << " missing from\n" << yaml;
  }
}

TEST(ConfigWriterTest, RoundTripWithDefaultSettingsAndAwkwardValues) {
  RunConfig config = parse(R"(default_settings:
  hyperparameters:
    learning_rate_schedule: constant
  even_checkpoints: true
  max_steps: 1000
behaviors:
  "true":
    hyperparameters:
      learning_rate: 0.1
  "123":
    trainer_type: poca
    init_path: "null"
env_settings:
  env_id: CartPole
checkpoint_settings:
  run_id: "456"
  initialize_from: "yes"
)");
  // Values with no short decimal spelling must survive too.
  BehaviorConfig& odd = config.behaviors.at("true");
  odd.hyperparameters.learning_rate = 1.0f / 3.0f;
  odd.hyperparameters.beta = 1e-7f;
  odd.hyperparameters.epsilon = 0.1f + 0.2f;
  odd.extrinsic.strength = -2.5f;
  odd.network_settings.activation = Activation::kRelu;
  odd.max_steps = 123456789012345;
  config.env_settings.params = {{"wind speed", 0.1f}, {"1", -0.0f}};
  config.environment_parameters = {{"null", 7.0f}, {"y", 1e30f}};
  config.env_settings.seed = 7;

  const std::string yaml = run_config_to_yaml(config);
  const RunConfig again = load_run_config_from_string(yaml, "resolved.yaml");
  expect_same(config, again);
  EXPECT_EQ(again.behaviors.at("123").init_path, "null");
  EXPECT_EQ(again.checkpoint_settings.initialize_from, "yes");
  EXPECT_EQ(again.default_settings->checkpoint_interval, 200);  // resolved from even_checkpoints
  EXPECT_EQ(run_config_to_yaml(again), yaml);
}

TEST(ConfigWriterTest, RoundTripOfSelfPlayAndCurricula) {
  RunConfig config = parse(kWallJumpCurriculum);
  SelfPlaySettings self_play;
  self_play.save_steps = 123;
  self_play.team_change = 7;
  self_play.play_against_latest_model_ratio = 0.1f + 0.2f;
  self_play.initial_elo = 1000.0 / 3.0;
  self_play.turn_parameters = {{"big_wall_height", 0.1f}, {"goal_size", 2.f}};
  config.behaviors.at("BigWallJump").self_play = self_play;
  // A one-lesson curriculum is not a plain sampler; a lesson named like its parameter neither.
  Lesson only;
  only.name = "solo";
  only.value = SamplerSettings::gaussian(0.1f, 1e-7f);
  config.environment_parameters["solo"].curriculum = {only};
  only.name = "same";
  config.environment_parameters["same"].curriculum = {only};
  config.environment_parameters["big_wall_height"].curriculum[0].completion_criteria->threshold =
      1.0 / 3.0;

  const std::string yaml = run_config_to_yaml(config);
  const RunConfig again = load_run_config_from_string(yaml, "resolved.yaml");
  expect_same(config, again);
  EXPECT_EQ(again.behaviors.at("BigWallJump").self_play, self_play);
  EXPECT_FALSE(again.behaviors.at("SmallWallJump").self_play.has_value());
  EXPECT_EQ(run_config_to_yaml(again), yaml);
  for (const char* key : {"sampler_type: uniform", "sampler_type: multirangeuniform",
                          "curriculum:", "completion_criteria:", "require_reset: true",
                          "team_change: 7", "goal_size: 3.0"}) {
    EXPECT_NE(yaml.find(key), std::string::npos) << key << " missing from\n" << yaml;
  }
}

TEST(ConfigWriterTest, EnumNames) {
  EXPECT_STREQ(schedule_name(Schedule::kLinear), "linear");
  EXPECT_STREQ(schedule_name(Schedule::kConstant), "constant");
  EXPECT_STREQ(activation_name(Activation::kSwish), "swish");
  EXPECT_STREQ(activation_name(Activation::kTanh), "tanh");
  EXPECT_STREQ(activation_name(Activation::kRelu), "relu");
}

}  // namespace
}  // namespace rlt
