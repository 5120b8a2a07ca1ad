// The PPO objective on one minibatch, as ML-Agents' `ppo/optimizer_torch.py` computes it:
//   policy = -mean(min(r A, clip(r, 1 - eps, 1 + eps) A)),  r = exp(log_prob - old_log_prob)
//   value  = mean(max((R - V)^2, (R - V_clip)^2)),          V_clip = V_old + clip(V - V_old, -eps, eps)
//   total  = policy + c value - beta mean(H_gaussian) - beta_d mean(H_discrete)
//            (c = value_loss_coef, ML-Agents: 0.5; beta_d = discrete_beta, our extension: the
//            discrete branches' own entropy bonus, so that exploring a rare choice does not cost
//            noisier continuous actions; ML-Agents has one beta, which discrete_beta = beta is)
// and, to watch how far an update moves the policy (no gradient): the approximate KL divergence
// from the old policy, mean((r - 1) - log r) (Schulman's low-variance estimator, never negative),
// and the clip fraction, the share of rows with |r - 1| > eps.
#pragma once

#include <torch/torch.h>

namespace rlt {

struct PpoLoss {
  torch::Tensor policy;   // []
  torch::Tensor value;    // []
  torch::Tensor entropy;  // [] mean entropy
  torch::Tensor total;    // []
  torch::Tensor approx_kl;      // [] no gradient
  torch::Tensor clip_fraction;  // [] no gradient
};

// mean(max((R - V)^2, (R - V_clip)^2)); every argument is [B]
torch::Tensor clipped_value_loss(const torch::Tensor& values, const torch::Tensor& old_values,
                                 const torch::Tensor& returns, float epsilon);

// one row's term of clipped_value_loss, max((R - V)^2, (R - V_clip)^2), and its derivative with
// respect to V (ties of the max and the clamp's edges follow LibTorch: half the gradient each
// on a tie, the clamp passing the gradient at its edges); for the hand-written gradients
struct ClippedValueTerm {
  double loss = 0;
  double gradient = 0;  // d loss / d V
};
ClippedValueTerm clipped_value_term(double value, double old_value, double ret, float epsilon);

// every tensor argument is [B]; entropy is the whole action's, discrete_entropy its discrete
// branches' part (undefined when there are none)
PpoLoss ppo_loss(const torch::Tensor& log_prob, const torch::Tensor& old_log_prob,
                 const torch::Tensor& advantages, const torch::Tensor& values,
                 const torch::Tensor& old_values, const torch::Tensor& returns,
                 const torch::Tensor& entropy, const torch::Tensor& discrete_entropy,
                 float epsilon, float beta, float discrete_beta, float value_loss_coef = 0.5f);

}  // namespace rlt
