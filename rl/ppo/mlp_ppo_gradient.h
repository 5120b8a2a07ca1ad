// The PPO loss of one minibatch and its gradient for the MLP actor-critic, written out by hand in
// Eigen (its large matrix products go through the BLAS, see matrix_product.h): the fast path of
// PpoTrainer::update.
//
// The loss is exactly ppo_loss() over evaluate_actions() and PolicyNetwork (see ppo_loss.h); the
// autograd version of the same computation is the reference, and the tests compare the two
// gradients on hybrid, masked, shared-critic and normalized networks with the clip active.
// Why: with the small networks of RL tasks a LibTorch minibatch step is about a hundred operator
// calls of a few microseconds each; measured on CartPole's 64-64 actor and critic, the autograd step
// took about 480 us per 128-sample minibatch and the updates were over 90% of training time.
//
// A network without a critic (NetworkShape::with_critic false: MA-POCA's actor) gets the policy
// and entropy terms only, and its value loss is 0.
//
// Backward pass, per row i with g_i = d total / d log_prob_i:
//   continuous:  d/d mean_ij = g_i z_ij / s_j,  d/d log_std_j = sum_i g_i (z_ij^2 - 1) - beta
//   discrete:    d/d logit_ik = g_i (1[k = a_i] - p_ik) + (beta_d / B) p_ik (log p_ik + H_i)
//                (beta_d = discrete_beta, the branches' own entropy bonus; beta by default)
//   value:       d/d v_i from the larger of the two squared errors (half each on a tie)
// then through the heads and bodies (tanh' = 1 - y^2, relu' = 1[z > 0],
// swish' = s(z) (1 + z (1 - s(z)))). Ties of the min/max follow LibTorch: half the gradient each.
#pragma once

#include <cstdint>
#include <vector>

#include "rl/core/fast_actor.h"
#include "rl/core/policy_network.h"

namespace rlt {

// One minibatch, row-major, B rows.
struct MinibatchView {
  int64_t rows = 0;
  const float* obs = nullptr;         // [B, D] normalized observations
  const float* continuous = nullptr;  // [B, C] raw sampled continuous actions
  const int64_t* discrete = nullptr;  // [B, K] chosen options
  const float* mask = nullptr;        // [B, M] 1 = allowed (null: everything allowed)
  const float* old = nullptr;         // [B, 4] old log-prob, advantage, old value, return
};

struct LossValues {
  double policy = 0, value = 0, entropy = 0, total = 0;
  double approx_kl = 0, clip_fraction = 0;  // as ppo_loss() (no gradient)
};

class MlpPpoGradient {
 public:
  explicit MlpPpoGradient(PolicyNetworkImpl& net) : net_(net) {}

  // Computes the loss and writes its gradient into every parameter's .grad() (overwriting it).
  // The entropy bonus is beta for the Gaussian part and discrete_beta for the discrete branches.
  LossValues compute(const MinibatchView& mb, float epsilon, float beta, float discrete_beta,
                     float value_loss_coef);

 private:
  // forward through a body, keeping pre-activations and outputs: z[l], y[l] are [B, H]
  void body_forward(const std::vector<DenseLayer>& body, const RowMatrix& x,
                    std::vector<RowMatrix>& z, std::vector<RowMatrix>& y) const;
  // backward through a body given d loss / d (last output); writes weight and bias gradients
  void body_backward(const std::vector<DenseLayer>& body, const RowMatrix& x,
                     const std::vector<RowMatrix>& z, const std::vector<RowMatrix>& y,
                     RowMatrix dy);

  PolicyNetworkImpl& net_;
  std::vector<RowMatrix> actor_z_, actor_y_, critic_z_, critic_y_;  // scratch, [B, H] each
};

}  // namespace rlt
