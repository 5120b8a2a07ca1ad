// PocaTrainer on a hand-built three-agent group: what it records per experience (the groupmates'
// observations and actions, never the agent's own action), rewards shared within the group, and the
// posthumous bootstrap of an agent that leaves before its group.
#include "rl/poca/poca_trainer.h"

#include <gtest/gtest.h>

#include "rl/config/config_parser.h"
#include "rl/env_api/vector_env.h"
#include "rl/env_api/env_registry.h"

namespace rlt {
namespace {

// Three agents in one group. Observation: one-hot of the slot and the time. Agent 2 leaves
// (terminated) after 3 steps; the others run 6 steps. Reward: 0.1 x action per agent;
// group reward 1 at the last step.
class GroupEnv : public Env {
 public:
  GroupEnv() {
    spec_.name = "GroupEnv";
    spec_.max_episode_steps = 6;
    BehaviorSpec b;
    b.name = "Member";
    b.agent_slots = 3;
    b.observations.push_back({"state", {4}, ObservationKind::kVector, 0.f, 1.f});
    b.action.discrete_branches = {4};
    spec_.behaviors.push_back(b);
  }
  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t) override {}
  void reset(StepView& out) override {
    t_ = 0;
    for (int s = 0; s < 3; ++s) {
      out[0].step_type(s) = StepType::kFirst;
      out[0].agent_id(s) = s;
      out[0].group_id(s) = 0;
      write(out, s);
    }
  }
  void step(StepView& io) override {
    ++t_;
    auto& v = io[0];
    for (int s = 0; s < 3; ++s) {
      if (!needs_action(v.step_type(s))) {
        v.step_type(s) = StepType::kAbsent;
        continue;
      }
      v.reward(s) = 0.1f * v.discrete_action(s)[0];
      const bool leaves = (s == 2 && t_ == 3) || t_ == 6;
      v.step_type(s) = leaves ? StepType::kLast : StepType::kMid;
      v.terminated(s) = leaves ? 1 : 0;
      if (t_ == 6) v.group_reward(s) = 1.f;
      write(io, s);
    }
  }

 private:
  void write(StepView& v, int s) {
    float* o = v[0].observation(s);
    for (int i = 0; i < 3; ++i) o[i] = i == s ? 1.f : 0.f;
    o[3] = t_ / 6.f;
  }
  EnvSpec spec_;
  int t_ = 0;
};

class InspectablePoca : public PocaTrainer {
 public:
  using PocaTrainer::PocaTrainer;
  const ExperienceBuffer& update_buffer() const { return buffer_; }
  const ExperienceBuffer& trajectory(int row) const { return trajectories_[row]; }
  const std::vector<float>& rewards(int row) const { return rewards_[row]; }
};

BehaviorConfig poca_config() {
  auto config = load_run_config_from_string(
      "behaviors:\n  Member:\n    trainer_type: poca\n"
      "    hyperparameters: {batch_size: 8, buffer_size: 64}\n"
      "    network_settings: {hidden_units: 8, num_layers: 1}\n"
      "    time_horizon: 100\nenv_settings: {env_id: GroupEnv}\n",
      "test.yaml");
  return config.behaviors.at("Member");
}

class PocaTrainerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!EnvRegistry::instance().contains("GroupEnv"))
      EnvRegistry::instance().add("GroupEnv", [](const Parameters&) { return std::make_unique<GroupEnv>(); });
  }
};

TEST_F(PocaTrainerTest, RecordsGroupmatesObservationsAndActionsNotItsOwn) {
  VectorEnv env("GroupEnv", 1, 0);
  torch::manual_seed(0);
  InspectablePoca trainer(env.spec().behaviors[0], poca_config(), 3, 1, "GroupEnv");
  env.reset();
  auto& buf = env.buffers(0);
  trainer.act(buf);
  for (int r = 0; r < 3; ++r) {
    const auto& t = trainer.trajectory(r);
    ASSERT_EQ(t.others_present.size(), 2u);
    ASSERT_EQ(t.others_action.size(), 2u * 4);
    int o = 0;
    for (int m = 0; m < 3; ++m) {
      if (m == r) continue;
      EXPECT_EQ(t.others_present[o], 1.f);
      EXPECT_EQ(t.others_obs[o * 4 + m], 1.f) << "slot " << o << " of row " << r << " holds member " << m;
      for (int a = 0; a < 4; ++a)
        EXPECT_EQ(t.others_action[o * 4 + a], a == buf.discrete_actions[m] ? 1.f : 0.f);
      ++o;
    }
  }
  // rewards are shared: each member's training reward is the sum over the group
  env.step();
  trainer.observe(buf);
  const float total = 0.1f * (buf.discrete_actions[0] + buf.discrete_actions[1] + buf.discrete_actions[2]);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(trainer.rewards(r).back(), total, 1e-6);
}

