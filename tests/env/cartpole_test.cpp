// CartPole against Gymnasium's CartPole-v1: golden steps, thresholds, truncation, seeding.
#include "env/classic/cartpole.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

using State = CartPole::State;

// One Euler step written out from the textbook equations (Barto, Sutton & Anderson 1983 with
// Florian's correction), independently of the env's code.
State reference_step(const State& s, int action) {
  const double g = 9.8, m_cart = 1.0, m_pole = 0.1, half_length = 0.5, dt = 0.02;
  const double m_total = m_cart + m_pole;
  const double f = action == 1 ? 10.0 : -10.0;
  const double c = std::cos(s.theta), sn = std::sin(s.theta);
  const double common = (f + m_pole * half_length * s.theta_dot * s.theta_dot * sn) / m_total;
  const double theta_acc =
      (g * sn - c * common) / (half_length * (4.0 / 3.0 - m_pole * c * c / m_total));
  const double x_acc = common - m_pole * half_length * theta_acc * c / m_total;
  return {s.x + dt * s.x_dot, s.x_dot + dt * x_acc, s.theta + dt * s.theta_dot,
          s.theta_dot + dt * theta_acc};
}

// Steps `env` once from `state` with `action`.
void step_from(CartPole& env, SingleEnvHarness& h, const State& state, int action) {
  env.set_state(state);
  h.set_discrete(0, action);
  h.step();
}

TEST(CartPoleTest, SpecIsCartPoleV1) {
  CartPole env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "CartPole");
  EXPECT_EQ(spec.max_episode_steps, 500);
  EXPECT_TRUE(spec.default_parameters.empty());
  ASSERT_EQ(spec.behaviors.size(), 1u);
  const BehaviorSpec& b = spec.behaviors[0];
  EXPECT_EQ(b.name, "CartPole");
  EXPECT_EQ(b.agent_slots, 1);
  ASSERT_EQ(b.observations.size(), 1u);
  EXPECT_EQ(b.observations[0].name, "state");
  EXPECT_EQ(b.observations[0].shape, std::vector<int>({4}));
  EXPECT_EQ(b.action.continuous_size, 0);
  EXPECT_EQ(b.action.discrete_branches, std::vector<int>({2}));
  EXPECT_DOUBLE_EQ(CartPole::kThetaThreshold, 12 * 2 * 3.141592653589793 / 360);
}

TEST(CartPoleTest, ResetStartsAnAgentNearUpright) {
  CartPole env;
  SingleEnvHarness h(env);
  for (uint64_t seed = 0; seed < 50; ++seed) {
    env.seed(seed);
    h.reset();
    EXPECT_EQ(h.step_type(), StepType::kFirst);
    EXPECT_EQ(h.buffers().agent_id[0], 0);
    EXPECT_EQ(h.buffers().group_id[0], 0);
    EXPECT_EQ(h.reward(), 0.f);
    EXPECT_EQ(env.elapsed_steps(), 0);
    for (int j = 0; j < 4; ++j) {
      EXPECT_GE(h.observation()[j], -0.05f);
      EXPECT_LE(h.observation()[j], 0.05f);
    }
    EXPECT_EQ(h.observation()[0], static_cast<float>(env.state().x));
    EXPECT_EQ(h.observation()[3], static_cast<float>(env.state().theta_dot));
  }
}

// Golden numbers: Gymnasium's CartPole-v1 step expressions evaluated in Python floats (IEEE double)
// from state (0.01, -0.02, 0.03, 0.04), then rounded to float32 as Gymnasium's observation is.
TEST(CartPoleTest, OneStepMatchesGymnasiumGolden) {
  CartPole env;
  SingleEnvHarness h(env);
  const State start{0.01, -0.02, 0.03, 0.04};

  h.reset();
  step_from(env, h, start, 1);
  EXPECT_EQ(h.observation()[0], 0.009600000455975533f);
  EXPECT_EQ(h.observation()[1], 0.17467918992042542f);
  EXPECT_EQ(h.observation()[2], 0.030799999833106995f);
  EXPECT_EQ(h.observation()[3], -0.24306872487068176f);
  EXPECT_EQ(h.reward(), 1.f);
  EXPECT_EQ(h.step_type(), StepType::kMid);
  EXPECT_EQ(h.terminated(), 0);

  h.reset();
  step_from(env, h, start, 0);
  EXPECT_EQ(h.observation()[0], 0.009600000455975533f);
  EXPECT_EQ(h.observation()[1], -0.21553902328014374f);
  EXPECT_EQ(h.observation()[2], 0.030799999833106995f);
  EXPECT_EQ(h.observation()[3], 0.3419952094554901f);
}

TEST(CartPoleTest, ThreeStepsMatchGymnasiumGolden) {
  CartPole env;
  SingleEnvHarness h(env);
  h.reset();
  env.set_state({0.01, -0.02, 0.03, 0.04});
  for (int action : {1, 1, 0}) {
    h.set_discrete(0, action);
    h.step();
  }
  EXPECT_EQ(h.observation()[0], 0.02048054337501526f);
  EXPECT_EQ(h.observation()[1], 0.17387081682682037f);
  EXPECT_EQ(h.observation()[2], 0.015421032905578613f);
  EXPECT_EQ(h.observation()[3], -0.22513741254806519f);
  EXPECT_EQ(env.elapsed_steps(), 3);
}

