#include "rl/core/action_distribution.h"

#include <cmath>

namespace rlt {

torch::Tensor masked_log_softmax(const ActionSpec& spec, const torch::Tensor& logits,
                                 const torch::Tensor& mask) {
  // forbidden options are pushed to -1e8 before each branch's softmax
  auto masked = logits + (mask - 1.f) * 1e8f;
  std::vector<torch::Tensor> parts;
  int64_t offset = 0;
  for (int n : spec.discrete_branches) {
    parts.push_back(torch::log_softmax(masked.narrow(1, offset, n), 1));
    offset += n;
  }
  return parts.size() == 1 ? parts[0] : torch::cat(parts, 1);
}

ActionLogProbs evaluate_actions(const ActionSpec& spec, const torch::Tensor& mean,
                                const torch::Tensor& log_std, const torch::Tensor& logits,
                                const torch::Tensor& mask, const torch::Tensor& continuous,
                                const torch::Tensor& discrete) {
  torch::Tensor log_prob, entropy, discrete_entropy;
  if (spec.continuous_size > 0) {
    // diagonal Gaussian: sum over dimensions
    const float half_log_2pi = 0.5f * std::log(2.f * float(M_PI));
    auto z = (continuous - mean) * torch::exp(-log_std);
    log_prob = (-0.5f * z * z - log_std - half_log_2pi).sum(1);
    entropy = (0.5f + half_log_2pi + log_std).sum().expand({mean.size(0)});
  }
  if (spec.num_branches() > 0) {
    auto logp = masked_log_softmax(spec, logits, mask);  // [B, M]
    auto p = torch::exp(logp);
    int64_t offset = 0;
    for (int k = 0; k < spec.num_branches(); ++k) {
      const int n = spec.discrete_branches[k];
      auto branch_logp = logp.narrow(1, offset, n);
      auto chosen = branch_logp.gather(1, discrete.narrow(1, k, 1)).squeeze(1);
      auto branch_entropy = -(p.narrow(1, offset, n) * branch_logp).sum(1);
      log_prob = log_prob.defined() ? log_prob + chosen : chosen;
      entropy = entropy.defined() ? entropy + branch_entropy : branch_entropy;
      discrete_entropy =
          discrete_entropy.defined() ? discrete_entropy + branch_entropy : branch_entropy;
      offset += n;
    }
  }
  return {log_prob, entropy, discrete_entropy};
}

}  // namespace rlt
