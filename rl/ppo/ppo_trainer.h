// Proximal Policy Optimization for one behavior, with ML-Agents' trainer semantics.
//
// References: Schulman et al. 2017, "Proximal Policy Optimization Algorithms"; ML-Agents
// `mlagents/trainers/ppo/trainer.py` and `ppo/optimizer_torch.py` (trajectories cut at
// time_horizon, GAE per trajectory, advantages normalized over the update buffer, clipped value
// loss, loss = policy + 0.5 value - beta entropy (value weight configurable: value_loss_coef), linear decay of learning rate to 1e-10, epsilon to
// 0.1 and beta to 1e-5 over max_steps, buffer cleared after each update); CleanRL ppo.py for the
// textbook details.
// Deliberate differences from ML-Agents:
//   - the probability ratio is of the joint action (see action_distribution.h);
//   - values stored with an experience are computed when acting (CleanRL), not re-evaluated when
//     the trajectory is processed;
//   - optional global gradient-norm clipping (`max_grad_norm`, CleanRL), off by default.
// The minibatch gradient is computed by MlpPpoGradient (hand-written backward in Eigen), checked in
// tests against autograd through evaluate_actions() and ppo_loss().
// A "step" is one decision of one agent of this behavior.
#pragma once

#include <torch/torch.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rl/config/run_config.h"
#include "rl/core/experience_buffer.h"
#include "rl/core/fast_actor.h"
#include "rl/core/flat_adam.h"
#include "rl/core/policy_network.h"
#include "rl/core/running_normalizer.h"
#include "rl/ppo/mlp_ppo_gradient.h"
#include "rl/env_api/step_buffers.h"

namespace rlt {

struct UpdateStats {
  float policy_loss = 0, value_loss = 0, entropy = 0;
  float learning_rate = 0, epsilon = 0, beta = 0;
  int64_t experiences = 0;
};

// Rewards of episodes that ended since the statistics were last taken.
struct EpisodeStats {
  std::vector<float> returns;  // cumulative reward per finished agent episode
  std::vector<float> lengths;  // decisions per finished agent episode
};

class PpoTrainer {
 public:
  // `rows`: rows of the behavior's step buffers (num_envs * agent_slots); `env_name` for messages
  PpoTrainer(const BehaviorSpec& spec, const BehaviorConfig& config, int rows, uint64_t seed,
             const std::string& env_name = "");

  const std::string& behavior() const { return spec_.name; }
  const BehaviorConfig& config() const { return config_; }
  int64_t step() const { return step_; }
  int64_t updates() const { return updates_; }
  bool finished() const { return step_ >= config_.max_steps; }

  // Chooses actions for every row that needs one and writes them into `buf`.
  void act(BehaviorBuffers& buf);
  // Reads rewards and step types after the env step; ends or cuts trajectories.
  void observe(const BehaviorBuffers& buf);
  // Ends every running trajectory as interrupted (bootstrapping from its last observation).
  void interrupt_all(const BehaviorBuffers& buf);

  bool update_ready() const { return buffer_.size() >= config_.hyperparameters.buffer_size; }
  UpdateStats update();

  EpisodeStats take_episode_stats();

  PolicyNetwork& network() { return net_; }
  const RunningNormalizer* normalizer() const {
    return config_.network_settings.normalize ? &normalizer_ : nullptr;
  }
  int obs_size() const { return obs_size_; }
  const BehaviorSpec& spec() const { return spec_; }

  // weights, optimizer, normalizer, counters, random engine, update buffer, episode statistics
  void save(torch::serialize::OutputArchive& archive) const;
  void load(torch::serialize::InputArchive& archive);
  // weights and normalizer only (--initialize-from, init_path)
  void load_weights(torch::serialize::InputArchive& archive);

  // decayed value at the current step: linear schedules go from `initial` to `minimum` at max_steps
  float decayed(float initial, float minimum, Schedule schedule) const;

 private:
  struct Pending {          // a decision waiting for its reward
    bool active = false;
  };
  void gather_obs(const BehaviorBuffers& buf, const std::vector<int>& rows, RowMatrix& out,
                  const char* what) const;
  void end_trajectory(int row, float bootstrap_value);
  void refresh_actor();
  std::string where(const BehaviorBuffers& buf, int row) const;

  BehaviorSpec spec_;
  BehaviorConfig config_;
  std::string env_name_;
  int rows_ = 0, obs_size_ = 0;

  PolicyNetwork net_;
  std::unique_ptr<FlatAdam> optimizer_;
  std::unique_ptr<MlpPpoGradient> gradient_;  // minibatch loss and gradient (hand-written backward)
  RunningNormalizer normalizer_;
  FastActor actor_;
  bool actor_stale_ = true;
  std::mt19937_64 rng_;  // action sampling and minibatch shuffling

  int64_t step_ = 0, updates_ = 0;
  std::vector<uint8_t> pending_;               // [rows] row acted and awaits its reward
  std::vector<ExperienceBuffer> trajectories_; // [rows] running trajectory of the row's agent
  std::vector<std::vector<float>> rewards_;    // [rows][T] rewards of the running trajectory
  std::vector<double> episode_return_;         // [rows] cumulative reward of the running episode
  std::vector<int> episode_length_;            // [rows]
  ExperienceBuffer buffer_;                    // the update buffer
  EpisodeStats episode_stats_;

  // scratch reused across steps
  std::vector<int> act_rows_;
  RowMatrix act_obs_;
  ActBatch act_out_;
};

}  // namespace rlt