TEST(CartPoleTest, StepsMatchTheEquationsFromRandomStates) {
  CartPole env;
  SingleEnvHarness h(env);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-2.0, 2.0), angle(-0.2, 0.2), speed(-3.0, 3.0);
  h.reset();
  for (int i = 0; i < 200; ++i) {
    const State s{pos(rng), speed(rng), angle(rng), speed(rng)};
    const int action = i % 2;
    step_from(env, h, s, action);
    const State want = reference_step(s, action);
    EXPECT_NEAR(env.state().x, want.x, 1e-12);
    EXPECT_NEAR(env.state().x_dot, want.x_dot, 1e-12);
    EXPECT_NEAR(env.state().theta, want.theta, 1e-12);
    EXPECT_NEAR(env.state().theta_dot, want.theta_dot, 1e-12);
    h.reset();  // a step may have ended the episode
  }
}

TEST(CartPoleTest, TerminatesWhenTheCartLeavesTheTrack) {
  CartPole env;
  SingleEnvHarness h(env);
  for (double dir : {1.0, -1.0}) {
    h.reset();
    step_from(env, h, {2.39 * dir, 1.0 * dir, 0.0, 0.0}, 0);  // x -> +-2.41
    EXPECT_EQ(h.step_type(), StepType::kLast);
    EXPECT_EQ(h.terminated(), 1);
    EXPECT_EQ(h.reward(), 1.f);  // the terminating step is rewarded too
    EXPECT_NEAR(h.observation()[0], 2.41 * dir, 1e-6);
  }
}

TEST(CartPoleTest, ThresholdsAreStrict) {
  CartPole env;
  SingleEnvHarness h(env);
  // exactly on the threshold with no velocity: still alive
  h.reset();
  step_from(env, h, {2.4, 0.0, 0.0, 0.0}, 1);
  EXPECT_EQ(env.state().x, 2.4);
  EXPECT_EQ(h.step_type(), StepType::kMid);
  h.reset();
  step_from(env, h, {0.0, 0.0, -CartPole::kThetaThreshold, 0.0}, 0);
  EXPECT_EQ(env.state().theta, -CartPole::kThetaThreshold);
  EXPECT_EQ(h.step_type(), StepType::kMid);
}

TEST(CartPoleTest, TerminatesWhenThePoleFalls) {
  CartPole env;
  SingleEnvHarness h(env);
  for (double dir : {1.0, -1.0}) {
    h.reset();
    step_from(env, h, {0.0, 0.0, 0.2 * dir, 1.0 * dir}, 0);  // theta -> +-0.22 > 0.2094
    EXPECT_EQ(h.step_type(), StepType::kLast);
    EXPECT_EQ(h.terminated(), 1);
    EXPECT_EQ(h.reward(), 1.f);
  }
}

TEST(CartPoleTest, TruncatesAfter500StepsWithTerminatedZero) {
  CartPole env;
  SingleEnvHarness h(env);
  env.seed(3);
  h.reset();
  for (int t = 1; t <= 500; ++t) {
    step_from(env, h, {}, t % 2);  // from rest every step: never falls
    EXPECT_EQ(h.reward(), 1.f);
    EXPECT_EQ(h.terminated(), 0);
    ASSERT_EQ(h.step_type(), t < 500 ? StepType::kMid : StepType::kLast) << "step " << t;
  }
  // the slot is empty until the next reset
  h.step();
  EXPECT_EQ(h.step_type(), StepType::kAbsent);
}

TEST(CartPoleTest, TerminationOnStep500IsATermination) {
  CartPole env;
  SingleEnvHarness h(env);
  h.reset();
  for (int t = 1; t < 500; ++t) step_from(env, h, {}, 0);
  step_from(env, h, {2.39, 1.0, 0.0, 0.0}, 0);
  EXPECT_EQ(h.step_type(), StepType::kLast);
  EXPECT_EQ(h.terminated(), 1);
}

TEST(CartPoleTest, PushingOneWayEndsWithinTheDeclaredBound) {
  CartPole env;
  SingleEnvHarness h(env);
  const float bound = env.spec().behaviors[0].observations[0].high;
  for (int action : {0, 1}) {
    env.seed(11);
    h.reset();
    int steps = 0;
    while (h.step_type() != StepType::kLast) {
      h.set_discrete(0, action);
      h.step();
      ++steps;
      for (int j = 0; j < 4; ++j) EXPECT_LE(std::fabs(h.observation()[j]), bound);
    }
    EXPECT_EQ(h.terminated(), 1);
    EXPECT_LT(steps, 30);  // the pole falls fast
  }
}

TEST(CartPoleTest, SameSeedSameEpisodeOtherSeedOtherEpisode) {
  auto run = [](uint64_t seed) {
    CartPole env;
    SingleEnvHarness h(env);
    env.seed(seed);
    h.reset();
    std::vector<float> trace(h.observation(), h.observation() + 4);
    for (int t = 0; t < 20 && h.step_type() != StepType::kLast; ++t) {
      h.set_discrete(0, (t / 3) % 2);
      h.step();
      trace.insert(trace.end(), h.observation(), h.observation() + 4);
    }
    return trace;
  };
  EXPECT_EQ(run(5), run(5));
  EXPECT_NE(run(5), run(6));
}

TEST(CartPoleTest, RejectsAnInvalidAction) {
  CartPole env;
  SingleEnvHarness h(env);
  h.reset();
  h.set_discrete(0, 2);
  EXPECT_THROW(h.step(), std::invalid_argument);
  h.set_discrete(0, -1);
  EXPECT_THROW(h.step(), std::invalid_argument);
}

}  // namespace
}  // namespace rlt
