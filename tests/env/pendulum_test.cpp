// Pendulum against Gymnasium's Pendulum-v1: golden steps, clipping, truncation, the "g" parameter.
#include "env/classic/pendulum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "env/register_builtin_envs.h"
#include "rl/env_api/env_registry.h"
#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

constexpr double kPi = 3.141592653589793;
using State = Pendulum::State;

// Steps `env` once from `state` with continuous action `action` (in [-1, 1] before clipping).
void step_from(Pendulum& env, SingleEnvHarness& h, const State& state, float action) {
  env.set_state(state);
  h.set_continuous(0, action);
  h.step();
}

TEST(PendulumTest, SpecIsPendulumV1) {
  Pendulum env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "Pendulum");
  EXPECT_EQ(spec.max_episode_steps, 200);
  ASSERT_EQ(spec.default_parameters.size(), 1u);
  EXPECT_EQ(spec.default_parameters.at("g"), 10.f);
  ASSERT_EQ(spec.behaviors.size(), 1u);
  const BehaviorSpec& b = spec.behaviors[0];
  EXPECT_EQ(b.name, "Pendulum");
  EXPECT_EQ(b.observations[0].shape, std::vector<int>({3}));
  EXPECT_EQ(b.observations[0].low, -8.f);
  EXPECT_EQ(b.observations[0].high, 8.f);
  EXPECT_EQ(b.action.continuous_size, 1);
  EXPECT_TRUE(b.action.discrete_branches.empty());
}

// Golden numbers: Gymnasium's Pendulum-v1 step expressions evaluated in Python floats (IEEE
// double), rounded to float32. Torque = 2 * action.
TEST(PendulumTest, StepsMatchGymnasiumGolden) {
  Pendulum env;
  SingleEnvHarness h(env);
  h.reset();

  // th = 1, thdot = 0.5, torque 0.5
  step_from(env, h, {1.0, 0.5}, 0.25f);
  EXPECT_EQ(h.observation()[0], 0.4886058568954468f);
  EXPECT_EQ(h.observation()[1], 0.8725046515464783f);
  EXPECT_EQ(h.observation()[2], 1.2061032056808472f);
  EXPECT_EQ(h.reward(), -1.02524995803833f);
  EXPECT_EQ(h.step_type(), StepType::kMid);

  // th = 4 (beyond pi: the cost wraps it), thdot = -2, torque -2
  step_from(env, h, {4.0, -2.0}, -1.f);
  EXPECT_EQ(h.observation()[0], -0.7550753951072693f);
  EXPECT_EQ(h.observation()[1], -0.6556379795074463f);
  EXPECT_EQ(h.observation()[2], -2.8676018714904785f);
  EXPECT_EQ(h.reward(), -5.6169352531433105f);

  // th = -3, thdot = 7.9, torque 2: the new speed 8.09 is clipped to 8
  step_from(env, h, {-3.0, 7.9}, 1.f);
  EXPECT_EQ(h.observation()[0], -0.8568887710571289f);
  EXPECT_EQ(h.observation()[1], -0.5155013799667358f);
  EXPECT_EQ(h.observation()[2], 8.f);
  EXPECT_EQ(h.reward(), -15.244999885559082f);
  EXPECT_DOUBLE_EQ(env.state().theta, -2.6);
}

TEST(PendulumTest, StepsMatchTheEquationsFromRandomStates) {
  Pendulum env;
  SingleEnvHarness h(env);
  h.reset();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(-10.0, 10.0), speed(-8.0, 8.0), action(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const State s{angle(rng), speed(rng)};
    const float a = static_cast<float>(action(rng));
    step_from(env, h, s, a);
    // written out: wrapped angle, torque, speed update clipped to 8, angle from the new speed
    const double u = 2.0 * a;
    const double wrapped = s.theta - 2 * kPi * std::floor((s.theta + kPi) / (2 * kPi));
    const double cost = wrapped * wrapped + 0.1 * s.theta_dot * s.theta_dot + 0.001 * u * u;
    const double speed_new =
        std::min(8.0, std::max(-8.0, s.theta_dot + (15.0 * std::sin(s.theta) + 3.0 * u) * 0.05));
    EXPECT_NEAR(env.state().theta_dot, speed_new, 1e-12);
    EXPECT_NEAR(env.state().theta, s.theta + 0.05 * speed_new, 1e-12);
    EXPECT_NEAR(h.reward(), -cost, 1e-5);
  }
}

TEST(PendulumTest, AngleNormalizeFollowsPythonModulo) {
  EXPECT_EQ(Pendulum::angle_normalize(0.0), 0.0);
  EXPECT_NEAR(Pendulum::angle_normalize(0.5), 0.5, 1e-15);
  EXPECT_NEAR(Pendulum::angle_normalize(-0.5), -0.5, 1e-15);
  EXPECT_NEAR(Pendulum::angle_normalize(4.0), 4.0 - 2 * kPi, 1e-15);
  EXPECT_NEAR(Pendulum::angle_normalize(-4.0), -4.0 + 2 * kPi, 1e-15);
  EXPECT_NEAR(Pendulum::angle_normalize(2 * kPi + 1.0), 1.0, 1e-14);
  EXPECT_NEAR(Pendulum::angle_normalize(-6 * kPi - 1.0), -1.0, 1e-14);
  // pi maps to -pi: the range is [-pi, pi)
  EXPECT_NEAR(Pendulum::angle_normalize(kPi), -kPi, 1e-15);
}

