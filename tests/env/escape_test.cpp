// Escape: conformance, scripted scenes (sacrifice, pick-up, escape, time limit), observation
// layout, and success rates of a random and a scripted team.
#include "env/toy/escape.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <set>
#include <string>

#include "env/register_builtin_envs.h"
#include "rl/env_api/conformance.h"
#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

using Cell = Escape::Cell;
constexpr int kStay = 0, kUp = 1, kDown = 2, kLeft = 3, kRight = 4;

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += s + "\n";
  return out;
}

// the three agents' rows of the harness
struct Rows {
  BehaviorBuffers& b;
  StepType type(int s) const { return b.step_type[s]; }
  float group_reward(int s) const { return b.group_reward[s]; }
  float reward(int s) const { return b.reward[s]; }
  int terminated(int s) const { return b.terminated[s]; }
  const float* obs(int s) const { return b.observations[0].data() + s * Escape::kObservationSize; }
  void act(int s, int a) { b.discrete_actions[s] = a; }
  void act_all(int a0, int a1, int a2) { act(0, a0), act(1, a1), act(2, a2); }
};

// A scene: agents at (0,0), (4,0), (4,4); guard (1,0); door (0,4) on the 5 x 5 grid.
void set_scene(Escape& env) {
  env.set_agent_cell(0, {0, 0});
  env.set_agent_cell(1, {4, 0});
  env.set_agent_cell(2, {4, 4});
  env.set_guard_cell({1, 0});
  env.set_door_cell({0, 4});
}

// greedy step from `from` towards `to`: the axis with the longer way first
int toward(Cell from, Cell to) {
  const int dx = to.x - from.x, dy = to.y - from.y;
  if (dx == 0 && dy == 0) return kStay;
  if (std::abs(dx) >= std::abs(dy)) return dx > 0 ? kRight : kLeft;
  return dy > 0 ? kUp : kDown;
}

int manhattan(Cell a, Cell b) { return std::abs(a.x - b.x) + std::abs(a.y - b.y); }

// The scripted team: everyone walks to the guard while it lives (the first to arrive is taken);
// then the agent nearest to the key fetches it and the holder walks to the door.
void scripted_actions(const Escape& env, Rows& rows) {
  int fetcher = -1;
  if (env.key_on_floor()) {
    for (int s = 0; s < Escape::kAgents; ++s) {
      if (!needs_action(rows.type(s))) continue;
      if (fetcher < 0 || manhattan(env.agent_cell(s), env.key_cell()) <
                             manhattan(env.agent_cell(fetcher), env.key_cell()))
        fetcher = s;
    }
  }
  for (int s = 0; s < Escape::kAgents; ++s) {
    const Cell me = env.agent_cell(s);
    int a = kStay;
    if (env.guard_alive()) a = toward(me, env.guard_cell());
    if (s == fetcher) a = toward(me, env.key_cell());
    if (env.key_holder() == s) a = toward(me, env.door_cell());
    rows.act(s, a);
  }
}

// Plays `episodes` episodes; `policy(rows)` writes the actions. Returns the success rate and the
// mean group reward of the agents that reached the end of an episode.
template <typename Policy>
std::pair<double, double> play(Escape& env, int episodes, Policy policy) {
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  double successes = 0, reward = 0;
  int finishers = 0;
  for (int e = 0; e < episodes; ++e) {
    h.reset();
    bool any_acts = true;
    while (any_acts) {
      policy(rows);
      h.step();
      any_acts = false;
      for (int s = 0; s < Escape::kAgents; ++s) {
        any_acts = any_acts || needs_action(rows.type(s));
        reward += rows.group_reward(s);
      }
    }
    for (int s = 0; s < Escape::kAgents; ++s) finishers += env.agent_present(s);
    successes += env.episode_metrics().at("success_rate");
  }
  return {successes / episodes, reward / std::max(finishers, 1)};
}

