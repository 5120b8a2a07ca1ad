// The update buffer of one behavior: processed experiences waiting for the next PPO update.
// Rows are appended one trajectory at a time; every array is row-major so that LibTorch wraps it
// without copying.
#pragma once

#include <cstdint>
#include <vector>

namespace rlt {

struct ExperienceBuffer {
  int obs_size = 0, continuous_size = 0, num_branches = 0, mask_size = 0;

  std::vector<float> obs;          // [N, obs_size] raw observations
  std::vector<float> continuous;   // [N, continuous_size] raw sampled actions
  std::vector<int64_t> discrete;   // [N, num_branches] chosen options
  std::vector<float> mask;         // [N, mask_size] 1 = allowed
  std::vector<float> log_prob;     // [N] joint log-probability when acting
  std::vector<float> value;        // [N] critic value when acting
  std::vector<float> returns;      // [N] lambda-returns (GAE + value)
  std::vector<float> advantages;   // [N] GAE advantages

  int64_t size() const { return static_cast<int64_t>(log_prob.size()); }
  void clear() {
    for (auto* v : {&obs, &continuous, &mask, &log_prob, &value, &returns, &advantages}) v->clear();
    discrete.clear();
  }
  void append(const ExperienceBuffer& other) {
    auto cat = [](auto& a, const auto& b) { a.insert(a.end(), b.begin(), b.end()); };
    cat(obs, other.obs);
    cat(continuous, other.continuous);
    cat(discrete, other.discrete);
    cat(mask, other.mask);
    cat(log_prob, other.log_prob);
    cat(value, other.value);
    cat(returns, other.returns);
    cat(advantages, other.advantages);
  }
};

}  // namespace rlt
