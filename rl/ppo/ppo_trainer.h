// Proximal Policy Optimization for one behavior, with ML-Agents' trainer semantics.
//
// References: Schulman et al. 2017, "Proximal Policy Optimization Algorithms"; ML-Agents
// `mlagents/trainers/ppo/trainer.py` and `ppo/optimizer_torch.py` (trajectories cut at
// time_horizon, GAE per trajectory, advantages normalized over the update buffer, clipped value
// loss, loss = policy + 0.5 value - beta entropy (value weight configurable: value_loss_coef; the
// discrete branches' entropy weighed by discrete_beta instead when it is set, see ppo_loss.h),
// linear decay of learning rate to 1e-10, epsilon to 0.1 and beta to 1e-5 over max_steps, buffer
// cleared after each update); CleanRL ppo.py for the textbook details.
// Deliberate differences from ML-Agents:
//   - the probability ratio is of the joint action (see action_distribution.h);
//   - values stored with an experience are computed when acting (CleanRL), not re-evaluated when
//     the trajectory is processed;
//   - optional global gradient-norm clipping (`max_grad_norm`, CleanRL), off by default.
// The minibatch gradient is computed by MlpPpoGradient (hand-written backward in Eigen), checked in
// tests against autograd through evaluate_actions() and ppo_loss().
#pragma once

#include <memory>

#include "rl/ppo/mlp_ppo_gradient.h"
#include "rl/trainer/on_policy_trainer.h"

namespace rlt {

class PpoTrainer : public OnPolicyTrainer {
 public:
  PpoTrainer(const BehaviorSpec& spec, const BehaviorConfig& config, int rows, uint64_t seed,
             const std::string& env_name = "");

  UpdateStats update() override;

 protected:
  void end_trajectories(const BehaviorBuffers& buf, const std::vector<int>& terminated,
                        const std::vector<int>& bootstrapped) override;

 private:
  void finish(int row, float bootstrap_value);

  std::unique_ptr<MlpPpoGradient> gradient_;  // minibatch loss and gradient (hand-written backward)
};

}  // namespace rlt
