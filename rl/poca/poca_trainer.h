// MA-POCA (multi-agent posthumous credit assignment) for one behavior.
//
// References: Cohen et al. 2021, "On the Use and Misuse of Absorbing States in Multi-agent
// Reinforcement Learning"; ML-Agents `trainers/poca/trainer.py` and `poca/optimizer_torch.py`.
// - The actor sees only the agent's own observations (PolicyNetwork without critic).
// - The centralized value V is over every member of the agent's group (same env instance, same
//   group id) present at that step; the counterfactual baseline of agent i is over i's observation
//   and the other members' observations and actions (PocaCritic).
// - A member's reward is its own reward plus its groupmates' rewards plus the group reward, times
//   the signal strength (ML-Agents' add_groupmate_rewards).
// - Returns are lambda-returns from V; advantage = return - baseline; advantages are normalized
//   over the update buffer; loss = policy + 0.5 (value + 0.5 baseline) - beta entropy (the
//   discrete branches' part weighed by discrete_beta when set, as PPO's), value and baseline
//   losses clipped like PPO's value loss.
// - An agent that leaves before its group bootstraps from the group's value V of the observations
//   at the step it left; only when the whole group is done and terminated is the bootstrap 0.
// Deliberate differences: as in PPO, the joint action's ratio is clipped (see
// action_distribution.h); absent members are masked explicitly (see poca_critic.h).
// The minibatch gradient is written out by hand, MlpPpoGradient for the actor (it has no critic)
// and PocaCriticGradient for the critic, each checked in tests against autograd.
#pragma once

#include <memory>

#include "rl/poca/poca_critic.h"
#include "rl/poca/poca_critic_gradient.h"
#include "rl/ppo/mlp_ppo_gradient.h"
#include "rl/trainer/on_policy_trainer.h"

namespace rlt {

class PocaTrainer : public OnPolicyTrainer {
 public:
  PocaTrainer(const BehaviorSpec& spec, const BehaviorConfig& config, int rows, uint64_t seed,
              const std::string& env_name = "");

  UpdateStats update() override;
  PocaCritic& critic() { return critic_; }

 protected:
  void end_trajectories(const BehaviorBuffers& buf, const std::vector<int>& terminated,
                        const std::vector<int>& bootstrapped) override;
  float step_reward(const BehaviorBuffers& buf, int row) const override;
  void on_acted(const BehaviorBuffers& buf, const std::vector<int>& rows) override;
  std::vector<torch::Tensor> extra_parameters() override { return critic_->parameters(); }
  void save_extra(torch::serialize::OutputArchive& archive) const override;
  void load_extra(torch::serialize::InputArchive& archive) override;

 private:
  // slots of the same env instance as `row` that hold a member of its group (other than `row`)
  // whose step type satisfies `member`; -1 where not
  template <typename Pred>
  std::vector<int> groupmates(const BehaviorBuffers& buf, int row, Pred member) const;
  // writes the action of `row` as the critic sees it: continuous values then one-hot branches
  void encode_action(const BehaviorBuffers& buf, int row, float* out) const;
  void finish(const BehaviorBuffers& buf, int row, bool terminal);
  // member slots (of others_) used by any of the n rows of `present` [n, others_]: slots are
  // packed, present groupmates first
  int64_t packed_others(const std::vector<float>& present, int64_t n) const;
  double shape_hidden() const;  // the critic's width

  // the loss's weights: policy + 0.5 (value + 0.5 baseline) - beta entropy
  static constexpr float kValueCoef = 0.5f, kBaselineCoef = 0.25f;

  PocaCritic critic_;
  std::unique_ptr<MlpPpoGradient> actor_gradient_;        // the actor's loss and gradient
  std::unique_ptr<PocaCriticGradient> critic_gradient_;   // the critic's
  int others_ = 0;       // member slots besides the agent's own: agent_slots - 1
  int action_code_ = 0;  // encoded action size
};

}  // namespace rlt
