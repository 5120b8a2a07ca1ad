// Pursuit: conformance for every level and team size, tags, the prep phase, sight through walls,
// walls that stop agents, rays, and tag rates of random and scripted seekers.
#include "env/toy/pursuit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>

#include "env/register_builtin_envs.h"
#include "rl/env_api/conformance.h"
#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

constexpr int kNone = 0, kUp = 1, kDown = 2, kLeft = 3, kRight = 4;
constexpr auto kHider = Pursuit::kHider;
constexpr auto kSeeker = Pursuit::kSeeker;

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += s + "\n";
  return out;
}

// rows of one behavior in the harness
struct Rows {
  BehaviorBuffers& b;
  StepType type(int s) const { return b.step_type[s]; }
  float reward(int s) const { return b.reward[s]; }
  float group_reward(int s) const { return b.group_reward[s]; }
  int terminated(int s) const { return b.terminated[s]; }
  const float* obs(int s) const { return b.observations[0].data() + s * Pursuit::kObservationSize; }
  const uint8_t* mask(int s) const { return b.action_mask.data() + s * Pursuit::kActions; }
  void act(int s, int a) { b.discrete_actions[s] = a; }
};

// a harness over a Pursuit with `params`, reset once
struct Game {
  explicit Game(const Parameters& params = {}) : h(env) {
    env.set_parameters(params);
    h.reset();
  }
  void step(int hider_action, int seeker_action) {
    for (int s = 0; s < Pursuit::kMaxHiders; ++s) hiders.act(s, hider_action);
    for (int s = 0; s < Pursuit::kMaxSeekers; ++s) seekers.act(s, seeker_action);
    h.step();
  }
  Pursuit env;
  SingleEnvHarness h;
  Rows hiders{h.buffers(0)};
  Rows seekers{h.buffers(1)};
};

// the discrete option that accelerates from (x, y) most directly towards (tx, ty)
int toward(double x, double y, double tx, double ty) {
  const double dx = tx - x, dy = ty - y;
  if (std::fabs(dx) >= std::fabs(dy)) return dx > 0 ? kRight : kLeft;
  return dy > 0 ? kUp : kDown;
}

// A scripted seeker's move towards (tx, ty): straight when the way is clear, else through the
// corner (0.5 m out from a wall's end) that gives the shortest clear two-leg path.
int chase(const Pursuit& env, double x, double y, double tx, double ty) {
  if (env.line_of_sight(x, y, tx, ty)) return toward(x, y, tx, ty);
  double best = 1e9, wx = tx, wy = ty;
  for (bool need_both : {true, false}) {
    for (const auto& w : env.walls())
      for (int cx : {-1, 1})
        for (int cy : {-1, 1}) {
          const double px = w.cx + cx * (w.hx + 0.5), py = w.cy + cy * (w.hy + 0.5);
          if (std::fabs(px) > 4.7 || std::fabs(py) > 4.7) continue;
          if (!env.line_of_sight(x, y, px, py)) continue;
          if (need_both && !env.line_of_sight(px, py, tx, ty)) continue;
          const double len = std::hypot(px - x, py - y) + std::hypot(tx - px, ty - py);
          if (len < best) best = len, wx = px, wy = py;
        }
    if (best < 1e9) break;
  }
  return toward(x, y, wx, wy);
}

