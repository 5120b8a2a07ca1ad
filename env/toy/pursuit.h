// Pursuit: hiders and seekers as point masses in a walled square, a fast 2D hide-and-seek.
//
// In the spirit of OpenAI's hide-and-seek (Baker et al. 2020, "Emergent Tool Use From Multi-Agent
// Autocurricula") and of this project's 3D world (SPEC.md section 6): a prep phase in which the
// seekers are frozen, line-of-sight vision blocked by walls, tagging by touch, small rewards for
// hiding and seeing. No props, no physics engine: it trains in seconds.
//
// World: the square [-5, 5]^2 m with axis-aligned walls 0.2 m thick, chosen by `level`:
//   1: one wall x = 0, y in [-2.5, 2.5];
//   2: a plus, the wall of level 1 and y = 0, x in [-2.5, 2.5];
//   3: the plus and two walls from the border: y = 2.5, x in [-5, -2.5]; y = -2.5, x in [2.5, 5].
// Agents are discs of radius 0.3 m; each decision lasts 0.1 s: v = 0.75 (v + 10 a 0.1) with the
// acceleration a of the action, speed capped at 3 m/s, then the disc moves in two substeps that
// slide along walls and the border. Agents pass through each other. Spawns are uniform, clear of
// walls, seekers at least 3 m from every hider.
// Behaviors "Hider" (2 slots, group 0, agent id = slot) and "Seeker" (3 slots, group 1, agent id =
// 2 + slot); `num_hiders` (1-2) and `num_seekers` (1-3) pick how many are used, the other slots
// stay kAbsent. Actions: one discrete branch of 5 accelerations, 0 none, 1 +y, 2 -y, 3 -x, 4 +x.
// During the prep phase, the first round(prep_fraction * episode_length) decisions, seekers are
// frozen and their mask allows only option 0 (1 = allowed).
// Seeing: a seeker sees a hider (and the hider sees it) when they are closer than `vision_range`
// and the segment between their centres crosses no wall.
// Rewards each decision of the test phase (after the prep phase):
//   - a seeker closer than 0.6 m (radius sum) to a hider tags it: the hider gets -1 and leaves
//     (kLast, terminated); every seeker gets group reward +1 per tagged hider;
//   - each hider still in the game and seen by no seeker gets `hide_reward` (default 0.005);
//   - every seeker gets group reward `seen_reward` (default 0.005) per hider seen.
// (0.005 per 0.1 s decision is about the paper's 0.001 per 20 ms frame, small next to a tag.)
// End: all hiders tagged with `end_on_tag` = 1 (seekers kLast terminated), or `episode_length`
// decisions (10-300; everyone kLast truncated).
// Parameters (defaults): num_hiders 1, num_seekers 2, prep_fraction 0.3, episode_length 100,
// level 1, end_on_tag 1, hide_reward 0.005, seen_reward 0.005, vision_range 10 (m).
//
// Observations, one vector "state" of 30 values in [-1, 1] for both behaviors; another agent is
// written as (unit direction to it (2), distance / arena diagonal 14.14 m, flag):
//   [0, 2) own position / 5        [2, 4) velocity / 3        [4] elapsed / episode_length
//   [5] prep phase (1 while the seekers are frozen)
//   per opponent slot (Hider: 3 seeker slots, Seeker: 2 hider slots): the other agent with a
//     visible flag, zeros when not visible or absent;
//   per teammate slot, in slot order after mine (Hider: 1, Seeker: 2): the other agent with a
//     present flag, zeros when absent;
//   [22, 30) 8 rays at 0, 45, ..., 315 degrees from +x: distance to the nearest wall or border
//     / 5 m, 1 when none within 5 m.
// Hider: 6 + 3 * 4 + 4 + 8 = 30; Seeker: 6 + 2 * 4 + 2 * 4 + 8 = 30.
// Metrics: "tag_rate" (1 if a hider was tagged), "seen_fraction" (share of test-phase decisions
// with a hider present in which some hider was seen, a tag counting as seen), "tagged" (count).
//
// Measured (defaults; pursuit_test, 2000 episodes): random seekers against a random hider tag in
// 3% of the episodes (seen_fraction 0.79); scripted seekers (accelerate at the nearest hider, round
// a wall's end when it is in the way) tag a still hider in 99.7% (after 24 test-phase decisions on
// average; 97.6% at level 3) and a random hider in 100%.
// Learning, with this project's PPO (rlt train, 8 envs, 64-64 tanh, lr 3e-4, buffer 2048) for the
// seekers against a random hider (its learning rate 1e-10): tag rate 0.45 after 200k seeker steps,
// 0.99 after 500k. Why these choices, measured the same way:
//   - 2 continuous accelerations instead of the 5 moves: 0.05 after 200k, 0.93-0.96 after 500k;
//   - opponents as relative position / 10 instead of (direction, distance): 0.17-0.32 after 500k,
//     about 0.5 after 1M (small inputs near the target say little about where to go).
// Both teams learning (PPO, 500k steps each): tag rate 0.73.
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "rl/env_api/env.h"

