#include "rl/core/gae.h"

namespace rlt {

void compute_gae(const float* rewards, const float* values, int64_t length, float bootstrap_value,
                 float gamma, float lambda, float* advantages, float* returns) {
  float next_value = bootstrap_value;
  float next_advantage = 0.f;
  for (int64_t t = length - 1; t >= 0; --t) {
    const float delta = rewards[t] + gamma * next_value - values[t];
    next_advantage = delta + gamma * lambda * next_advantage;
    advantages[t] = next_advantage;
    returns[t] = next_advantage + values[t];
    next_value = values[t];
  }
}

}  // namespace rlt
