// The MA-POCA critic: absent members change nothing, members are a set (order does not matter),
// and the baseline depends on the other members' actions (the agent's own is not an input).
#include "rl/poca/poca_critic.h"

#include <gtest/gtest.h>

namespace rlt {
namespace {

PocaCritic make_critic() {
  torch::manual_seed(5);
  PocaCriticShape shape;
  shape.obs_size = 5;
  shape.action_size = 3;
  shape.hidden_units = 16;
  shape.num_layers = 2;
  shape.heads = 4;
  return PocaCritic(shape);
}

TEST(PocaCritic, AbsentMembersChangeNothing) {
  auto critic = make_critic();
  torch::NoGradGuard g;
  auto obs = torch::randn({6, 4, 5});                         // 4 member slots
  auto present = torch::tensor({1.f, 1.f, 0.f, 0.f}).repeat({6, 1});
  auto v = critic->value(obs, present);
  // garbage in the absent slots
  auto garbage = obs.clone();
  garbage.narrow(1, 2, 2).copy_(torch::randn({6, 2, 5}) * 1000);
  EXPECT_TRUE(torch::equal(critic->value(garbage, present), v));
  // the same group without the absent slots at all
  EXPECT_TRUE(torch::allclose(critic->value(obs.narrow(1, 0, 2), present.narrow(1, 0, 2)), v, 1e-5, 1e-6));
  // while a present member does matter
  auto changed = obs.clone();
  changed.select(1, 1).add_(1.f);
  EXPECT_FALSE(torch::allclose(critic->value(changed, present), v, 1e-3, 1e-3));

  // baseline: an absent other member's observation and action change nothing
  auto own = torch::randn({6, 5});
  auto others = torch::randn({6, 3, 5}), actions = torch::randn({6, 3, 3});
  auto others_present = torch::tensor({1.f, 0.f, 1.f}).repeat({6, 1});
  auto b = critic->baseline(own, others, actions, others_present);
  auto others2 = others.clone(), actions2 = actions.clone();
  others2.select(1, 1).fill_(77.f);
  actions2.select(1, 1).fill_(-9.f);
  EXPECT_TRUE(torch::equal(critic->baseline(own, others2, actions2, others_present), b));
}

TEST(PocaCritic, MembersAreASet) {
  auto critic = make_critic();
  torch::NoGradGuard g;
  auto obs = torch::randn({3, 3, 5});
  auto present = torch::ones({3, 3});
  auto permuted = obs.index_select(1, torch::tensor({2, 0, 1}, torch::kInt64));
  EXPECT_TRUE(torch::allclose(critic->value(permuted, present), critic->value(obs, present), 1e-5, 1e-6));
}

TEST(PocaCritic, BaselineDependsOnOthersActionsOnly) {
  auto critic = make_critic();
  torch::NoGradGuard g;
  auto own = torch::randn({4, 5});
  auto others = torch::randn({4, 2, 5}), actions = torch::randn({4, 2, 3});
  auto present = torch::ones({4, 2});
  auto b = critic->baseline(own, others, actions, present);
  // another member's action changes the baseline
  auto other_actions = actions.clone();
  other_actions.select(1, 0).add_(1.f);
  EXPECT_FALSE(torch::allclose(critic->baseline(own, others, other_actions, present), b, 1e-4, 1e-4));
  // the agent's own action has no input at all (the trainer stores only the groupmates' actions:
  // see poca_trainer_test); the baseline differs from the group value (which sees no actions)
  auto all = torch::cat({own.unsqueeze(1), others}, 1);
  EXPECT_FALSE(torch::allclose(critic->value(all, torch::ones({4, 3})), b, 1e-4, 1e-4));
}

}  // namespace
}  // namespace rlt