namespace rlt {

class Pursuit : public Env {
 public:
  enum Team { kHider = 0, kSeeker = 1 };

  struct Body {
    double x = 0, y = 0;    // position (m)
    double vx = 0, vy = 0;  // velocity (m/s)
    bool present = false;   // in the game (not tagged, slot in use)
  };
  // an axis-aligned box: centre and half extents (m)
  struct Wall {
    double cx, cy, hx, hy;
  };

  static constexpr int kMaxHiders = 2;
  static constexpr int kMaxSeekers = 3;
  static constexpr int kActions = 5;  // none, +y, -y, -x, +x
  static constexpr int kRays = 8;
  static constexpr int kObservationSize = 30;
  static constexpr int kMaxEpisodeLength = 300;  // largest `episode_length`
  static constexpr double kHalfSize = 5.0;       // arena [-5, 5]^2 (m)
  static constexpr double kRadius = 0.3;         // agent disc (m)
  static constexpr double kDt = 0.1;             // seconds per decision
  static constexpr double kAccel = 10.0;         // m/s^2 at full action
  static constexpr double kDamping = 0.75;       // velocity factor per decision
  static constexpr double kMaxSpeed = 3.0;       // m/s
  static constexpr double kRayLength = 5.0;      // m
  static constexpr double kWallHalfThickness = 0.1;
  static constexpr double kDiagonal = 14.142135623730951;  // of the arena (m)

  Pursuit();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override;
  void reset(StepView& out) override;
  void step(StepView& io) override;
  EpisodeMetrics episode_metrics() const override;

  // walls of a level (1-3), without the border
  static std::vector<Wall> level_walls(int level);

  // the state, and test hooks on the current episode
  const Body& body(Team team, int slot) const { return bodies_[team][slot]; }
  void set_body(Team team, int slot, double x, double y, double vx = 0, double vy = 0) {
    bodies_[team][slot] = {x, y, vx, vy, bodies_[team][slot].present};
  }
  const std::vector<Wall>& walls() const { return walls_; }
  int elapsed_steps() const { return elapsed_; }
  int prep_steps() const { return prep_steps_; }
  bool in_prep() const { return elapsed_ < prep_steps_; }
  // true when the segment between the two points crosses no wall
  bool line_of_sight(double x0, double y0, double x1, double y1) const;
  // true when seeker `s` sees hider `h` (both present, in range, line of sight)
  bool sees(int seeker, int hider) const;
  // distance from (x, y) along the unit direction (dx, dy) to a wall or the border, at most `max`
  double ray_distance(double x, double y, double dx, double dy, double max) const;

 private:
  void move(Body& b, double ax, double ay);  // ax, ay: acceleration in [-1, 1], |a| <= 1
  void write_observation(BehaviorView& view, Team team, int slot) const;
  void write_mask(BehaviorView& view, Team team, int slot) const;
  bool overlaps_wall(double x, double y, double clearance) const;

  EnvSpec spec_;
  std::mt19937_64 engine_;

  // settings of the episode, read from the parameters at reset
  int num_agents_[2] = {1, 2};  // hiders, seekers in use
  int episode_length_ = 100;
  int prep_steps_ = 30;
  bool end_on_tag_ = true;
  double vision_range_ = 10.0;
  float hide_reward_ = 0.005f;
  float seen_reward_ = 0.005f;
  std::vector<Wall> walls_;

  // state
  std::array<std::array<Body, kMaxSeekers>, 2> bodies_{};  // [team][slot]; hiders use 2 slots
  int elapsed_ = 0;
  int tagged_ = 0;
  int test_steps_ = 0;  // test-phase decisions with a hider present
  int seen_steps_ = 0;  // of which some hider was seen
};

}  // namespace rlt