TEST(EscapeTest, SpecIsThreeAgentsOfOneBehavior) {
  Escape env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "Escape");
  EXPECT_EQ(spec.max_episode_steps, 50);
  ASSERT_EQ(spec.behaviors.size(), 1u);
  const BehaviorSpec& b = spec.behaviors[0];
  EXPECT_EQ(b.name, "EscapeAgent");
  EXPECT_EQ(b.agent_slots, 3);
  EXPECT_EQ(b.observations.at(0).shape, std::vector<int>({19}));
  EXPECT_EQ(b.observations.at(0).low, -1.f);
  EXPECT_EQ(b.observations.at(0).high, 1.f);
  EXPECT_EQ(b.action.continuous_size, 0);
  EXPECT_EQ(b.action.discrete_branches, std::vector<int>({5}));
  EXPECT_EQ(spec.default_parameters.at("grid_size"), 5.f);
}

TEST(EscapeTest, Conforms) {
  register_builtin_envs();
  for (float grid : {3.f, 5.f, 8.f}) {
    SCOPED_TRACE(grid);
    const auto violations = check_env_conformance("Escape", {{"grid_size", grid}});
    EXPECT_TRUE(violations.empty()) << joined(violations);
  }
}

TEST(EscapeTest, ResetPlacesFiveDifferentCellsAndThreeAgents) {
  Escape env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  std::set<std::pair<int, int>> guard_cells;
  for (uint64_t seed = 0; seed < 200; ++seed) {
    env.seed(seed);
    h.reset();
    std::set<std::pair<int, int>> cells;
    for (int s = 0; s < 3; ++s) {
      EXPECT_EQ(rows.type(s), StepType::kFirst);
      EXPECT_EQ(h.buffers().agent_id[s], s);
      EXPECT_EQ(h.buffers().group_id[s], 0);
      cells.insert({env.agent_cell(s).x, env.agent_cell(s).y});
    }
    cells.insert({env.guard_cell().x, env.guard_cell().y});
    cells.insert({env.door_cell().x, env.door_cell().y});
    EXPECT_EQ(cells.size(), 5u);
    for (const auto& [x, y] : cells) {
      EXPECT_TRUE(x >= 0 && x < 5 && y >= 0 && y < 5);
    }
    EXPECT_TRUE(env.guard_alive());
    EXPECT_FALSE(env.key_on_floor());
    EXPECT_EQ(env.key_holder(), -1);
    guard_cells.insert({env.guard_cell().x, env.guard_cell().y});
  }
  EXPECT_EQ(guard_cells.size(), 25u) << "the guard can stand anywhere";
}

TEST(EscapeTest, MovesStayOnTheGrid) {
  EXPECT_EQ(Escape::moved({2, 2}, kUp, 5), (Cell{2, 3}));
  EXPECT_EQ(Escape::moved({2, 2}, kDown, 5), (Cell{2, 1}));
  EXPECT_EQ(Escape::moved({2, 2}, kLeft, 5), (Cell{1, 2}));
  EXPECT_EQ(Escape::moved({2, 2}, kRight, 5), (Cell{3, 2}));
  EXPECT_EQ(Escape::moved({2, 2}, kStay, 5), (Cell{2, 2}));
  EXPECT_EQ(Escape::moved({4, 4}, kUp, 5), (Cell{4, 4}));
  EXPECT_EQ(Escape::moved({4, 4}, kRight, 5), (Cell{4, 4}));
  EXPECT_EQ(Escape::moved({0, 0}, kDown, 5), (Cell{0, 0}));
  EXPECT_EQ(Escape::moved({0, 0}, kLeft, 5), (Cell{0, 0}));
}

