// The PPO objective on one minibatch, as ML-Agents' `ppo/optimizer_torch.py` computes it:
//   policy = -mean(min(r A, clip(r, 1 - eps, 1 + eps) A)),  r = exp(log_prob - old_log_prob)
//   value  = mean(max((R - V)^2, (R - V_clip)^2)),          V_clip = V_old + clip(V - V_old, -eps, eps)
//   total  = policy + c value - beta mean(entropy)    (c = value_loss_coef, ML-Agents: 0.5)
#pragma once

#include <torch/torch.h>

namespace rlt {

struct PpoLoss {
  torch::Tensor policy;   // []
  torch::Tensor value;    // []
  torch::Tensor entropy;  // [] mean entropy
  torch::Tensor total;    // []
};

// mean(max((R - V)^2, (R - V_clip)^2)); every argument is [B]
torch::Tensor clipped_value_loss(const torch::Tensor& values, const torch::Tensor& old_values,
                                 const torch::Tensor& returns, float epsilon);

// every argument is [B]
PpoLoss ppo_loss(const torch::Tensor& log_prob, const torch::Tensor& old_log_prob,
                 const torch::Tensor& advantages, const torch::Tensor& values,
                 const torch::Tensor& old_values, const torch::Tensor& returns,
                 const torch::Tensor& entropy, float epsilon, float beta,
                 float value_loss_coef = 0.5f);

}  // namespace rlt