TEST(PendulumTest, ActionsAreClippedToOneBeforeScaling) {
  Pendulum env;
  SingleEnvHarness h(env);
  h.reset();
  for (float big : {5.f, -3.f}) {
    step_from(env, h, {0.3, 0.1}, big);
    const State clipped_state = env.state();
    const float clipped_reward = h.reward();
    step_from(env, h, {0.3, 0.1}, big > 0 ? 1.f : -1.f);
    EXPECT_EQ(env.state().theta_dot, clipped_state.theta_dot);
    EXPECT_EQ(h.reward(), clipped_reward);
  }
}

TEST(PendulumTest, TruncatesAfter200StepsAndNeverTerminates) {
  Pendulum env;
  SingleEnvHarness h(env);
  env.seed(9);
  h.reset();
  EXPECT_EQ(h.step_type(), StepType::kFirst);
  for (int t = 1; t <= 200; ++t) {
    h.set_continuous(0, t % 3 == 0 ? 1.f : -1.f);
    h.step();
    EXPECT_EQ(h.terminated(), 0);
    EXPECT_LE(h.reward(), 0.f);
    EXPECT_GE(h.reward(), -16.2736044f - 1e-4f);  // pi^2 + 0.1 * 64 + 0.001 * 4
    ASSERT_EQ(h.step_type(), t < 200 ? StepType::kMid : StepType::kLast) << "step " << t;
  }
  h.step();
  EXPECT_EQ(h.step_type(), StepType::kAbsent);
}

TEST(PendulumTest, ResetDrawsAngleAndSpeedInRange) {
  Pendulum env;
  SingleEnvHarness h(env);
  double max_abs_theta = 0;
  for (uint64_t seed = 0; seed < 200; ++seed) {
    env.seed(seed);
    h.reset();
    EXPECT_EQ(h.step_type(), StepType::kFirst);
    EXPECT_EQ(h.reward(), 0.f);
    EXPECT_LE(std::fabs(env.state().theta), kPi);
    EXPECT_LE(std::fabs(env.state().theta_dot), 1.0);
    EXPECT_EQ(h.observation()[0], static_cast<float>(std::cos(env.state().theta)));
    EXPECT_EQ(h.observation()[1], static_cast<float>(std::sin(env.state().theta)));
    EXPECT_EQ(h.observation()[2], static_cast<float>(env.state().theta_dot));
    max_abs_theta = std::max(max_abs_theta, std::fabs(env.state().theta));
  }
  EXPECT_GT(max_abs_theta, 2.5);  // the whole circle is used, not just [-1, 1]
}

TEST(PendulumTest, GravityParameterTakesEffectAtReset) {
  Pendulum env;
  SingleEnvHarness h(env);
  h.reset();
  EXPECT_EQ(env.gravity(), 10.0);
  env.set_parameters({{"g", 9.81f}});
  EXPECT_EQ(env.gravity(), 10.0);  // not before the next reset
  h.reset();
  EXPECT_EQ(env.gravity(), static_cast<double>(9.81f));
  // golden: th = 1, thdot = 0.5, torque 0.5 with g = float(9.81)
  step_from(env, h, {1.0, 0.5}, 0.25f);
  EXPECT_EQ(h.observation()[2], 1.1941123008728027f);
  EXPECT_EQ(h.reward(), -1.02524995803833f);  // the cost does not depend on g
}

TEST(PendulumTest, RegistryPassesTheGravityParameter) {
  register_builtin_envs();
  auto env = EnvRegistry::instance().make("Pendulum", {{"g", 4.f}});
  auto* pendulum = dynamic_cast<Pendulum*>(env.get());
  ASSERT_NE(pendulum, nullptr);
  SingleEnvHarness h(*env);
  h.reset();
  EXPECT_EQ(pendulum->gravity(), 4.0);
  EXPECT_THROW(EnvRegistry::instance().make("Pendulum", {{"gravity", 4.f}}), std::invalid_argument);
}

TEST(PendulumTest, SameSeedSameEpisodeOtherSeedOtherEpisode) {
  auto run = [](uint64_t seed) {
    Pendulum env;
    SingleEnvHarness h(env);
    env.seed(seed);
    h.reset();
    std::vector<float> trace;
    for (int t = 0; t < 30; ++t) {
      h.set_continuous(0, std::sin(0.3f * t));
      h.step();
      trace.insert(trace.end(), h.observation(), h.observation() + 3);
      trace.push_back(h.reward());
    }
    return trace;
  };
  EXPECT_EQ(run(1), run(1));
  EXPECT_NE(run(1), run(2));
}

}  // namespace
}  // namespace rlt