TEST(EscapeTest, ObservationLayout) {
  Escape env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  set_scene(env);
  rows.act_all(kStay, kStay, kStay);
  h.step();
  const float* o = rows.obs(1);  // agent 1 at (4, 0)
  const float q = 0.25f;         // one cell
  EXPECT_EQ(o[0], 1.f);
  EXPECT_EQ(o[1], 0.f);
  EXPECT_EQ(o[2], 1.f / 50);
  EXPECT_EQ(o[3], -3 * q);  // guard (1, 0)
  EXPECT_EQ(o[4], 0.f);
  EXPECT_EQ(o[5], 1.f);
  for (int k = 6; k <= 10; ++k) EXPECT_EQ(o[k], 0.f) << k;  // no key yet
  EXPECT_EQ(o[11], -1.f);                                   // door (0, 4)
  EXPECT_EQ(o[12], 1.f);
  EXPECT_EQ(o[13], 0.f);  // agent 2 at (4, 4)
  EXPECT_EQ(o[14], 1.f);
  EXPECT_EQ(o[15], 1.f);
  EXPECT_EQ(o[16], -1.f);  // agent 0 at (0, 0)
  EXPECT_EQ(o[17], 0.f);
  EXPECT_EQ(o[18], 1.f);
}

TEST(EscapeTest, SacrificePickUpAndEscape) {
  Escape env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  set_scene(env);

  // agent 0 steps onto the guard: it leaves, the guard vanishes, the key lies on (1, 0)
  rows.act_all(kRight, kLeft, kStay);
  h.step();
  EXPECT_EQ(rows.type(0), StepType::kLast);
  EXPECT_EQ(rows.terminated(0), 1);
  EXPECT_EQ(rows.reward(0), 0.f);
  EXPECT_EQ(rows.group_reward(0), 0.f);
  EXPECT_FALSE(env.agent_present(0));
  EXPECT_FALSE(env.guard_alive());
  EXPECT_TRUE(env.key_on_floor());
  EXPECT_EQ(env.key_cell(), (Cell{1, 0}));
  EXPECT_EQ(rows.type(1), StepType::kMid);
  EXPECT_EQ(rows.type(2), StepType::kMid);
  const float* o1 = rows.obs(1);  // agent 1 at (3, 0)
  EXPECT_EQ(o1[5], 0.f);          // guard gone
  EXPECT_EQ(o1[6], -0.5f);        // key two cells left
  EXPECT_EQ(o1[8], 1.f);
  EXPECT_EQ(o1[13], 0.25f);  // agent 2, the first teammate of agent 1, at (4, 4): still there
  EXPECT_EQ(o1[15], 1.f);
  EXPECT_EQ(o1[18], 0.f);  // agent 0 gone
  EXPECT_EQ(o1[16], 0.f);

  // agent 0 stays absent; agent 1 walks onto the key
  rows.act_all(kRight, kLeft, kStay);
  h.step();
  EXPECT_EQ(rows.type(0), StepType::kAbsent);
  EXPECT_EQ(h.buffers().agent_id[0], -1);
  EXPECT_EQ(env.key_holder(), -1);
  rows.act_all(kStay, kLeft, kStay);
  h.step();
  EXPECT_EQ(env.key_holder(), 1);
  EXPECT_FALSE(env.key_on_floor());
  EXPECT_EQ(rows.obs(1)[9], 1.f);   // I hold it
  EXPECT_EQ(rows.obs(2)[10], 1.f);  // a teammate holds it, at (1, 0) seen from (4, 4)
  EXPECT_EQ(rows.obs(2)[6], -0.75f);
  EXPECT_EQ(rows.obs(2)[7], -1.f);
  EXPECT_EQ(rows.group_reward(1), 0.f);

  // the holder walks (1, 0) -> (0, 0) -> (0, 4): escape at decision 3 + 5 = 8
  const int path[5] = {kLeft, kUp, kUp, kUp, kUp};
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(rows.type(1), StepType::kMid);
    rows.act_all(kStay, path[k], kDown);
    h.step();
  }
  const float expected = 1.f - 0.5f * 8.f / 50.f;
  for (int s : {1, 2}) {
    EXPECT_EQ(rows.type(s), StepType::kLast) << s;
    EXPECT_EQ(rows.terminated(s), 1) << s;
    EXPECT_FLOAT_EQ(rows.group_reward(s), expected) << s;
    EXPECT_EQ(rows.reward(s), 0.f) << s;
  }
  EXPECT_EQ(rows.type(0), StepType::kAbsent);
  EXPECT_EQ(env.episode_metrics().at("success_rate"), 1.f);
  EXPECT_EQ(env.episode_metrics().at("sacrificed"), 1.f);
  h.step();
  for (int s = 0; s < 3; ++s) EXPECT_EQ(rows.type(s), StepType::kAbsent);
}

