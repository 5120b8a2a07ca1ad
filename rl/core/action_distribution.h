// Log-probabilities and entropy of hybrid actions: a diagonal Gaussian over the continuous part and
// one masked categorical per discrete branch, all independent.
//
// Reference: ML-Agents `mlagents/trainers/torch_entities/distributions.py` (GaussianDistInstance,
// CategoricalDistInstance with masks) and `action_model.py`. Deliberate difference: ML-Agents keeps
// one log-probability per action component and PPO clips each component's ratio separately; we sum
// them into the joint log-probability of the whole action (the textbook PPO ratio).
#pragma once

#include <torch/torch.h>

#include "rl/env_api/spec.h"

namespace rlt {

struct ActionLogProbs {
  torch::Tensor log_prob;  // [B] joint log-probability of the action
  torch::Tensor entropy;   // [B] entropy of the whole action distribution
  torch::Tensor discrete_entropy;  // [B] the discrete branches' part of it (undefined: no branches)
};

// Evaluates actions under the distribution.
//   mean            [B, C] Gaussian means (undefined when C = 0)
//   log_std         [C]    state-independent log standard deviations
//   logits          [B, M] discrete logits, M = spec.mask_size() (undefined when no branches)
//   mask            [B, M] 1 = allowed, 0 = forbidden (float)
//   continuous      [B, C] raw sampled continuous actions (before clipping)
//   discrete        [B, K] chosen option per branch (int64)
ActionLogProbs evaluate_actions(const ActionSpec& spec, const torch::Tensor& mean,
                                const torch::Tensor& log_std, const torch::Tensor& logits,
                                const torch::Tensor& mask, const torch::Tensor& continuous,
                                const torch::Tensor& discrete);

// Per-branch log-softmax of masked logits: forbidden options get log-probability about -1e8.
// logits, mask: [B, M] -> [B, M]
torch::Tensor masked_log_softmax(const ActionSpec& spec, const torch::Tensor& logits,
                                 const torch::Tensor& mask);

// What the environment receives for a raw continuous sample: clamp(a, -3, 3) / 3, as ML-Agents.
inline float clip_continuous_action(float a) { return std::min(3.f, std::max(-3.f, a)) / 3.f; }

}  // namespace rlt
