// Reading and writing the run configuration (run_config.h) in Unity ML-Agents' trainer YAML schema.
//
// A file looks like an ML-Agents trainer config, with `env_settings.env_id` naming a registered
// environment instead of a Unity binary:
//
//   behaviors:
//     3DBall:
//       trainer_type: ppo
//       hyperparameters: {batch_size: 64, buffer_size: 12000, learning_rate: 3.0e-4}
//       network_settings: {normalize: true, hidden_units: 128, num_layers: 2}
//       reward_signals: {extrinsic: {gamma: 0.99, strength: 1.0}}
//       max_steps: 500000
//   env_settings: {env_id: Ball3D, num_envs: 8}
//
// What the parser does with each key:
// - Stored: every field of run_config.h, under the ML-Agents key of the same name
//   (reward_signals.extrinsic -> BehaviorConfig::extrinsic).
// - Merged: `default_settings` is the base of every behavior; a behavior's keys override it key by
//   key inside each section (hyperparameters, network_settings, reward_signals.extrinsic), as in
//   ML-Agents. `behaviors` holds the merged result; `default_settings` is kept for behaviors the
//   file does not list (see behavior_config()).
// - Resolved: beta_schedule and epsilon_schedule are filled from learning_rate_schedule when not
//   given; `even_checkpoints: true` sets checkpoint_interval to max_steps / keep_checkpoints;
//   self_play.team_change is 5 * save_steps when not given (ML-Agents' default).
// - self_play: a mapping of SelfPlaySettings keys (an empty one takes ML-Agents' defaults);
//   `self_play: null` means no self-play, also over a self_play of default_settings (ML-Agents'
//   merge), and a behavior's self_play keys override those of default_settings key by key.
// - environment_parameters: each entry is a constant (`gravity: 9.8`), a sampler
//   (`{sampler_type: uniform|gaussian|multirangeuniform|constant, sampler_parameters: {...}}`) or
//   a curriculum (`{curriculum: [{name, value, completion_criteria}, ...]}`, a lesson's value a
//   constant or a sampler), as in ML-Agents; our extension, a lesson's `other_parameters`
//   (`{name: value or sampler, ...}`), sets further parameters with it: every lesson of the
//   curriculum names the same ones, and neither an entry of its own nor another curriculum's
//   lessons may set them. Checked: sampler_parameters keys per sampler,
//   min_value <= max_value, st_dev >= 0, intervals [min, max] with min <= max, non-empty
//   curricula, a completion_criteria on every lesson but the last (one on the last lesson is
//   kept and never used), completion_criteria.behavior one of `behaviors` (any non-empty name
//   when default_settings is given), measure reward|progress, a progress threshold in [0, 1],
//   min_lesson_length >= 0. List items appear in key paths as `curriculum[1]`.
// - Accepted and ignored (there is no Unity engine or player here): engine_settings.{width,
//   height, quality_level, time_scale, target_frame_rate, capture_frame_rate, no_graphics};
//   env_settings.{env_args, base_port, num_areas, timeout_wait, max_lifetime_restarts,
//   restarts_rate_limit_n, restarts_rate_limit_period_s}; env_settings.env_path: null;
//   checkpoint_settings.train_model; checkpoint_settings.{load_model, inference}: false;
//   network_settings.goal_conditioning_type (hyper|none); network_settings.memory: null;
//   reward_signals.extrinsic.network_settings (any mapping); behavioral_cloning: null;
//   torch_settings.device: cpu or null; debug (bool); sampler_parameters.seed (ML-Agents' seed of
//   one sampler: draws come from the run's seeded engine instead).
//   A null section (`network_settings:` with nothing after it) means "not given" (self_play:
//   null excepted, see above).
// - Rejected with a ConfigError: unknown keys (with a did-you-mean suggestion), wrong types
//   (quoted strings where numbers or booleans are expected; a non-integral number where an
//   integer is expected, though integral values such as `5.0e5` are accepted as ML-Agents does),
//   out-of-range values, trainer_type other than ppo|poca, network_settings.memory (LSTM),
//   reward signals other than extrinsic (curiosity, gail, rnd), behavioral_cloning,
//   env_settings.env_path (a Unity binary; use env_id), a missing env_id, bad samplers and
//   curricula (see above), torch_settings.device other than cpu, checkpoint_settings.load_model:
//   true (use resume) and inference: true (use `rlt eval`), buffer_size < batch_size (ML-Agents
//   only warns; a buffer_size that is not a multiple of batch_size is accepted), a missing or
//   empty file, YAML syntax errors, and a file with neither `behaviors` nor `default_settings`.
// - Not checked here: whether env_id is a registered environment (the env registry does that).
#pragma once

#include <stdexcept>
#include <string>

#include "rl/config/run_config.h"

namespace rlt {

// A problem in a configuration. what() reads "FILE:LINE: KEY.PATH: PROBLEM", for example
// "configs/x.yaml:7: behaviors.CartPole.hyperparameters.batch_size: expected a positive integer,
// got 'abc'"; ":LINE" is left out when the line is unknown and "KEY.PATH: " when the problem is
// not about one key.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string file, std::string key_path, int line, std::string problem);

  const std::string& file() const { return file_; }          // file (or source name) of the YAML
  const std::string& key_path() const { return key_path_; }  // dotted key path; "" = whole file
  int line() const { return line_; }                         // 1-based line; 0 = unknown
  const std::string& problem() const { return problem_; }    // the message without the location

 private:
  std::string file_;
  std::string key_path_;
  int line_;
  std::string problem_;
};

// Reads and validates the YAML file at `path`. Throws ConfigError.
RunConfig load_run_config(const std::string& path);

// Same as load_run_config for YAML text; `source_name` stands for the file name in messages and in
// RunConfig::source_file, and a base_config in the text is read from disk relative to
// source_name's folder. Throws ConfigError.
RunConfig load_run_config_from_string(const std::string& yaml, const std::string& source_name);

// The fully resolved configuration (every field, defaults filled in) in the same schema, such that
// load_run_config_from_string(run_config_to_yaml(c), ...) gives back `c` (except source_file).
std::string run_config_to_yaml(const RunConfig& config);

// The settings of `behavior`: its entry in config.behaviors, else config.default_settings.
// Throws ConfigError naming the behavior when neither exists.
const BehaviorConfig& behavior_config(const RunConfig& config, const std::string& behavior);

// YAML spellings of the enums: "linear"/"constant" and "swish"/"tanh"/"relu".
const char* schedule_name(Schedule schedule);
const char* activation_name(Activation activation);

}  // namespace rlt
