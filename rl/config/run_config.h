// The run configuration: Unity ML-Agents' trainer YAML schema as plain structs.
//
// Each field carries ML-Agents' default and meaning (mlagents/trainers/settings.py). Keys that
// ML-Agents does not have are marked "extension". Parsing (config_parser.h) fills these structs
// and rejects unknown keys, wrong types and out-of-range values with the file and key path.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rlt {

enum class Schedule { kLinear, kConstant };

struct Hyperparameters {
  int batch_size = 1024;           // experiences per gradient step (minibatch)
  int buffer_size = 10240;         // experiences collected before an update; multiple of batch_size
  float learning_rate = 3e-4f;     // Adam step size at step 0
  Schedule learning_rate_schedule = Schedule::kLinear;  // linear: decays to 1e-10 at max_steps
  float beta = 5e-3f;              // entropy bonus strength
  std::optional<Schedule> beta_schedule;     // default: learning_rate_schedule; linear -> 1e-5
  std::optional<float> discrete_beta;        // extension: the discrete branches' entropy bonus
                                             // (default: beta); decays as beta does
  // extension: with discrete_beta_steps > 0, the branches' bonus moves linearly from
  // discrete_beta at step 0 to discrete_beta_end at that step of the behavior and stays there
  // (beta_schedule's decay then applies to it as to beta)
  std::optional<float> discrete_beta_end;
  int64_t discrete_beta_steps = 0;
  float epsilon = 0.2f;            // PPO clip range of ratio and value
  std::optional<Schedule> epsilon_schedule;  // default: learning_rate_schedule; linear -> 0.1
  float lambd = 0.95f;             // GAE lambda
  int num_epoch = 3;               // passes over the buffer per update
  bool shared_critic = false;      // actor and critic share the body
  float max_grad_norm = 0.f;       // extension: clip the global gradient norm (0 = off, as ML-Agents)
  float value_loss_coef = 0.5f;    // extension: weight of the value loss (ML-Agents: 0.5)
};

enum class Activation { kSwish, kTanh, kRelu };

struct NetworkSettings {
  bool normalize = false;    // running mean/variance normalization of vector observations
  // extension: normalize grid observations too (ML-Agents never does; rlt did before
  // 2026-11-25, and hide-and-seek's seekers learned to chase sooner with it)
  bool normalize_grids = false;
  int hidden_units = 128;    // width of each hidden layer
  int num_layers = 2;        // hidden layers
  std::string vis_encode_type = "simple";  // encoder of grid observations
  bool deterministic = false;              // act with the distribution's mode during training
  Activation activation = Activation::kSwish;  // extension: ML-Agents uses swish
};

struct RewardSignal {
  float gamma = 0.99f;    // discount
  float strength = 1.0f;  // scale applied to the env reward
};

// Self-play (ML-Agents' ghost trainer): the behavior plays against snapshots of its own policy.
struct SelfPlaySettings {
  int64_t save_steps = 20000;    // trainer steps between snapshots added to the pool
  int64_t team_change = 100000;  // trainer steps before the learning team changes; ML-Agents'
                                 // default is 5 * save_steps (filled in when not given)
  int64_t swap_steps = 2000;     // ghost steps between swaps of the opponent snapshot
  int window = 10;               // snapshots kept in the pool
  float play_against_latest_model_ratio = 0.5f;  // probability of facing the current policy
  double initial_elo = 1200.0;                   // ELO rating at the start of training
  // Our extension: environment parameters that hold while this behavior's team is the learning
  // one, over the curriculum's and env_settings' values (episodes begun after the turn started
  // get them). It lets each team learn in the setting it needs, e.g. hiders met outside the room
  // while the seekers learn to chase.
  std::map<std::string, float> turn_parameters;

  bool operator==(const SelfPlaySettings& o) const {
    return save_steps == o.save_steps && team_change == o.team_change &&
           swap_steps == o.swap_steps && window == o.window &&
           play_against_latest_model_ratio == o.play_against_latest_model_ratio &&
           initial_elo == o.initial_elo && turn_parameters == o.turn_parameters;
  }
  bool operator!=(const SelfPlaySettings& o) const { return !(*this == o); }
};

struct BehaviorConfig {
  std::string trainer_type = "ppo";
  Hyperparameters hyperparameters;
  NetworkSettings network_settings;
  RewardSignal extrinsic;   // reward_signals.extrinsic; the only reward signal so far
  std::string init_path;    // checkpoint to initialize weights from ("" = none)
  int keep_checkpoints = 5;             // newest checkpoints kept on disk
  int64_t checkpoint_interval = 500000; // steps between checkpoints
  int64_t max_steps = 500000;           // steps of this behavior before training stops
  int time_horizon = 64;                // experiences per agent before a trajectory is cut (bootstrap)
  int64_t summary_freq = 50000;         // steps between summary lines
  bool threaded = false;                // accepted for compatibility; has no effect
  std::optional<SelfPlaySettings> self_play;  // none: ordinary training
};

