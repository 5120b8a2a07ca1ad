// Generalized advantage estimation over one trajectory.
//
// Reference: Schulman et al. 2016, "High-Dimensional Continuous Control Using Generalized Advantage
// Estimation"; ML-Agents `mlagents/trainers/trainer/trainer_utils.py` (get_gae) and CleanRL's ppo.py.
// The trajectory is one agent's consecutive experiences; `bootstrap_value` is V(s_T) of the
// observation after the last one: the value of the final observation when the agent was truncated
// or the trajectory was cut at time_horizon, and 0 when the agent's episode terminated.
#pragma once

#include <cstdint>

namespace rlt {

// rewards, values: [T]; writes advantages and returns (= advantages + values): [T]
//   delta_t = r_t + gamma * V_{t+1} - V_t   (V_T = bootstrap_value)
//   A_t     = delta_t + gamma * lambda * A_{t+1}
void compute_gae(const float* rewards, const float* values, int64_t length, float bootstrap_value,
                 float gamma, float lambda, float* advantages, float* returns);

}  // namespace rlt
