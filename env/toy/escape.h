// Escape: three agents on a small grid must sacrifice one of them to a guard to get out.
//
// In the spirit of Unity ML-Agents' DungeonEscape (`Project/Assets/ML-Agents/Examples/
// DungeonEscape`, the MA-POCA showcase): touching the dragon kills the agent and drops the key,
// a teammate picks the key up and opens the door, and the whole group is rewarded. An independent
// learner that sacrifices itself never sees the reward, so the task needs group credit assignment.
//
// World: a grid of `grid_size` x `grid_size` cells (default 5). At reset the three agents, the
// guard and the door are placed on five different cells drawn uniformly; the key is hidden.
// One behavior "EscapeAgent", 3 slots, agent id = slot, group 0. Actions: one branch of 5,
// 0 stay, 1 up (y + 1), 2 down (y - 1), 3 left (x - 1), 4 right (x + 1); a move off the grid
// stays. All options are always allowed. Agents may share cells. Each step, in this order:
//   1. every agent moves;
//   2. sacrifice: the first agent (in slot order) on the guard's cell, while the guard is alive,
//      leaves the episode (kLast, terminated, reward 0); the guard vanishes and the key drops on
//      that cell;
//   3. pick-up: the first other agent on the key's cell takes the key (possibly in the same step);
//   4. escape: when the holder stands on the door, every agent still present gets group reward
//      1 - 0.5 * elapsed / 50, kLast terminated; metric success_rate = 1.
// After 50 decisions the episode is truncated (kLast, terminated 0, success_rate 0). No other reward.
// Deliberate difference from DungeonEscape: its escape reward 1 - elapsed / max falls to 0 at the
// time limit; ours keeps half of it, a clearer signal for a late escape. The guard does not move.
//
// Observation "state" (19 values in [-1, 1]) of the agent in slot s; "rel" = (other - own) /
// (grid_size - 1) per axis, positions are cell / (grid_size - 1):
//   [0, 2)   own position                 [2]     elapsed / 50
//   [3, 5)   guard rel (0 once gone)      [5]     guard present
//   [6, 8)   key rel: on the floor, or at the teammate holding it; else 0
//   [8]      key on the floor             [9]     I hold the key       [10] a teammate holds it
//   [11, 13) door rel
//   [13, 19) teammates in slots s+1, s+2 (mod 3): rel x, rel y, present (zeros when gone)
// Metrics: "success_rate" (1 escaped, 0 not; its mean over episodes is the rate), "sacrificed"
// (1 when the guard was taken out).
//
// Parameter: `grid_size` (default 5, 3-8), read at reset.
//
// Measured on the default 5 x 5 grid (escape_test, 20000 episodes): uniform random actions escape
// in 18% of the episodes (mean reward of an agent still present at the end: 0.11); the scripted
// team of escape_test (all walk to the guard, the one nearest to the key fetches it, the holder
// walks to the door) escapes in 100%, after 6.6 decisions on average (reward 0.93), about optimal.
// Learning, with this project's PPO (rlt train, one policy shared by the three agents, 8 envs,
// 64-64 tanh, buffer 2048): independent learners escape in 19% after 300k agent steps and 11%
// after 1M at lr 3e-4 (10% and 9% at lr 1e-3), having learned to avoid the guard (sacrifice rate
// 0.30, then 0.12). The same runs on a variant where the sacrificed agent stays in the game and
// shares the escape reward reach 89% after 300k at lr 3e-4 (100% after 1M) and 100% after 300k at
// lr 1e-3 (7.0 decisions): the task is easy once the sacrifice is credited, which is what
// MA-POCA's group value is for. This project's MA-POCA trainer (16 envs, 64-64, lr 1e-3, buffer
// 2048) escapes in 100% of 1000 evaluation episodes after 300k agent steps (43 s on one core).
#pragma once

#include <array>
#include <cstdint>
#include <random>

#include "rl/env_api/env.h"

namespace rlt {

class Escape : public Env {
 public:
  struct Cell {
    int x = 0;
    int y = 0;
    bool operator==(const Cell& o) const { return x == o.x && y == o.y; }
  };

  static constexpr int kAgents = 3;
  static constexpr int kActions = 5;  // stay, up, down, left, right
  static constexpr int kObservationSize = 19;
  static constexpr int kEpisodeSteps = 50;
  static constexpr int kMinGrid = 3;
  static constexpr int kMaxGrid = 8;
  static constexpr float kDefaultGrid = 5.f;

  Escape();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override;
  void reset(StepView& out) override;
  void step(StepView& io) override;
  EpisodeMetrics episode_metrics() const override;

  // the state, and test hooks that move things on the current episode's grid
  int grid_size() const { return grid_; }
  const Cell& agent_cell(int slot) const { return agents_[slot]; }
  bool agent_present(int slot) const { return present_[slot]; }
  const Cell& guard_cell() const { return guard_; }
  bool guard_alive() const { return guard_alive_; }
  const Cell& key_cell() const { return key_; }
  bool key_on_floor() const { return key_on_floor_; }
  int key_holder() const { return key_holder_; }  // slot, or -1
  const Cell& door_cell() const { return door_; }
  int elapsed_steps() const { return elapsed_; }
  void set_agent_cell(int slot, Cell c) { agents_[slot] = c; }
  void set_guard_cell(Cell c) { guard_ = c; }
  void set_door_cell(Cell c) { door_ = c; }

  // the cell one action leads to from `c`, on a grid of `n` cells per side
  static Cell moved(Cell c, int action, int n);

 private:
  void write_observation(BehaviorView& view, int slot) const;

  EnvSpec spec_;
  std::mt19937_64 engine_;
  int grid_ = 5;                         // cells per side, fixed at reset
  std::array<Cell, kAgents> agents_{};   // [3] cell of each slot's agent
  std::array<bool, kAgents> present_{};  // [3] agent still in the episode
  Cell guard_;
  bool guard_alive_ = true;
  Cell key_;  // where the key lies once dropped
  bool key_on_floor_ = false;
  int key_holder_ = -1;  // slot holding the key, or -1
  Cell door_;
  int elapsed_ = 0;  // decisions in this episode
  bool success_ = false;
};

}  // namespace rlt
