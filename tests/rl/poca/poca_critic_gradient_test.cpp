// The hand-written MA-POCA critic gradient equals autograd through PocaCritic::value(),
// ::baseline() and clipped_value_loss() (the reference): with absent members, with no other
// member at all, with one head or several, for every activation, with the value clip active on
// both sides, and with layers large enough for the BLAS path of multiply().
#include "rl/poca/poca_critic_gradient.h"

#include <gtest/gtest.h>

#include "rl/core/matrix_product.h"
#include "rl/ppo/ppo_loss.h"

namespace rlt {
namespace {

struct CriticCase {
  int64_t others;  // U other-member slots
  int heads;
  Activation activation;
  int obs_size = 6, action_size = 3, hidden_units = 16, num_layers = 2;
  int64_t rows = 37;
};

class PocaCriticGradientTest : public ::testing::TestWithParam<CriticCase> {};

TEST_P(PocaCriticGradientTest, EqualsAutograd) {
  const auto c = GetParam();
  torch::manual_seed(17);
  PocaCriticShape shape;
  shape.obs_size = c.obs_size;
  shape.action_size = c.action_size;
  shape.hidden_units = c.hidden_units;
  shape.num_layers = c.num_layers;
  shape.activation = c.activation;
  shape.heads = c.heads;
  PocaCritic critic(shape);
  {
    // away from the initialization (the norm's gain and shift too), so that every term matters
    torch::NoGradGuard g;
    for (auto& p : critic->parameters()) p.add_(torch::randn_like(p) * 0.2);
  }
  const int64_t B = c.rows, U = c.others, D = c.obs_size, A = c.action_size;
  auto own = torch::randn({B, D});         // [B, D]
  auto others = torch::randn({B, U, D});   // [B, U, D]
  auto actions = torch::randn({B, U, A});  // [B, U, A]
  auto present = torch::zeros({B, U});     // [B, U] packed: row i has i % (U + 1) members
  for (int64_t i = 0; i < B; ++i)
    for (int64_t u = 0; u < i % (U + 1); ++u) present[i][u] = 1.f;
  auto all = torch::cat({own.unsqueeze(1), others}, 1);              // [B, 1 + U, D]
  auto all_present = torch::cat({torch::ones({B, 1}), present}, 1);  // [B, 1 + U]
  torch::Tensor value, baseline;
  {
    torch::NoGradGuard g;
    value = critic->value(all, all_present);
    baseline = critic->baseline(own, others, actions, present);
  }
  const float epsilon = 0.2f, value_coef = 0.5f, baseline_coef = 0.25f;
  auto old_value = value + torch::randn({B}) * 0.4,
       old_baseline = baseline + torch::randn({B}) * 0.4;
  auto returns = value + torch::randn({B});
  // old outputs are the current ones plus noise, so that the value clip is active on some rows
  ASSERT_GT(((value - old_value).abs() > epsilon).sum().item<int>(), 0);

  // reference: autograd
  for (auto& p : critic->parameters()) p.mutable_grad() = torch::zeros_like(p);
  auto ref_value = clipped_value_loss(critic->value(all, all_present), old_value, returns, epsilon);
  auto ref_baseline = clipped_value_loss(critic->baseline(own, others, actions, present),
                                         old_baseline, returns, epsilon);
  (value_coef * ref_value + baseline_coef * ref_baseline).backward();
  std::vector<torch::Tensor> expected;
  for (auto& p : critic->parameters()) expected.push_back(p.grad().clone());

  // hand-written (gradients overwritten: start from garbage)
  for (auto& p : critic->parameters()) p.mutable_grad().fill_(123.f);
  auto old = torch::stack({old_value, old_baseline, returns}, 1).contiguous();  // [B, 3]
  auto others_c = others.contiguous(), actions_c = actions.contiguous();
  CriticMinibatchView mb;
  mb.rows = B;
  mb.others = U;
  mb.obs = own.data_ptr<float>();
  mb.others_obs = others_c.data_ptr<float>();
  mb.others_actions = actions_c.data_ptr<float>();
  mb.others_present = present.data_ptr<float>();
  mb.old = old.data_ptr<float>();
  PocaCriticGradient gradient(*critic);
  CriticLossValues got = gradient.compute(mb, epsilon, value_coef, baseline_coef);

  const double tolerance = 1e-4 * std::max(1.f, ref_value.item<float>());
  EXPECT_NEAR(got.value, ref_value.item<float>(), tolerance);
  EXPECT_NEAR(got.baseline, ref_baseline.item<float>(), tolerance);
  const auto names = critic->named_parameters().keys();
  auto params = critic->parameters();
  for (size_t i = 0; i < params.size(); ++i) {
    EXPECT_TRUE(torch::allclose(params[i].grad(), expected[i], 1e-3, 1e-5))
        << names[i] << "\nhand-written\n"
        << params[i].grad() << "\nautograd\n"
        << expected[i];
    // alone, a member attends only to itself (weight 1 whatever the scores): without others the
    // (observation, action) embedding, the query and the key get no gradient
    auto starts = [&](const char* prefix) { return names[i].rfind(prefix, 0) == 0; };
    const bool unused =
        U == 0 && (starts("obs_action_embedding") || starts("query") || starts("key"));
    if (!unused) {
      EXPECT_GT(expected[i].abs().sum().item<float>(), 0.f) << names[i] << " has no gradient";
    }
  }
  // a second minibatch on the same object (scratch reused) gives the same result
  for (auto& p : critic->parameters()) p.mutable_grad().fill_(-5.f);
  CriticLossValues again = gradient.compute(mb, epsilon, value_coef, baseline_coef);
  EXPECT_EQ(again.value, got.value);
  for (size_t i = 0; i < params.size(); ++i)
    EXPECT_TRUE(torch::allclose(params[i].grad(), expected[i], 1e-3, 1e-5)) << names[i];
}

INSTANTIATE_TEST_SUITE_P(
    Critics, PocaCriticGradientTest,
    ::testing::Values(CriticCase{1, 4, Activation::kSwish}, CriticCase{3, 4, Activation::kTanh},
                      CriticCase{2, 1, Activation::kRelu}, CriticCase{0, 2, Activation::kSwish},
                      CriticCase{3, 2, Activation::kSwish, 6, 3, 16, 1},
                      CriticCase{3, 2, Activation::kSwish, 6, 3, 16, 0},
                      // layers large enough for the BLAS path of multiply() (see below)
                      CriticCase{1, 4, Activation::kSwish, 40, 9, 160, 2, 100}));

TEST(PocaCriticGradientSizes, LargeCaseTakesTheBlasPath) {
  // the attention projections of the large case: 2 x 100 rows x 2 members, 160 x 160
  EXPECT_GE(int64_t(2 * 100 * 2) * 160 * 160, kBlasProductMinMultiplies);
  EXPECT_LT(int64_t(2 * 37 * 4) * 16 * 16, kBlasProductMinMultiplies);
}

}  // namespace
}  // namespace rlt