TEST_F(PocaTrainerTest, AgentLeavingEarlyBootstrapsFromTheGroupValue) {
  VectorEnv env("GroupEnv", 1, 0);
  torch::manual_seed(0);
  InspectablePoca trainer(env.spec().behaviors[0], poca_config(), 3, 1, "GroupEnv");
  env.reset();
  auto& buf = env.buffers(0);
  for (int t = 0; t < 3; ++t) {
    trainer.act(buf);
    env.step();
    trainer.observe(buf);
  }
  // agent 2 left (terminated) while the others go on: its trajectory is in the update buffer and
  // its last lambda-return is r + gamma V(group now), V over its final and the others' observations
  const auto& b = trainer.update_buffer();
  ASSERT_EQ(b.size(), 3);
  const float gamma = poca_config().extrinsic.gamma;
  const float r_last = buf.reward[0] + buf.reward[1] + buf.reward[2];  // shared within the group
  float expected_bootstrap;
  {
    torch::NoGradGuard g;
    auto obs = torch::from_blob(buf.observations[0].data(), {1, 3, 4}).clone();  // slots 0, 1, 2
    auto group = obs.index_select(1, torch::tensor({2, 0, 1}, torch::kInt64));    // own first
    expected_bootstrap = trainer.critic()->value(group, torch::ones({1, 3})).item<float>();
  }
  EXPECT_GT(std::abs(expected_bootstrap), 1e-4f);
  EXPECT_NEAR(b.returns[2], r_last + gamma * expected_bootstrap, 1e-5);
  // the rest of the group finishes together, terminated: no bootstrap, the last return is the
  // last reward (both members' rewards plus the group reward of 1)
  for (int t = 3; t < 6; ++t) {
    trainer.act(buf);
    env.step();
    trainer.observe(buf);
  }
  ASSERT_EQ(b.size(), 3 + 2 * 6);
  const float final_reward = buf.reward[0] + buf.reward[1] + 1.f;
  EXPECT_NEAR(b.returns[3 + 5], final_reward, 1e-6);
  EXPECT_NEAR(b.returns[3 + 11], final_reward, 1e-6);
  // advantage = return - baseline
  for (int i = 0; i < b.size(); ++i) EXPECT_NEAR(b.advantages[i], b.returns[i] - b.baseline[i], 1e-6);
}

TEST_F(PocaTrainerTest, AbsentMembersTakeTheLastSlots) {
  // after agent 2 leaves, each remaining member records its one groupmate in slot 0 and an empty
  // slot 1 (the critic skips slots that no experience uses)
  VectorEnv env("GroupEnv", 1, 0);
  torch::manual_seed(0);
  InspectablePoca trainer(env.spec().behaviors[0], poca_config(), 3, 1, "GroupEnv");
  env.reset();
  auto& buf = env.buffers(0);
  for (int t = 0; t < 4; ++t) {
    trainer.act(buf);
    if (t < 3) {
      env.step();
      trainer.observe(buf);
    }
  }
  for (int r = 0; r < 2; ++r) {
    const auto& t = trainer.trajectory(r);
    const int steps = int(t.others_present.size()) / 2;
    ASSERT_EQ(steps, 4);
    const int last = steps - 1, mate = 1 - r;
    EXPECT_EQ(t.others_present[last * 2 + 0], 1.f);
    EXPECT_EQ(t.others_present[last * 2 + 1], 0.f);
    EXPECT_EQ(t.others_obs[(last * 2 + 0) * 4 + mate], 1.f) << "row " << r;
    for (int i = 0; i < 4; ++i) EXPECT_EQ(t.others_obs[(last * 2 + 1) * 4 + i], 0.f);
  }
}

}  // namespace
}  // namespace rlt