// Plays `episodes` episodes with greedy seekers (or random ones) against a still (or random)
// hider. Returns the means of the metrics tag_rate and seen_fraction and of the decisions after
// the prep phase until the first tag, over tagged episodes.
struct Rates {
  double tag_rate = 0, seen_fraction = 0, decisions_to_tag = 0;
};
Rates play(const Parameters& params, int episodes, bool greedy_seekers, bool random_hider,
           uint64_t seed) {
  Pursuit env;
  env.set_parameters(params);
  env.seed(seed);
  SingleEnvHarness h(env);
  Rows hiders{h.buffers(0)}, seekers{h.buffers(1)};
  std::mt19937_64 rng(seed + 1);
  std::uniform_int_distribution<int> option(0, Pursuit::kActions - 1);
  Rates r;
  int tagged_episodes = 0;
  for (int e = 0; e < episodes; ++e) {
    h.reset();
    int first_tag = -1;
    for (;;) {
      bool any = false;
      for (int s = 0; s < Pursuit::kMaxHiders; ++s) {
        any = any || needs_action(hiders.type(s));
        hiders.act(s, random_hider ? option(rng) : kNone);
      }
      for (int s = 0; s < Pursuit::kMaxSeekers; ++s) {
        any = any || needs_action(seekers.type(s));
        const Pursuit::Body& me = env.body(kSeeker, s);
        int a = option(rng);
        if (greedy_seekers) {
          // nearest hider still in the game
          double best = 1e9;
          a = kNone;
          for (int k = 0; k < Pursuit::kMaxHiders; ++k) {
            const Pursuit::Body& hb = env.body(kHider, k);
            const double d = std::hypot(hb.x - me.x, hb.y - me.y);
            if (hb.present && d < best) best = d, a = chase(env, me.x, me.y, hb.x, hb.y);
          }
        }
        if (!seekers.mask(s)[a]) a = kNone;
        seekers.act(s, a);
      }
      if (!any) break;
      h.step();
      if (first_tag < 0 && env.episode_metrics().at("tagged") > 0) first_tag = env.elapsed_steps();
    }
    const EpisodeMetrics m = env.episode_metrics();
    r.tag_rate += m.at("tag_rate");
    r.seen_fraction += m.at("seen_fraction");
    if (first_tag >= 0) {
      r.decisions_to_tag += first_tag - env.prep_steps();
      ++tagged_episodes;
    }
  }
  r.tag_rate /= episodes;
  r.seen_fraction /= episodes;
  r.decisions_to_tag /= std::max(tagged_episodes, 1);
  return r;
}

TEST(PursuitTest, SpecHasHidersAndSeekers) {
  Pursuit env;
  const EnvSpec& spec = env.spec();
  EXPECT_EQ(spec.name, "Pursuit");
  ASSERT_EQ(spec.behaviors.size(), 2u);
  EXPECT_EQ(spec.behaviors[0].name, "Hider");
  EXPECT_EQ(spec.behaviors[0].agent_slots, 2);
  EXPECT_EQ(spec.behaviors[1].name, "Seeker");
  EXPECT_EQ(spec.behaviors[1].agent_slots, 3);
  for (const auto& b : spec.behaviors) {
    EXPECT_EQ(b.observations.at(0).shape, std::vector<int>({30}));
    EXPECT_EQ(b.action.discrete_branches, std::vector<int>({5}));
    EXPECT_EQ(b.action.continuous_size, 0);
  }
  for (const char* p : {"num_hiders", "num_seekers", "prep_fraction", "episode_length", "level",
                        "end_on_tag", "hide_reward", "seen_reward", "vision_range"})
    EXPECT_TRUE(spec.default_parameters.count(p)) << p;
  EXPECT_EQ(spec.default_parameters.at("prep_fraction"), 0.3f);
  EXPECT_GE(spec.max_episode_steps, 100);
}

TEST(PursuitTest, ConformsAtEveryLevelAndTeamSize) {
  register_builtin_envs();
  ConformanceOptions opts;
  opts.steps = 260;  // two default episodes and some
  for (float level : {1.f, 2.f, 3.f})
    for (float hiders : {1.f, 2.f})
      for (float seekers : {1.f, 2.f, 3.f}) {
        const Parameters p = {{"level", level}, {"num_hiders", hiders}, {"num_seekers", seekers}};
        SCOPED_TRACE("level " + std::to_string(level) + ", " + std::to_string(hiders) +
                     " hiders, " + std::to_string(seekers) + " seekers");
        const auto violations = check_env_conformance("Pursuit", p, opts);
        EXPECT_TRUE(violations.empty()) << joined(violations);
      }
  // the whole default-length rollout, no prep, episodes that go on after every tag
  for (const Parameters& p : {Parameters{}, Parameters{{"prep_fraction", 0.f}, {"end_on_tag", 0.f}},
                              Parameters{{"episode_length", 300.f}, {"num_hiders", 2.f}}}) {
    const auto violations = check_env_conformance("Pursuit", p);
    EXPECT_TRUE(violations.empty()) << joined(violations);
  }
}