struct EnvSettings {
  std::string env_id;        // extension: registered env name instead of a Unity binary
  int num_envs = 1;          // env instances stepped together
  int64_t seed = -1;         // base seed; -1 picks 0 (deterministic by default)
  int num_threads = 0;       // extension: env worker threads (0 = one per core, capped at num_envs)
  // extension: after every (re)start instance i plays i * stagger_steps / num_envs still steps
  // first (VectorEnv::stagger), so the instances' episodes are spread out; 0 = off
  int stagger_steps = 0;
  std::map<std::string, float> params;  // extension: env parameters applied at construction
};

struct CheckpointSettings {
  std::string run_id = "ppo";        // folder name under results_dir
  std::string initialize_from;       // run id to take initial weights from ("" = none)
  bool resume = false;
  bool force = false;
  std::string results_dir = "results";
};

// How an environment parameter's value is drawn at an environment reset (ML-Agents'
// ParameterRandomizationSettings). Only the fields of `type` are meaningful; each carries
// ML-Agents' default.
enum class SamplerType { kConstant, kUniform, kGaussian, kMultiRangeUniform };

struct SamplerSettings {
  SamplerType type = SamplerType::kConstant;
  float value = 0.f;      // constant
  float min_value = 0.f;  // uniform in [min_value, max_value]
  float max_value = 1.f;
  float mean = 1.f;  // gaussian
  float st_dev = 1.f;
  // multirangeuniform: an interval [a, b] is picked with probability proportional to b - a, then
  // a value uniformly inside it
  std::vector<std::array<float, 2>> intervals = {{0.f, 1.f}};

  static SamplerSettings constant(float value) {
    SamplerSettings s;
    s.value = value;
    return s;
  }
  static SamplerSettings uniform(float min_value, float max_value) {
    SamplerSettings s;
    s.type = SamplerType::kUniform;
    s.min_value = min_value;
    s.max_value = max_value;
    return s;
  }
  static SamplerSettings gaussian(float mean, float st_dev) {
    SamplerSettings s;
    s.type = SamplerType::kGaussian;
    s.mean = mean;
    s.st_dev = st_dev;
    return s;
  }
  static SamplerSettings multi_range_uniform(std::vector<std::array<float, 2>> intervals) {
    SamplerSettings s;
    s.type = SamplerType::kMultiRangeUniform;
    s.intervals = std::move(intervals);
    return s;
  }

  // Compares the type and the fields of that type.
  bool operator==(const SamplerSettings& o) const {
    if (type != o.type) return false;
    switch (type) {
      case SamplerType::kConstant:
        return value == o.value;
      case SamplerType::kUniform:
        return min_value == o.min_value && max_value == o.max_value;
      case SamplerType::kGaussian:
        return mean == o.mean && st_dev == o.st_dev;
      case SamplerType::kMultiRangeUniform:
        return intervals == o.intervals;
    }
    return false;
  }
  bool operator!=(const SamplerSettings& o) const { return !(*this == o); }
};

enum class CompletionMeasure { kReward, kProgress, kMetric };

// When a lesson is complete (ML-Agents' CompletionCriteriaSettings).
struct CompletionCriteria {
  // the behavior whose progress or rewards are measured (required for reward and progress); with
  // metric (optional) only the episodes that behavior learned from throughout count (in
  // self-play, those played entirely in its turns)
  std::string behavior;
  // reward: mean episode reward of the behavior since the lesson began; progress: steps /
  // max_steps; metric (our extension): mean of the env's episode metric `metric` over the episodes
  // played entirely in the lesson (e.g. HideAndSeek's fort_rate), so a lesson can wait for a skill
  CompletionMeasure measure = CompletionMeasure::kReward;
  std::string metric;            // measure metric: a key of the env's episode metrics
  int min_lesson_length = 0;     // episodes (of `behavior`; metric: the counted env episodes)
                                 // before it may end
  bool signal_smoothing = true;  // reward, metric: 0.25 * previous smoothed value + 0.75 * mean
  double threshold = 0.0;        // the measure must exceed it; progress: in [0, 1]
  bool require_reset = false;    // reset every environment as soon as the lesson ends
  // Our extension, reward and metric only: a lesson whose skill collapsed goes back one lesson.
  // When the mean measure (unsmoothed) of the lesson's last fallback_length counted episodes is at
  // or below fallback_threshold, the curriculum returns to the lesson before, whose criteria then
  // have to be met again. Unset: lessons only advance (ML-Agents). Ignored on a first lesson.
  std::optional<double> fallback_threshold;
  int fallback_length = 0;  // episodes; 0: min_lesson_length (at least 1)
  // Our extension: the env's strategies (EnvSpec::strategies, e.g. HideAndSeek's
  // running_and_chasing) that must have emerged before the lesson may end; until then a lesson
  // whose measure is met goes on. Empty: none.
  std::vector<std::string> after_emerged;

