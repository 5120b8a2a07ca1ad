// The run configuration: Unity ML-Agents' trainer YAML schema as plain structs.
//
// Each field carries ML-Agents' default and meaning (mlagents/trainers/settings.py). Keys that
// ML-Agents does not have are marked "extension". Parsing (config_parser.h) fills these structs
// and rejects unknown keys, wrong types and out-of-range values with the file and key path.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
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
};

struct EnvSettings {
  std::string env_id;        // extension: registered env name instead of a Unity binary
  int num_envs = 1;          // env instances stepped together
  int64_t seed = -1;         // base seed; -1 picks 0 (deterministic by default)
  int num_threads = 0;       // extension: env worker threads (0 = one per core, capped at num_envs)
  std::map<std::string, float> params;  // extension: env parameters applied at construction
};

struct CheckpointSettings {
  std::string run_id = "ppo";        // folder name under results_dir
  std::string initialize_from;       // run id to take initial weights from ("" = none)
  bool resume = false;
  bool force = false;
  std::string results_dir = "results";
};

struct RunConfig {
  std::string source_file;                      // the YAML file it came from
  std::map<std::string, BehaviorConfig> behaviors;
  std::optional<BehaviorConfig> default_settings;
  EnvSettings env_settings;
  CheckpointSettings checkpoint_settings;
  std::map<std::string, float> environment_parameters;  // constants applied at every reset
};

}  // namespace rlt
