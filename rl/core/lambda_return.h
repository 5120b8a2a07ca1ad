// TD(lambda) returns over one trajectory, as MA-POCA uses them (the value target and, minus the
// counterfactual baseline, the advantage).
//
// Reference: Sutton & Barto, "Reinforcement Learning: An Introduction", 12.1 (the lambda-return);
// ML-Agents `trainers/trainer/trainer_utils.py` (lambda_return), which this reproduces:
//   G_{T-1} = r_{T-1} + gamma V_T                                  (V_T = bootstrap value)
//   G_t     = r_t + gamma ((1 - lambda) V_{t+1} + lambda G_{t+1})
#pragma once

#include <cstdint>

namespace rlt {

// rewards, values: [T] -> returns: [T]
void compute_lambda_returns(const float* rewards, const float* values, int64_t length,
                            float bootstrap_value, float gamma, float lambda, float* returns);

}  // namespace rlt
