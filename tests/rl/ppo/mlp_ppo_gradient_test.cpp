// The hand-written PPO gradient equals autograd through PolicyNetwork, evaluate_actions() and
// ppo_loss() (the reference), for every kind of action space, activation and critic layout, with
// the ratio and value clips active on both sides, with one entropy bonus or the discrete branches'
// own, and for the actor alone (MA-POCA's).
#include "rl/ppo/mlp_ppo_gradient.h"

#include <gtest/gtest.h>

#include "rl/core/action_distribution.h"
#include "rl/core/matrix_product.h"
#include "rl/ppo/ppo_loss.h"

namespace rlt {
namespace {

struct GradientCase {
  int continuous;
  std::vector<int> branches;
  Activation activation;
  bool shared_critic;
  bool masked;
  float discrete_beta = 0.01f;  // the branches' entropy bonus (beta is 0.01)
  int obs_size = 6, hidden_units = 16;
  int64_t rows = 37;
  bool with_critic = true;  // false: the actor alone (MA-POCA's)
};

class MlpPpoGradientTest : public ::testing::TestWithParam<GradientCase> {};

TEST_P(MlpPpoGradientTest, EqualsAutograd) {
  const auto c = GetParam();
  torch::manual_seed(11);
  NetworkShape shape;
  shape.obs_size = c.obs_size;
  shape.action.continuous_size = c.continuous;
  shape.action.discrete_branches = c.branches;
  shape.hidden_units = c.hidden_units;
  shape.num_layers = 2;
  shape.activation = c.activation;
  shape.shared_critic = c.shared_critic;
  shape.with_critic = c.with_critic;
  PolicyNetwork net(shape);
  {
    // larger head weights and log-stds away from 0, so that every term matters
    torch::NoGradGuard g;
    for (auto& p : net->parameters()) p.add_(torch::randn_like(p) * 0.3);
  }
  const int64_t B = c.rows;
  const int M = shape.action.mask_size(), K = shape.action.num_branches(), C = c.continuous;
  auto obs = torch::randn({B, c.obs_size});
  torch::Tensor mask, cont, disc;
  if (K > 0) {
    mask = torch::ones({B, M});
    disc = torch::zeros({B, K}, torch::kInt64);
    int offset = 0;
    for (int k = 0; k < K; ++k) {
      const int n = c.branches[k];
      for (int64_t i = 0; i < B; ++i) {
        // forbid a random option (never the only one), choose among the allowed
        const int forbidden = c.masked ? int(i % n) : -1;
        if (forbidden >= 0 && n > 1) mask[i][offset + forbidden] = 0.f;
        int choice = int((i * 7 + k) % n);
        if (choice == forbidden && n > 1) choice = (choice + 1) % n;
        disc[i][k] = choice;
      }
      offset += n;
    }
  }
  torch::Tensor mean;
  {
    torch::NoGradGuard g;
    auto out = net->actor(obs);
    if (C > 0) {
      mean = out.mean;
      cont = out.mean + torch::randn({B, C}) * torch::exp(net->log_std);
    }
  }
  // old log-probs and values around the current ones, so that both clips are active on both sides
  torch::Tensor log_prob, value;
  {
    torch::NoGradGuard g;
    auto out = net->actor(obs);
    log_prob = evaluate_actions(shape.action, out.mean, net->log_std, out.logits, mask, cont, disc).log_prob;
    value = c.with_critic ? net->value(obs, out.hidden) : torch::zeros({B});
  }
  auto old_log_prob = log_prob + torch::randn({B}) * 0.3;
  auto advantages = torch::randn({B});
  // without a critic the value terms are 0 (the reference's values are constants)
  auto old_value = c.with_critic ? value + torch::randn({B}) * 0.4 : value;
  auto returns = c.with_critic ? value + torch::randn({B}) : value;
  const float epsilon = 0.2f, beta = 0.01f, value_coef = 0.5f;
  const auto ratio = torch::exp(log_prob - old_log_prob);
  ASSERT_GT((ratio > 1 + epsilon).sum().item<int>(), 0);
  ASSERT_GT((ratio < 1 - epsilon).sum().item<int>(), 0);

  // reference: autograd
  for (auto& p : net->parameters()) p.mutable_grad() = torch::zeros_like(p);
  auto out = net->actor(obs);
  auto lp = evaluate_actions(shape.action, out.mean, net->log_std, out.logits, mask, cont, disc);
  auto v = c.with_critic ? net->value(obs, out.hidden) : value;
  PpoLoss ref = ppo_loss(lp.log_prob, old_log_prob, advantages, v, old_value, returns, lp.entropy,
                         lp.discrete_entropy, epsilon, beta, c.discrete_beta, value_coef);
  ref.total.backward();
  std::vector<torch::Tensor> expected;
  for (auto& p : net->parameters()) expected.push_back(p.grad().clone());

  // hand-written
  for (auto& p : net->parameters()) p.mutable_grad().zero_();
  auto old = torch::stack({old_log_prob, advantages, old_value, returns}, 1).contiguous();
  MinibatchView mb;
  mb.rows = B;
  mb.obs = obs.data_ptr<float>();
  if (C > 0) mb.continuous = cont.data_ptr<float>();
  if (K > 0) {
    mb.discrete = disc.data_ptr<int64_t>();
    mb.mask = mask.data_ptr<float>();
  }
  mb.old = old.data_ptr<float>();
  MlpPpoGradient gradient(*net);
  LossValues got = gradient.compute(mb, epsilon, beta, c.discrete_beta, value_coef);

  EXPECT_NEAR(got.policy, ref.policy.item<float>(), 1e-5);
  EXPECT_NEAR(got.value, ref.value.item<float>(), 1e-4 * std::max(1.f, ref.value.item<float>()));
  EXPECT_NEAR(got.entropy, ref.entropy.item<float>(), 1e-4);
  EXPECT_NEAR(got.total, ref.total.item<float>(), 1e-4);
  EXPECT_NEAR(got.approx_kl, ref.approx_kl.item<float>(), 1e-5 * (1 + got.approx_kl));
  EXPECT_NEAR(got.clip_fraction, ref.clip_fraction.item<float>(), 1e-6);
  EXPECT_GT(got.clip_fraction, 0.0);  // the clip is active (asserted above)
  const auto names = net->named_parameters().keys();
  auto params = net->parameters();
  for (size_t i = 0; i < params.size(); ++i) {
    EXPECT_TRUE(torch::allclose(params[i].grad(), expected[i], 1e-3, 1e-5))
        << names[i] << "\nhand-written\n" << params[i].grad() << "\nautograd\n" << expected[i];
    EXPECT_GT(expected[i].abs().sum().item<float>(), 0.f) << names[i] << " has no gradient to compare";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Networks, MlpPpoGradientTest,
    ::testing::Values(GradientCase{2, {3, 2}, Activation::kTanh, false, true},
                      GradientCase{2, {3, 2}, Activation::kSwish, true, true},
                      GradientCase{1, {}, Activation::kRelu, false, false},
                      GradientCase{3, {}, Activation::kSwish, true, false},
                      GradientCase{0, {2}, Activation::kTanh, false, false},
                      GradientCase{0, {4, 3}, Activation::kRelu, true, true},
                      GradientCase{0, {4, 3}, Activation::kSwish, false, true},
                      // the branches' own entropy bonus, larger and switched off
                      GradientCase{2, {3, 2}, Activation::kTanh, false, true, 0.2f},
                      GradientCase{0, {4, 3}, Activation::kRelu, true, true, 0.f},
                      // the actor alone, as MA-POCA trains it
                      GradientCase{2, {3, 2}, Activation::kSwish, false, true, 0.01f, 6, 16, 37,
                                   false},
                      // bodies large enough for the BLAS path of multiply() (see the test below)
                      GradientCase{2, {3, 2}, Activation::kTanh, false, true, 0.05f, 160, 160,
                                   200}));

TEST(MlpPpoGradientSizes, LargeCaseTakesTheBlasPath) {
  EXPECT_GE(int64_t(200) * 160 * 160, kBlasProductMinMultiplies);
  EXPECT_LT(int64_t(37) * 16 * 16, kBlasProductMinMultiplies);
}

}  // namespace
}  // namespace rlt
