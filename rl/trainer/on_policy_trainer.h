// What PPO and MA-POCA share: acting with an Eigen copy of the actor, per-agent trajectories cut at
// time_horizon, step counting, schedules, observation normalization, episode statistics and the
// checkpointed state. The algorithms differ in how a finished trajectory becomes training data
// (end_trajectories) and in the update.
//
// Reference: ML-Agents `trainers/trainer/on_policy_trainer.py` and `agent_processor.py`.
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
#include "rl/distributed/communicator.h"
#include "rl/env_api/step_buffers.h"

namespace rlt {

struct UpdateStats {
  float policy_loss = 0, value_loss = 0, baseline_loss = 0, entropy = 0;
  float learning_rate = 0, epsilon = 0, beta = 0;
  float discrete_beta = 0;  // the discrete branches' entropy bonus (beta unless configured)
  // how far the update moved the policy, averaged over its minibatches (each measured before its
  // gradient step): the approximate KL divergence from the policy that collected the buffer and
  // the share of rows whose probability ratio left [1 - epsilon, 1 + epsilon]
  float approx_kl = 0, clip_fraction = 0;
  int64_t experiences = 0;
  // floating-point operations of the update's matrix products (forward and backward, counted
  // from the layer shapes, see matmul_flops_per_experience()), for throughput reports
  double matmul_flops = 0;
};

// Rewards of episodes that ended since the statistics were last taken.
struct EpisodeStats {
  std::vector<float> returns;        // cumulative reward per finished agent episode
  std::vector<float> group_returns;  // cumulative group reward of the same episodes
  std::vector<float> lengths;        // decisions per finished agent episode
};

class OnPolicyTrainer {
 public:
  // `rows`: rows of the behavior's step buffers (num_envs * agent_slots); `env_name` for messages.
  // `with_critic`: whether the policy network carries PPO's value head.
  OnPolicyTrainer(const BehaviorSpec& spec, const BehaviorConfig& config, int rows, uint64_t seed,
                  const std::string& env_name, bool with_critic);
  virtual ~OnPolicyTrainer() = default;

  const std::string& behavior() const { return spec_.name; }
  const BehaviorSpec& spec() const { return spec_; }
  const BehaviorConfig& config() const { return config_; }
  int64_t step() const { return step_; }
  int64_t updates() const { return updates_; }
  bool finished() const { return step_ >= config_.max_steps; }
  // A new step budget (a curriculum lesson's behavior_max_steps): a finished trainer whose budget
  // grows trains again. Linear schedules then decay towards the new budget.
  void set_max_steps(int64_t max_steps) { config_.max_steps = max_steps; }
  int obs_size() const { return obs_size_; }

  // Chooses actions for every row that needs one (and, when `learner_rows` is given, whose entry
  // is 1) and writes them into `buf`; those decisions become experiences.
  void act(BehaviorBuffers& buf, const std::vector<uint8_t>* learner_rows = nullptr);
  // Reads rewards and step types after the env step; ends or cuts trajectories.
  void observe(const BehaviorBuffers& buf);
  // Ends every running trajectory as interrupted (bootstrapping from its last observation).
  void interrupt_all(const BehaviorBuffers& buf);

  bool update_ready() const { return buffer_.size() >= config_.hyperparameters.buffer_size; }
  virtual UpdateStats update() = 0;

  // Data-parallel training: this learner is one replica of `comm->world_size()` that agree on
  // every update (rl/distributed/data_parallel.h); nullptr trains alone. buffer_size and
  // batch_size are then the totals over the ranks: each rank takes its share of every minibatch.
  void set_communicator(Communicator* comm);
  // experiences in the update buffer of this rank
  int64_t buffered() const { return buffer_.size(); }
  // experiences recorded in trajectories not yet ended into the update buffer, over every row
  int64_t open_steps() const;
  // the step counter as the ranks agreed it (their decisions summed)
  void set_step(int64_t step) { step_ = step; }
  // every trained parameter, [P] (the network and extra_parameters())
  const torch::Tensor& flat_parameters() const { return optimizer_->flat_parameters(); }
  // root's parameters on every rank (the replicas start equal)
  void broadcast_parameters(int root);

  EpisodeStats take_episode_stats();

  PolicyNetwork& network() { return net_; }
  const RunningNormalizer* normalizer() const {
    return config_.network_settings.normalize ? &normalizer_ : nullptr;
  }
  // an Eigen copy of the current actor (for opponents and evaluation)
  FastActor fast_actor() const;

  // weights, optimizer, normalizer, counters, random engine, update buffer, episode statistics
  void save(torch::serialize::OutputArchive& archive) const;
  void load(torch::serialize::InputArchive& archive);
  // weights and normalizer only (--initialize-from, evaluation)
  void load_weights(torch::serialize::InputArchive& archive);