TEST(EscapeTest, TheDoorNeedsTheKey) {
  Escape env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  set_scene(env);
  env.set_agent_cell(2, {0, 3});
  rows.act_all(kStay, kStay, kUp);  // agent 2 onto the door without the key
  h.step();
  EXPECT_EQ(env.agent_cell(2), (Cell{0, 4}));
  for (int s = 0; s < 3; ++s) EXPECT_EQ(rows.type(s), StepType::kMid);
  EXPECT_EQ(env.episode_metrics().at("success_rate"), 0.f);
}

TEST(EscapeTest, TwoAgentsOnTheGuardAtOnce) {
  Escape env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  set_scene(env);
  env.set_agent_cell(1, {2, 0});
  // agents 0 and 1 both reach (1, 0): slot 0 is taken, slot 1 picks the key up at once
  rows.act_all(kRight, kLeft, kStay);
  h.step();
  EXPECT_EQ(rows.type(0), StepType::kLast);
  EXPECT_EQ(rows.terminated(0), 1);
  EXPECT_EQ(rows.type(1), StepType::kMid);
  EXPECT_EQ(env.key_holder(), 1);
  EXPECT_FALSE(env.key_on_floor());
}

TEST(EscapeTest, TruncatedAfterFiftyDecisions) {
  Escape env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  set_scene(env);
  for (int t = 1; t <= 50; ++t) {
    rows.act_all(kStay, kStay, kStay);
    h.step();
    for (int s = 0; s < 3; ++s) {
      ASSERT_EQ(rows.type(s), t < 50 ? StepType::kMid : StepType::kLast) << t;
      EXPECT_EQ(rows.terminated(s), 0);
      EXPECT_EQ(rows.group_reward(s), 0.f);
    }
  }
  EXPECT_EQ(env.episode_metrics().at("success_rate"), 0.f);
  EXPECT_EQ(env.episode_metrics().at("sacrificed"), 0.f);
}

TEST(EscapeTest, RejectsAnOutOfRangeAction) {
  Escape env;
  SingleEnvHarness h(env);
  Rows rows{h.buffers()};
  h.reset();
  rows.act_all(kStay, 5, kStay);
  EXPECT_THROW(h.step(), std::invalid_argument);
}

TEST(EscapeTest, GridSizeParameter) {
  Escape env;
  env.set_parameters({{"grid_size", 3.f}});
  SingleEnvHarness h(env);
  h.reset();
  EXPECT_EQ(env.grid_size(), 3);
  env.set_parameters({{"grid_size", 20.f}});
  h.reset();
  EXPECT_EQ(env.grid_size(), 8);
}

// The measured numbers of the header comment: a scripted team nearly always escapes, fast; random
// actions rarely do.
TEST(EscapeTest, ScriptedTeamEscapesAndRandomRarelyDoes) {
  Escape env;
  env.seed(17);
  const auto [scripted_rate, scripted_return] =
      play(env, 20000, [&](Rows& rows) { scripted_actions(env, rows); });
  std::mt19937_64 rng(5);
  const auto [random_rate, random_return] = play(env, 20000, [&](Rows& rows) {
    for (int s = 0; s < 3; ++s) rows.act(s, std::uniform_int_distribution<int>(0, 4)(rng));
  });
  std::printf("scripted: success %.4f, return %.4f; random: success %.4f, return %.4f\n",
              scripted_rate, scripted_return, random_rate, random_return);
  EXPECT_GE(scripted_rate, 0.99);
  EXPECT_GE(scripted_return, 0.85);
  EXPECT_LE(random_rate, 0.5);
  EXPECT_GT(random_rate, 0.05);
  EXPECT_LT(random_return, 0.5 * scripted_return);
}

}  // namespace
}  // namespace rlt