TEST(PursuitTest, TeamSizesFillSlotsWithUniqueIds) {
  for (int nh = 1; nh <= 2; ++nh)
    for (int ns = 1; ns <= 3; ++ns) {
      Game g({{"num_hiders", float(nh)}, {"num_seekers", float(ns)}});
      std::set<int> ids;
      for (int s = 0; s < 2; ++s) {
        EXPECT_EQ(g.hiders.type(s), s < nh ? StepType::kFirst : StepType::kAbsent);
        if (s >= nh) continue;
        ids.insert(g.h.buffers(0).agent_id[s]);
        EXPECT_EQ(g.h.buffers(0).group_id[s], 0);
      }
      for (int s = 0; s < 3; ++s) {
        EXPECT_EQ(g.seekers.type(s), s < ns ? StepType::kFirst : StepType::kAbsent);
        if (s >= ns) continue;
        ids.insert(g.h.buffers(1).agent_id[s]);
        EXPECT_EQ(g.h.buffers(1).group_id[s], 1);
      }
      EXPECT_EQ(int(ids.size()), nh + ns);
    }
}

TEST(PursuitTest, SpawnsAreClearOfWallsAndSeekersAwayFromHiders) {
  Pursuit env;
  env.set_parameters({{"level", 3.f}, {"num_hiders", 2.f}, {"num_seekers", 3.f}});
  SingleEnvHarness h(env);
  for (uint64_t seed = 0; seed < 300; ++seed) {
    env.seed(seed);
    h.reset();
    for (int s = 0; s < 3; ++s) {
      const Pursuit::Body& sb = env.body(kSeeker, s);
      for (int k = 0; k < 2; ++k) {
        const Pursuit::Body& hb = env.body(kHider, k);
        EXPECT_GE(std::hypot(sb.x - hb.x, sb.y - hb.y), 3.0);
      }
    }
    for (int team : {0, 1})
      for (int s = 0; s < (team == 0 ? 2 : 3); ++s) {
        const Pursuit::Body& b = env.body(static_cast<Pursuit::Team>(team), s);
        for (const auto& w : env.walls()) {
          const double qx = std::clamp(b.x, w.cx - w.hx, w.cx + w.hx);
          const double qy = std::clamp(b.y, w.cy - w.hy, w.cy + w.hy);
          EXPECT_GE(std::hypot(b.x - qx, b.y - qy), Pursuit::kRadius);
        }
      }
  }
}

TEST(PursuitTest, ASeekerTouchingAHiderInTheTestPhaseTagsIt) {
  Game g({{"prep_fraction", 0.f}});
  g.env.set_body(kHider, 0, -3, -3);
  g.env.set_body(kSeeker, 0, -3.5, -3);  // 0.5 m apart: touching
  g.env.set_body(kSeeker, 1, 3, 3);
  g.step(kNone, kNone);
  EXPECT_EQ(g.hiders.type(0), StepType::kLast);
  EXPECT_EQ(g.hiders.terminated(0), 1);
  EXPECT_EQ(g.hiders.reward(0), -1.f);
  EXPECT_FALSE(g.env.body(kHider, 0).present);
  for (int s : {0, 1}) {
    // the episode ends with the last hider (end_on_tag = 1); +1 for the tag, nothing seen after
    EXPECT_EQ(g.seekers.type(s), StepType::kLast);
    EXPECT_EQ(g.seekers.terminated(s), 1);
    EXPECT_EQ(g.seekers.group_reward(s), 1.f);
    EXPECT_EQ(g.seekers.reward(s), 0.f);
  }
  const EpisodeMetrics m = g.env.episode_metrics();
  EXPECT_EQ(m.at("tag_rate"), 1.f);
  EXPECT_EQ(m.at("tagged"), 1.f);
  EXPECT_EQ(m.at("seen_fraction"), 1.f);
  g.step(kNone, kNone);
  EXPECT_EQ(g.hiders.type(0), StepType::kAbsent);
  EXPECT_EQ(g.seekers.type(0), StepType::kAbsent);
}

