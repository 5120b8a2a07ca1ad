// Duel: conformance, fair starts, wins, draws, time limit, symmetric observations, and a scripted
// player against a random one.
#include "env/toy/duel.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>

#include "env/register_builtin_envs.h"
#include "rl/env_api/conformance.h"
#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += s + "\n";
  return out;
}

struct Rows {
  BehaviorBuffers& b;
  StepType type(int s) const { return b.step_type[s]; }
  float reward(int s) const { return b.reward[s]; }
  int terminated(int s) const { return b.terminated[s]; }
  const float* obs(int s) const { return b.observations[0].data() + s * Duel::kObservationSize; }
  void act(int s, double vx, double vy) {
    b.continuous_actions[2 * s] = static_cast<float>(vx);
    b.continuous_actions[2 * s + 1] = static_cast<float>(vy);
  }
};

// full speed at the target, read from the observation alone
void straight_at_target(Rows& rows, int s) {
  const float* o = rows.obs(s);
  const double dx = o[6], dy = o[7];
  const double n = std::hypot(dx, dy);
  rows.act(s, n > 0 ? dx / n : 0, n > 0 ? dy / n : 0);
}

TEST(DuelTest, SpecIsOneBehaviorForTwoTeams) {
  Duel env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "Duel");
  EXPECT_EQ(spec.max_episode_steps, 30);
  ASSERT_EQ(spec.behaviors.size(), 1u);
  const BehaviorSpec& b = spec.behaviors[0];
  EXPECT_EQ(b.name, "Duelist");
  EXPECT_EQ(b.agent_slots, 2);
  EXPECT_EQ(b.observations.at(0).shape, std::vector<int>({10}));
  EXPECT_EQ(b.action.continuous_size, 2);
  EXPECT_EQ(b.action.num_branches(), 0);
}

TEST(DuelTest, Conforms) {
  register_builtin_envs();
  const auto violations = check_env_conformance("Duel");
  EXPECT_TRUE(violations.empty()) << joined(violations);
}

TEST(DuelTest, StartsAreFairAndInside) {
  Duel env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  for (uint64_t seed = 0; seed < 500; ++seed) {
    env.seed(seed);
    h.reset();
    for (int s = 0; s < 2; ++s) {
      EXPECT_EQ(rows.type(s), StepType::kFirst);
      EXPECT_EQ(h.buffers().agent_id[s], s);
      EXPECT_EQ(h.buffers().group_id[s], s);
      EXPECT_LE(std::fabs(env.player(s).x), 1.0);
      EXPECT_LE(std::fabs(env.player(s).y), 1.0);
    }
    const auto dist = [&](int s) {
      return std::hypot(env.player(s).x - env.target().x, env.player(s).y - env.target().y);
    };
    EXPECT_NEAR(dist(0), dist(1), 1e-12);
    EXPECT_GE(dist(0), 0.5 - 1e-12);
    EXPECT_LE(dist(0), 1.0 + 1e-12);
  }
}

TEST(DuelTest, ObservationsAreSymmetric) {
  Duel env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  env.seed(3);
  h.reset();
  env.set_player(0, {-0.5, 0.25});
  env.set_player(1, {0.5, -0.75});
  env.set_target({0.25, 0.5});
  rows.act(0, 0, 0);
  rows.act(1, 0, 0);
  h.step();
  // (me, opponent, target, unit direction to the target, distance / 2 sqrt 2, elapsed / 30)
  const double d0 = std::hypot(0.75, 0.25), d1 = std::hypot(-0.25, 1.25);
  const double diagonal = 2 * std::sqrt(2.0);
  const float expected0[10] = {-0.5f,
                               0.25f,
                               0.5f,
                               -0.75f,
                               0.25f,
                               0.5f,
                               float(0.75 / d0),
                               float(0.25 / d0),
                               float(d0 / diagonal),
                               1.f / 30};
  const float expected1[10] = {0.5f,
                               -0.75f,
                               -0.5f,
                               0.25f,
                               0.25f,
                               0.5f,
                               float(-0.25 / d1),
                               float(1.25 / d1),
                               float(d1 / diagonal),
                               1.f / 30};
  for (int k = 0; k < 10; ++k) {
    EXPECT_FLOAT_EQ(rows.obs(0)[k], expected0[k]) << k;
    EXPECT_FLOAT_EQ(rows.obs(1)[k], expected1[k]) << k;
  }
}

