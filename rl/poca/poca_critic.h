// MA-POCA's centralized critic: a value over all members of a group, and for each member a
// counterfactual baseline over its own observation and the other members' observations and actions.
//
// Reference: Cohen et al. 2021, "On the Use and Misuse of Absorbing States in Multi-agent
// Reinforcement Learning" (MA-POCA); ML-Agents `torch_entities/networks.py` (MultiAgentNetworkBody)
// and `torch_entities/attention.py` (EntityEmbedding, ResidualSelfAttention).
// Each member is an entity: embedded by a linear layer (observation only, or observation and
// action), then residual multi-head self-attention over the entities, a masked mean over the
// members present, an MLP and a linear head. Deliberate difference: absent members are given by an
// explicit mask, not by NaN-filled observations; masked keys get a score of -1e9, so an absent
// member's values never reach the output (its attention weight is exactly 0).
#pragma once

#include <torch/torch.h>

#include "rl/config/run_config.h"

namespace rlt {

struct PocaCriticShape {
  int obs_size = 0;            // flattened observation of one member
  int action_size = 0;         // encoded action: continuous values + one-hot of every branch
  int hidden_units = 128;
  int num_layers = 2;          // MLP layers after pooling
  Activation activation = Activation::kSwish;
  int heads = 4;               // attention heads (hidden_units must divide evenly)
};

class PocaCriticImpl : public torch::nn::Module {
 public:
  explicit PocaCriticImpl(const PocaCriticShape& shape);

  // obs: [B, N, D] normalized observations of the N member slots; present: [B, N] (1 or 0)
  // -> [B] value of the group
  torch::Tensor value(const torch::Tensor& obs, const torch::Tensor& present);

  // own_obs: [B, D]; others_obs: [B, N-1, D]; others_actions: [B, N-1, A]; others_present: [B, N-1]
  // -> [B] baseline of the member whose observation is own_obs (its own action is not an input)
  torch::Tensor baseline(const torch::Tensor& own_obs, const torch::Tensor& others_obs,
                         const torch::Tensor& others_actions,
                         const torch::Tensor& others_present);

  const PocaCriticShape& shape() const { return shape_; }

 private:
  friend class PocaCriticGradient;  // the hand-written gradient reads the layers directly

  // entities: [B, N, H], present: [B, N] -> [B] through attention, pooling, MLP and head
  torch::Tensor head(const torch::Tensor& entities, const torch::Tensor& present);

  PocaCriticShape shape_;
  torch::nn::Linear obs_embedding_{nullptr};         // D -> H
  torch::nn::Linear obs_action_embedding_{nullptr};  // D + A -> H
  torch::nn::Linear query_{nullptr}, key_{nullptr}, value_{nullptr}, out_{nullptr};  // H -> H
  torch::nn::LayerNorm norm_{nullptr};
  torch::nn::ModuleList mlp_;  // num_layers x (H -> H)
  torch::nn::Linear value_head_{nullptr};  // H -> 1
};
TORCH_MODULE(PocaCritic);

}  // namespace rlt