TEST(PursuitTest, WithoutEndOnTagSeekersPlayOn) {
  Game g({{"prep_fraction", 0.f}, {"end_on_tag", 0.f}, {"episode_length", 20.f}});
  g.env.set_body(kHider, 0, -3, -3);
  g.env.set_body(kSeeker, 0, -3.5, -3);
  g.step(kNone, kNone);
  EXPECT_EQ(g.hiders.type(0), StepType::kLast);
  EXPECT_EQ(g.seekers.type(0), StepType::kMid);
  for (int t = 2; t <= 20; ++t) {
    g.step(kNone, kNone);
    EXPECT_EQ(g.seekers.group_reward(0), 0.f);
  }
  EXPECT_EQ(g.seekers.type(0), StepType::kLast);
  EXPECT_EQ(g.seekers.terminated(0), 0);
  EXPECT_EQ(g.env.episode_metrics().at("seen_fraction"), 1.f);  // the one step with a hider
}

TEST(PursuitTest, SeekersAreFrozenAndCannotTagInThePrepPhase) {
  Game g;  // 100 decisions, 30 of prep
  EXPECT_EQ(g.env.prep_steps(), 30);
  g.env.set_body(kHider, 0, -3, -3);
  g.env.set_body(kSeeker, 0, -3.5, -3);
  const double x1 = g.env.body(kSeeker, 1).x, y1 = g.env.body(kSeeker, 1).y;
  for (int t = 1; t <= 30; ++t) {
    // the mask allows only "none"; a seeker that pushes anyway does not move
    for (int s : {0, 1}) {
      EXPECT_EQ(g.seekers.mask(s)[0], 1);
      for (int a = 1; a < 5; ++a) EXPECT_EQ(g.seekers.mask(s)[a], 0) << t;
      EXPECT_EQ(g.seekers.obs(s)[5], 1.f);
    }
    EXPECT_EQ(g.hiders.obs(0)[5], 1.f);
    for (int a = 0; a < 5; ++a) EXPECT_EQ(g.hiders.mask(0)[a], 1);
    g.step(kNone, kRight);
    EXPECT_EQ(g.hiders.type(0), StepType::kMid) << "no tag in the prep phase, step " << t;
    EXPECT_EQ(g.hiders.reward(0), 0.f);
    EXPECT_EQ(g.seekers.group_reward(0), 0.f);
    EXPECT_EQ(g.env.body(kSeeker, 0).x, -3.5);
    EXPECT_EQ(g.env.body(kSeeker, 1).x, x1);
    EXPECT_EQ(g.env.body(kSeeker, 1).y, y1);
  }
  // the test phase: masks open, and the next step tags
  EXPECT_EQ(g.seekers.obs(0)[5], 0.f);
  for (int a = 0; a < 5; ++a) EXPECT_EQ(g.seekers.mask(0)[a], 1);
  g.step(kNone, kNone);
  EXPECT_EQ(g.hiders.type(0), StepType::kLast);
  EXPECT_EQ(g.hiders.reward(0), -1.f);
}