  bool operator==(const CompletionCriteria& o) const {
    return behavior == o.behavior && measure == o.measure && metric == o.metric &&
           min_lesson_length == o.min_lesson_length && signal_smoothing == o.signal_smoothing &&
           threshold == o.threshold && require_reset == o.require_reset &&
           fallback_threshold == o.fallback_threshold && fallback_length == o.fallback_length &&
           after_emerged == o.after_emerged;
  }
  // the episodes a fallback judges: fallback_length, or min_lesson_length when it is 0
  int fallback_episodes() const {
    return fallback_length > 0 ? fallback_length : std::max(1, min_lesson_length);
  }
  bool operator!=(const CompletionCriteria& o) const { return !(*this == o); }
};

// Our extension: a lesson whose value for one parameter follows the hiders' (or any measured
// behavior's) skill instead of staying fixed, by the weighted up-down staircase of Kaernbach
// ("Simple adaptive testing with the weighted up-down method", Perception & Psychophysics 49,
// 1991). The value starts at the lesson's own constant for the parameter; every episode the
// lesson's completion_criteria counts moves it step_up toward `end` when its measure exceeds the
// criteria's threshold and step_down back toward the start otherwise. It settles where the
// share of episodes above the threshold is step_down / (step_up + step_down), so it climbs
// while the skill is above that share and waits while it is below. The lesson completes once the
// value has reached `end` (and the criteria's min_lesson_length episodes were counted).
struct Staircase {
  std::string parameter;  // the curriculum's own name or one of the lesson's other_parameters
  double end = 1.0;       // the value at which the lesson completes
  double step_up = 0.0;   // > 0: toward end after an episode above the threshold
  double step_down = 0.0;  // >= 0: back toward the start after any other counted episode

  bool operator==(const Staircase& o) const {
    return parameter == o.parameter && end == o.end && step_up == o.step_up &&
           step_down == o.step_down;
  }
  bool operator!=(const Staircase& o) const { return !(*this == o); }
};

struct Lesson {
  std::string name;
  SamplerSettings value;
  // Our extension: other env parameters this lesson sets, so that one curriculum can move several
  // together (e.g. HideAndSeek's level and prop_start_offset, which starts again at every level).
  // Every lesson of a curriculum names the same ones, and no other entry of
  // environment_parameters may set them.
  std::map<std::string, SamplerSettings> other_parameters;
  // Our extension: behaviors that train on once the curriculum reaches this lesson, to the
  // given total of their steps (a budget above their own max_steps; e.g. the seekers of
  // hide-and-seek learning again against the level the hiders reached). From this lesson on a
  // behavior's max_steps is the largest of its own and the budgets of the lessons reached.
  std::map<std::string, int64_t> behavior_max_steps;
  // Required on every lesson but the last; on the last lesson it is accepted and never used.
  std::optional<CompletionCriteria> completion_criteria;
  // Our extension: the value of one parameter moves by the counted episodes (see Staircase);
  // needs completion_criteria measuring reward or metric, also on the last lesson.
  std::optional<Staircase> staircase;

  bool operator==(const Lesson& o) const {
    return name == o.name && value == o.value && other_parameters == o.other_parameters &&
           behavior_max_steps == o.behavior_max_steps &&
           completion_criteria == o.completion_criteria && staircase == o.staircase;
  }
  bool operator!=(const Lesson& o) const { return !(*this == o); }
};

// One entry of `environment_parameters`: a sampler (a constant is the plain `name: 3.0`), or a
// curriculum of lessons, each with its own sampler.
struct EnvironmentParameterSettings {
  SamplerSettings sampler;         // the value when `curriculum` is empty
  std::vector<Lesson> curriculum;  // non-empty: lesson-based; `sampler` is unused

  EnvironmentParameterSettings() = default;
  // A constant, as `name: 3.0` in the YAML; implicit so that `parameters["x"] = 3` reads naturally.
  EnvironmentParameterSettings(float constant)  // NOLINT(runtime/explicit)
      : sampler(SamplerSettings::constant(constant)) {}

  bool is_curriculum() const { return !curriculum.empty(); }
  // the other parameters its lessons set (every lesson names the same ones); none without lessons
  const std::map<std::string, SamplerSettings>& other_parameters() const {
    static const std::map<std::string, SamplerSettings> kNone;
    return is_curriculum() ? curriculum[0].other_parameters : kNone;
  }

  bool operator==(const EnvironmentParameterSettings& o) const {
    return curriculum == o.curriculum && (is_curriculum() || sampler == o.sampler);
  }
  bool operator!=(const EnvironmentParameterSettings& o) const { return !(*this == o); }
};

struct RunConfig {
  std::string source_file;                      // the YAML file it came from
  std::map<std::string, BehaviorConfig> behaviors;
  std::optional<BehaviorConfig> default_settings;
  EnvSettings env_settings;
  CheckpointSettings checkpoint_settings;
  // ML-Agents' environment_parameters: values applied at every environment reset, constants,
  // samplers or curricula (rl/curriculum/environment_parameter_manager.h applies them)
  std::map<std::string, EnvironmentParameterSettings> environment_parameters;
};

}  // namespace rlt