  // decayed value at the current step: linear schedules go from `initial` to `minimum` at max_steps
  float decayed(float initial, float minimum, Schedule schedule) const;

 protected:
  // Rows whose trajectory ends now: `terminated` ones with value 0 after the last step, the
  // `bootstrapped` ones (interrupted, cut at time_horizon) from the observation now in `buf`.
  // Implementations turn trajectories_[row] / rewards_[row] into update-buffer rows and clear them.
  virtual void end_trajectories(const BehaviorBuffers& buf, const std::vector<int>& terminated,
                                const std::vector<int>& bootstrapped) = 0;
  // The training reward of `row` for the step just observed: (reward + group reward) x strength.
  virtual float step_reward(const BehaviorBuffers& buf, int row) const;
  // Called after the actions of `rows` were chosen (act_out_ holds them, in the same order).
  virtual void on_acted(const BehaviorBuffers& buf, const std::vector<int>& rows) {}
  // Modules other than the policy network that are trained and checkpointed (the POCA critic).
  virtual std::vector<torch::Tensor> extra_parameters() { return {}; }
  virtual void save_extra(torch::serialize::OutputArchive& archive) const {}
  virtual void load_extra(torch::serialize::InputArchive& archive) {}

  // multiply-adds of one forward pass of the actor and of PPO's critic, per experience
  double actor_macs() const;
  double ppo_critic_macs() const;
  // multiply-adds of the actor's first layer (observations to hidden units), per experience
  double actor_input_macs() const;
  // the products' floating-point operations of one experience's forward and backward pass: 2 per
  // multiply-add forward, twice that backward (the weights' and the input's gradients), except
  // that layers reading the observations (input_macs of the macs) need no input gradient
  static double matmul_flops_per_experience(double macs, double input_macs) {
    return 6.0 * macs - 2.0 * input_macs;
  }

  // concatenated observations of `rows`: [rows, obs_size]; NaN and infinity are errors naming `what`
  void gather_obs(const BehaviorBuffers& buf, const std::vector<int>& rows, RowMatrix& out,
                  const char* what) const;
  std::string where(const BehaviorBuffers& buf, int row) const;
  // the network's observation normalization as tensors: mean [D], 1/std [D]
  torch::Tensor normalize(const torch::Tensor& obs) const;
  // learning rate, epsilon and beta at the current step, written into `stats`
  void fill_schedules(UpdateStats& stats) const;
  // fresh permutation of [0, n) from the trainer's engine
  std::vector<int64_t> permutation(int64_t n);
  // folds a trajectory's observations ([rows, obs_size]) into the normalizer: at once when alone;
  // when data-parallel at the next update, with every rank's (sync_normalizer)
  void fold_observations(const float* obs, int64_t rows);
  // Called as an update starts: merges the ranks' new observations into the normalizer.
  void sync_normalizer();
  // this rank's rows per minibatch: batch_size over the ranks
  int64_t local_batch_size() const;
  // the minibatches per epoch every rank can fill from `n` rows of its own
  int64_t agreed_batches(int64_t n);
  // (adv - mean) / (std + 1e-10) with the mean and std over every rank's advantages ([N])
  torch::Tensor normalize_advantages(const torch::Tensor& adv);
  // the minibatch gradient as the mean over ranks (before clipping and the optimizer step)
  void reduce_gradients();
  void refresh_actor();
  // builds the optimizer over the network and extra_parameters(); derived constructors call it
  void create_optimizer();

  BehaviorSpec spec_;
  BehaviorConfig config_;
  std::string env_name_;
  int rows_ = 0, obs_size_ = 0;

  PolicyNetwork net_;
  std::unique_ptr<FlatAdam> optimizer_;
  RunningNormalizer normalizer_;
  FastActor actor_;
  bool actor_stale_ = true;
  std::mt19937_64 rng_;  // action sampling and minibatch shuffling

  int64_t step_ = 0, updates_ = 0;
  std::vector<uint8_t> pending_;               // [rows] row acted and awaits its reward
  std::vector<ExperienceBuffer> trajectories_; // [rows] running trajectory of the row's agent
  std::vector<std::vector<float>> rewards_;    // [rows][T] rewards of the running trajectory
  std::vector<double> episode_return_;         // [rows] cumulative reward of the running episode
  std::vector<double> episode_group_return_;   // [rows] cumulative group reward of that episode
  std::vector<int> episode_length_;            // [rows]
  std::vector<uint8_t> whole_episode_;         // [rows] 1: seen from its first step (stats count)
  ExperienceBuffer buffer_;                    // the update buffer
  EpisodeStats episode_stats_;
  Communicator* comm_ = nullptr;          // data-parallel replicas, or alone
  RunningNormalizer pending_normalizer_;  // this rank's observations since the last update

  // scratch reused across steps
  std::vector<int> act_rows_;
  RowMatrix act_obs_;
  ActBatch act_out_;
};

}  // namespace rlt