TEST(PursuitTest, AWallBlocksSight) {
  Game g({{"prep_fraction", 0.f}, {"episode_length", 50.f}});  // level 1: wall x = 0, |y| <= 2.5
  g.env.set_body(kHider, 0, -2, 0);
  g.env.set_body(kSeeker, 0, 2, 0);
  g.env.set_body(kSeeker, 1, 2, 1);
  EXPECT_FALSE(g.env.line_of_sight(-2, 0, 2, 0));
  EXPECT_TRUE(g.env.line_of_sight(-2, 3, 2, 3));
  EXPECT_TRUE(g.env.line_of_sight(-2, -2, -4, 4));
  g.step(kNone, kNone);
  EXPECT_FALSE(g.env.sees(0, 0));
  EXPECT_FALSE(g.env.sees(1, 0));
  // hidden: the hider is rewarded, nobody sees anybody
  EXPECT_FLOAT_EQ(g.hiders.reward(0), 0.005f);
  EXPECT_EQ(g.seekers.group_reward(0), 0.f);
  for (int k = 6; k < 18; ++k) EXPECT_EQ(g.hiders.obs(0)[k], 0.f) << k;
  for (int k = 6; k < 14; ++k) EXPECT_EQ(g.seekers.obs(0)[k], 0.f) << k;

  // above the wall: seen, by both, and both sides know where the other is
  g.env.set_body(kHider, 0, -2, 4);
  g.env.set_body(kSeeker, 0, 2, 4);
  g.env.set_body(kSeeker, 1, 2, 3);
  g.step(kNone, kNone);
  EXPECT_TRUE(g.env.sees(0, 0));
  EXPECT_TRUE(g.env.sees(1, 0));
  EXPECT_EQ(g.hiders.reward(0), 0.f);
  EXPECT_FLOAT_EQ(g.seekers.group_reward(0), 0.005f);  // one hider seen
  EXPECT_FLOAT_EQ(g.seekers.group_reward(1), 0.005f);
  const double diagonal = 10 * std::sqrt(2.0);
  const float* ho = g.hiders.obs(0);  // seekers at [6, 18), teammate [18, 22), rays [22, 30)
  EXPECT_FLOAT_EQ(ho[6], 1.f);        // seeker 0: 4 m along +x
  EXPECT_FLOAT_EQ(ho[7], 0.f);
  EXPECT_FLOAT_EQ(ho[8], float(4 / diagonal));
  EXPECT_EQ(ho[9], 1.f);
  EXPECT_FLOAT_EQ(ho[10], float(4 / std::sqrt(17.0)));  // seeker 1 at (+4, -1) m
  EXPECT_FLOAT_EQ(ho[11], float(-1 / std::sqrt(17.0)));
  EXPECT_FLOAT_EQ(ho[12], float(std::sqrt(17.0) / diagonal));
  EXPECT_EQ(ho[13], 1.f);
  for (int k = 14; k < 22; ++k) EXPECT_EQ(ho[k], 0.f) << k;  // seeker slot 2, hider slot 1 unused
  const float* so = g.seekers.obs(0);  // hiders at [6, 14), teammates [14, 22), rays [22, 30)
  EXPECT_FLOAT_EQ(so[6], -1.f);
  EXPECT_FLOAT_EQ(so[7], 0.f);
  EXPECT_EQ(so[9], 1.f);
  for (int k = 10; k < 14; ++k) EXPECT_EQ(so[k], 0.f) << k;  // hider slot 1 unused
  EXPECT_FLOAT_EQ(so[14], 0.f);                              // teammate seeker 1, 1 m along -y
  EXPECT_FLOAT_EQ(so[15], -1.f);
  EXPECT_FLOAT_EQ(so[16], float(1 / diagonal));
  EXPECT_EQ(so[17], 1.f);
  for (int k = 18; k < 22; ++k) EXPECT_EQ(so[k], 0.f) << k;  // seeker slot 2 unused

  // out of range: a short vision range hides the hider again
  Game far({{"prep_fraction", 0.f}, {"vision_range", 3.f}});
  far.env.set_body(kHider, 0, -2, 4);
  far.env.set_body(kSeeker, 0, 2, 4);
  far.env.set_body(kSeeker, 1, 2, 3);
  far.step(kNone, kNone);
  EXPECT_FALSE(far.env.sees(0, 0));
  EXPECT_FLOAT_EQ(far.hiders.reward(0), 0.005f);
}

TEST(PursuitTest, WallsAndBorderStopAgents) {
  for (int level : {1, 2, 3}) {
    Game g({{"level", float(level)}, {"episode_length", 300.f}});
    g.env.set_body(kHider, 0, -2, 1);
    g.env.set_body(kSeeker, 0, 4, -4);
    g.env.set_body(kSeeker, 1, 4, -3);
    // push right into the wall x = 0 for a while, then up into the border
    for (int t = 0; t < 60; ++t) {
      g.step(kRight, kNone);
      EXPECT_LE(g.env.body(kHider, 0).x, -Pursuit::kRadius - Pursuit::kWallHalfThickness + 1e-9);
    }
    EXPECT_NEAR(g.env.body(kHider, 0).x, -0.4, 1e-9);
    EXPECT_NEAR(g.env.body(kHider, 0).vx, 0.0, 1e-9);
    for (int t = 0; t < 60; ++t) g.step(kUp, kNone);
    EXPECT_NEAR(g.env.body(kHider, 0).y, 4.7, 1e-9);
    // speed cap
    for (int t = 0; t < 30; ++t) {
      g.step(kDown, kNone);
      EXPECT_LE(std::hypot(g.env.body(kHider, 0).vx, g.env.body(kHider, 0).vy), 3.0 + 1e-9);
    }
  }
}

