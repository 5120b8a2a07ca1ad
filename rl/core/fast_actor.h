// A copy of a PolicyNetwork's weights in Eigen, for acting in rollouts.
//
// Acting runs a handful of agents at a time, where LibTorch's per-operation cost (microseconds)
// would dominate; a plain Eigen forward pass of the same MLP costs well under a microsecond per
// layer. The weights are copied after every update, so it always acts with the learner's policy.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <random>
#include <vector>

#include "rl/config/run_config.h"
#include "rl/core/matrix_product.h"
#include "rl/core/running_normalizer.h"
#include "rl/env_api/uniform_random.h"
#include "rl/env_api/spec.h"

namespace rlt {

class PolicyNetworkImpl;

// Actions chosen for a batch of agents.
struct ActBatch {
  RowMatrix continuous;               // [B, C] raw samples (before clipping)
  Eigen::Matrix<int32_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> discrete;  // [B, K]
  Eigen::VectorXf log_prob;           // [B] joint log-probability
  Eigen::VectorXf value;              // [B] critic value
};

class FastActor {
 public:
  FastActor() = default;
  // copies weights of `net`; `normalizer` may be null (no normalization)
  void copy_from(const PolicyNetworkImpl& net, const RunningNormalizer* normalizer);

  // obs: [B, obs_size] raw observations; mask: [B, M] (1 = allowed) or null.
  // Samples actions with `rng` (the mode when `deterministic`) and evaluates the critic.
  void act(const RowMatrix& obs, const uint8_t* mask, bool deterministic, std::mt19937_64& rng,
           ActBatch& out) const;
  // critic only: obs [B, obs_size] -> [B] (zeros for an actor without critic)
  Eigen::VectorXf value(const RowMatrix& obs) const;

 private:
  struct Layer {
    RowMatrix weight;        // [in, out]
    Eigen::RowVectorXf bias; // [out]
  };
  RowMatrix normalized(const RowMatrix& obs) const;
  RowMatrix run_body(const std::vector<Layer>& body, RowMatrix x) const;

  ActionSpec action_;
  Activation activation_ = Activation::kSwish;
  bool shared_critic_ = false;
  bool with_critic_ = true;
  bool normalize_ = false;
  Eigen::RowVectorXf obs_mean_, obs_inv_std_;  // [obs_size]
  std::vector<Layer> actor_body_, critic_body_;
  Layer mean_head_, logits_head_, value_head_;
  Eigen::RowVectorXf log_std_;  // [C]
};

// Standard normal by Box-Muller.
double standard_normal(std::mt19937_64& rng);

}  // namespace rlt