TEST(DuelTest, TheFirstToTouchTheTargetWins) {
  for (int winner : {0, 1}) {
    Duel env;
    SingleEnvHarness h(env);
    Rows rows{h.buffers()};
    h.reset();
    env.set_target({0, 0});
    env.set_player(winner, {0.4, 0});
    env.set_player(1 - winner, {-0.5, 0});
    // the winner needs 2 moves of 0.15 to come within 0.15; the other would need 3
    for (int t = 1; t <= 2; ++t) {
      rows.act(winner, -1, 0);
      rows.act(1 - winner, 1, 0);
      h.step();
      ASSERT_EQ(rows.type(0), t < 2 ? StepType::kMid : StepType::kLast) << t;
    }
    EXPECT_EQ(rows.reward(winner), 1.f);
    EXPECT_EQ(rows.reward(1 - winner), -1.f);
    for (int s = 0; s < 2; ++s) {
      EXPECT_EQ(rows.type(s), StepType::kLast);
      EXPECT_EQ(rows.terminated(s), 1);
    }
    const EpisodeMetrics m = env.episode_metrics();
    EXPECT_EQ(m.at("win_team0"), winner == 0 ? 1.f : 0.f);
    EXPECT_EQ(m.at("draw"), 0.f);
    h.step();
    EXPECT_EQ(rows.type(0), StepType::kAbsent);
    EXPECT_EQ(rows.type(1), StepType::kAbsent);
  }
}

TEST(DuelTest, TouchingTogetherIsADraw) {
  Duel env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  env.set_target({0, 0});
  env.set_player(0, {0.2, 0});
  env.set_player(1, {0, -0.2});
  rows.act(0, -1, 0);
  rows.act(1, 0, 1);
  h.step();
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(rows.type(s), StepType::kLast);
    EXPECT_EQ(rows.terminated(s), 1);
    EXPECT_EQ(rows.reward(s), 0.f);
  }
  EXPECT_EQ(env.episode_metrics().at("win_team0"), 0.5f);
  EXPECT_EQ(env.episode_metrics().at("draw"), 1.f);
}

TEST(DuelTest, SpeedIsCappedAndPlayersStayInside) {
  Duel env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  env.set_target({-0.8, -0.8});
  env.set_player(0, {0.5, 0.5});
  env.set_player(1, {0.95, 0});
  rows.act(0, 5, 5);  // clipped to (1, 1), then to length 1
  rows.act(1, 1, 0);
  h.step();
  EXPECT_NEAR(env.player(0).x, 0.5 + 0.15 / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(env.player(0).y, 0.5 + 0.15 / std::sqrt(2.0), 1e-6);
  EXPECT_EQ(env.player(1).x, 1.0);
}

TEST(DuelTest, TimeLimitIsATruncatedDraw) {
  Duel env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  for (int t = 1; t <= 30; ++t) {
    rows.act(0, 0, 0);
    rows.act(1, 0, 0);
    h.step();
    ASSERT_EQ(rows.type(0), t < 30 ? StepType::kMid : StepType::kLast);
    ASSERT_EQ(rows.type(1), rows.type(0));
    EXPECT_EQ(rows.reward(0), 0.f);
  }
  EXPECT_EQ(rows.terminated(0), 0);
  EXPECT_EQ(rows.terminated(1), 0);
  EXPECT_EQ(env.episode_metrics().at("win_team0"), 0.5f);
  EXPECT_EQ(env.episode_metrics().at("draw"), 1.f);
}

// The measured numbers of the header comment.
TEST(DuelTest, AScriptedPlayerBeatsARandomOne) {
  Duel env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  env.seed(11);
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  const int episodes = 20000;
  // scripted on side `scripted` (-1: none, 2: both); returns mean win_team0, mean draw, length
  auto play = [&](int scripted) {
    double win0 = 0, draws = 0, length = 0;
    for (int e = 0; e < episodes; ++e) {
      h.reset();
      while (needs_action(rows.type(0))) {
        for (int s = 0; s < 2; ++s) {
          if (scripted == s || scripted == 2) {
            straight_at_target(rows, s);
          } else {
            rows.act(s, u(rng), u(rng));
          }
        }
        h.step();
      }
      win0 += env.episode_metrics().at("win_team0");
      draws += env.episode_metrics().at("draw");
      length += env.elapsed_steps();
    }
    return std::array<double, 3>{win0 / episodes, draws / episodes, length / episodes};
  };
  const auto random = play(-1);
  const auto scripted0 = play(0);
  const auto scripted1 = play(1);
  const auto both = play(2);
  std::printf(
      "random: win_team0 %.4f draw %.4f length %.2f; scripted 0: %.4f; scripted 1: %.4f; both "
      "scripted: draw %.4f, length %.2f\n",
      random[0], random[1], random[2], scripted0[0], scripted1[0], both[1], both[2]);
  EXPECT_NEAR(random[0], 0.5, 0.02);
  EXPECT_GE(random[1], 0.7);  // a random walk seldom touches the target
  EXPECT_GE(scripted0[0], 0.99);
  EXPECT_LE(scripted1[0], 0.01);
  EXPECT_EQ(both[1], 1.0);
  EXPECT_LE(both[2], 7.0);
}

}  // namespace
}  // namespace rlt