TEST(PursuitTest, RaysMeasureWallDistances) {
  Game g;  // level 1
  g.env.set_body(kHider, 0, -2, 1, 1.5, 0);
  g.step(kNone, kNone);  // one step moves the hider: read the position it reached
  const Pursuit::Body& b = g.env.body(kHider, 0);
  const float* o = g.hiders.obs(0);
  const float* rays = o + 22;
  EXPECT_NEAR(rays[0], (-0.1 - b.x) / 5.0, 1e-6);            // +x: the wall's face at x = -0.1
  EXPECT_NEAR(rays[2], std::min(1.0, (5 - b.y) / 5), 1e-6);  // +y: the border
  EXPECT_NEAR(rays[4], std::min(1.0, (5 + b.x) / 5), 1e-6);  // -x: the border
  EXPECT_NEAR(rays[6], std::min(1.0, (5 + b.y) / 5), 1e-6);  // -y: the border, 6 m away
  EXPECT_NEAR(o[0], b.x / 5, 1e-6);
  EXPECT_NEAR(o[2], b.vx / 3, 1e-6);
  EXPECT_NEAR(g.env.ray_distance(0, 4, 0, -1, 5), 4 - 2.5, 1e-12);  // down onto the wall's top
  EXPECT_NEAR(g.env.ray_distance(-3, 0, 1, 0, 5), 2.9, 1e-12);
  EXPECT_EQ(g.env.ray_distance(-3, 0, 1, 0, 2), 2.0);
}

TEST(PursuitTest, TruncatedAtTheEpisodeLength) {
  Game g({{"episode_length", 40.f}});
  EXPECT_EQ(g.env.prep_steps(), 12);
  g.env.set_body(kHider, 0, -4, 4);
  g.env.set_body(kSeeker, 0, 4, 4);
  g.env.set_body(kSeeker, 1, 4, 3.5);
  for (int t = 1; t <= 40; ++t) {
    g.step(kNone, kNone);
    ASSERT_EQ(g.hiders.type(0), t < 40 ? StepType::kMid : StepType::kLast);
    EXPECT_EQ(g.seekers.type(1), t < 40 ? StepType::kMid : StepType::kLast);
    EXPECT_FLOAT_EQ(g.hiders.obs(0)[4], t / 40.f);
  }
  EXPECT_EQ(g.hiders.terminated(0), 0);
  EXPECT_EQ(g.seekers.terminated(0), 0);
  const EpisodeMetrics m = g.env.episode_metrics();
  EXPECT_EQ(m.at("tag_rate"), 0.f);
  EXPECT_EQ(m.at("seen_fraction"), 1.f);  // above the wall: seen in all 28 test decisions
}

TEST(PursuitTest, RejectsAnOutOfRangeAction) {
  Game g;
  g.hiders.act(0, 7);
  EXPECT_THROW(g.h.step(), std::invalid_argument);
}

// The measured numbers of the header comment.
TEST(PursuitTest, GreedySeekersTagAndRandomOnesRarelyDo) {
  const Rates still = play({}, 2000, /*greedy_seekers=*/true, /*random_hider=*/false, 3);
  const Rates moving = play({}, 2000, true, true, 4);
  const Rates random = play({}, 2000, false, true, 5);
  const Rates level3 = play({{"level", 3.f}}, 2000, true, false, 6);
  std::printf(
      "greedy vs still: tag %.4f seen %.3f after %.1f; greedy vs random: tag %.4f seen %.3f; "
      "random vs random: tag %.4f seen %.3f; level 3 greedy vs still: tag %.4f seen %.3f\n",
      still.tag_rate, still.seen_fraction, still.decisions_to_tag, moving.tag_rate,
      moving.seen_fraction, random.tag_rate, random.seen_fraction, level3.tag_rate,
      level3.seen_fraction);
  EXPECT_GE(still.tag_rate, 0.9);
  EXPECT_GE(moving.tag_rate, 0.9);
  EXPECT_LE(random.tag_rate, 0.3);
  EXPECT_LT(random.tag_rate, still.tag_rate - 0.5);
}

}  // namespace
}  // namespace rlt
