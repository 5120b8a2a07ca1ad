#include "rl/core/lambda_return.h"

namespace rlt {

void compute_lambda_returns(const float* rewards, const float* values, int64_t length,
                            float bootstrap_value, float gamma, float lambda, float* returns) {
  if (length <= 0) return;
  returns[length - 1] = rewards[length - 1] + gamma * bootstrap_value;
  for (int64_t t = length - 2; t >= 0; --t)
    returns[t] = rewards[t] + gamma * ((1.f - lambda) * values[t + 1] + lambda * returns[t + 1]);
}

}  // namespace rlt
