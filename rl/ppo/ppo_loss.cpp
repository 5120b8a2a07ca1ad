#include "rl/ppo/ppo_loss.h"

#include <algorithm>

namespace rlt {

torch::Tensor clipped_value_loss(const torch::Tensor& values, const torch::Tensor& old_values,
                                 const torch::Tensor& returns, float epsilon) {
  auto values_clipped = old_values + torch::clamp(values - old_values, -epsilon, epsilon);
  return torch::max(torch::square(returns - values), torch::square(returns - values_clipped)).mean();
}

ClippedValueTerm clipped_value_term(double value, double old_value, double ret, float epsilon) {
  const double delta = std::clamp(value - old_value, -double(epsilon), double(epsilon));
  const double clipped = old_value + delta;
  const double l1 = (ret - value) * (ret - value), l2 = (ret - clipped) * (ret - clipped);
  const bool tie = l1 == l2;
  const bool delta_in_range = value - old_value >= -epsilon && value - old_value <= epsilon;
  const double share1 = tie ? 0.5 : (l1 > l2 ? 1.0 : 0.0), share2 = tie ? 0.5 : 1.0 - share1;
  ClippedValueTerm out;
  out.loss = std::max(l1, l2);
  out.gradient = share1 * -2 * (ret - value) +
                 share2 * (delta_in_range ? -2 * (ret - clipped) : 0.0);
  return out;
}

PpoLoss ppo_loss(const torch::Tensor& log_prob, const torch::Tensor& old_log_prob,
                 const torch::Tensor& advantages, const torch::Tensor& values,
                 const torch::Tensor& old_values, const torch::Tensor& returns,
                 const torch::Tensor& entropy, const torch::Tensor& discrete_entropy,
                 float epsilon, float beta, float discrete_beta, float value_loss_coef) {
  PpoLoss out;
  // clipped surrogate
  auto log_ratio = log_prob - old_log_prob;  // [B]
  auto ratio = torch::exp(log_ratio);         // [B]
  auto clipped_ratio = torch::clamp(ratio, 1.f - epsilon, 1.f + epsilon);
  out.policy = -torch::min(ratio * advantages, clipped_ratio * advantages).mean();
  out.value = clipped_value_loss(values, old_values, returns, epsilon);
  out.entropy = entropy.mean();
  out.total = out.policy + value_loss_coef * out.value - beta * out.entropy;
  // the branches' bonus at discrete_beta instead of beta (nothing changes when the two are equal)
  if (discrete_entropy.defined() && discrete_beta != beta)
    out.total = out.total - (discrete_beta - beta) * discrete_entropy.mean();
  {
    torch::NoGradGuard no_grad;
    out.approx_kl = (ratio - 1 - log_ratio).mean();
    out.clip_fraction = ((ratio - 1).abs() > epsilon).to(torch::kFloat).mean();
  }
  return out;
}

}  // namespace rlt
