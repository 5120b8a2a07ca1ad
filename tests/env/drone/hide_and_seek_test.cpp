// HideAndSeek: conformance at every level, the prep phase freezes seekers, tags, masks, closing an
// opening, the reward presets, and the scripted policies (SPEC.md section 6, issue 4).
#include "env/drone/hide_and_seek.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

#include "env/drone/drone_task.h"
#include "env/register_builtin_envs.h"
#include "rl/env_api/conformance.h"
#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

using Team = HideAndSeek::Team;

// a harness with both behaviors and helpers to drive one HideAndSeek
struct Game {
  explicit Game(const Parameters& p, uint64_t seed = 1) {
    env.set_parameters(p);
    env.seed(seed);
    harness.reset();
  }
  BehaviorBuffers& hiders() { return harness.buffers(HideAndSeek::kHider); }
  BehaviorBuffers& seekers() { return harness.buffers(HideAndSeek::kSeeker); }
  // every agent's thrust (4 floats) and discrete choices
  void set_all(float forward, int grab = 0, int lock = 0) {
    for (auto* b : {&hiders(), &seekers()}) {
      for (int r = 0; r < b->rows; ++r) {
        for (int k = 0; k < 4; ++k) b->continuous_actions[r * 4 + k] = 0.0f;
        b->continuous_actions[r * 4] = forward;
        b->discrete_actions[r * 2] = grab;
        b->discrete_actions[r * 2 + 1] = lock;
      }
    }
  }
  // one decision with every action 0 but `lock` on the lock branch; returns the first hider's
  // reward
  float lock_step(int lock) {
    set_all(0.0f, 0, lock);
    harness.step();
    return hiders().reward[0];
  }
  float idle_step() { return lock_step(0); }
  // scripted actions for one team
  void script(Team team) {
    StepView views;
    views.emplace_back(&hiders(), 0);
    views.emplace_back(&seekers(), 0);
    ASSERT_TRUE(env.write_scripted_actions(team, views[team]));
  }
  bool over() {
    for (auto* b : {&hiders(), &seekers()})
      for (int r = 0; r < b->rows; ++r)
        if (needs_action(b->step_type[r])) return false;
    return true;
  }
  HideAndSeek env;
  SingleEnvHarness harness{env};
};

// puts `hider` where a lock acts on `prop`: 1 m inside it from the opening with outward normal
// `n`, facing out, at rest
void stand_behind(drone::DroneBody& hider, const drone::Prop& prop, const btVector3& n) {
  drone::DroneTask::place(hider, prop.position() - n * 1.0f + btVector3(0, 0.2f, 0),
                          std::atan2(n.x(), n.z()));
}

TEST(HideAndSeekTest, ConformsAtEveryLevel) {
  register_builtin_envs();
  for (int level = 1; level <= 4; ++level) {
    ConformanceOptions opts;
    opts.steps = 260;  // two short episodes and a bit
    const Parameters p = {{"level", float(level)}, {"episode_frames", 360.f},
                          {"num_hiders", level == 1 ? 1.f : 2.f},
                          {"num_seekers", float(level)}, {"end_on_tag", level % 2 ? 1.f : 0.f}};
    const auto violations = check_env_conformance("HideAndSeek", p, opts);
    EXPECT_TRUE(violations.empty()) << "level " << level << ": " << violations.front();
  }
  // the baker preset too
  ConformanceOptions opts;
  opts.steps = 130;
  const auto violations = check_env_conformance(
      "HideAndSeek", {{"level", 2.f}, {"reward_preset", 1.f}, {"episode_frames", 300.f}}, opts);
  EXPECT_TRUE(violations.empty()) << violations.front();
}

TEST(HideAndSeekTest, BadParametersAreNamed) {
  for (const auto& [name, value] :
       std::vector<std::pair<std::string, float>>{{"level", 5.f},
                                                  {"num_seekers", 0.f},
                                                  {"num_hiders", 2.5f},
                                                  {"prep_fraction", -1.f},
                                                  {"hider_outside_chance", 1.5f},
                                                  {"hider_outside_chance", -0.5f},
                                                  {"prop_start_offset", 1.1f},
                                                  {"close_reward_mode", 3.f},
                                                  {"close_credit", 2.f},
                                                  {"prop_shaping", 1.5f},
                                                  {"reach_shaping", -0.1f},
                                                  {"reach_shaping", 0.6f},  // + 0.5 > 1
                                                  {"shaping_range", 0.f},
                                                  {"prop_cues", 2.f},
                                                  {"object_obs", -1.f},
                                                  {"prop_start_spread", 1.5f},
                                                  {"prop_start_far_chance", -0.1f},
                                                  {"prop_start_far_offset", 1.2f},
                                                  {"prop_pairing", 0.5f},
                                                  {"cover_depth", 0.4f},
                                                  {"unlock_cost", -0.1f},
                                                  {"cover_shaping", 0.6f},  // + 0.5 > 1
                                                  {"push_shaping", -0.2f},
                                                  {"push_shaping", 0.6f},  // + 0.5 > 1
                                                  {"doorway_swap_chance", 1.5f},
                                                  {"doorway_swap_chance", -0.1f},
                                                  {"clock_frames", -1.f},
                                                  {"clock_frames", 7000.f},
                                                  {"fort_reward", NAN}}) {
    HideAndSeek env;
    env.set_parameters({{name, value}});
    SingleEnvHarness harness(env);
    try {
      harness.reset();
      FAIL() << name << " = " << value << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

// where hiders start: inside the room, or just outside it with chance hider_outside_chance (-1: the
// level's own, 0 at levels 1-2 and 0.5 at 3-4)
TEST(HideAndSeekTest, HiderOutsideChancePlacesHiders) {
  const auto count_outside = [](float level, float chance) {
    int outside = 0;
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      Game g({{"level", level}, {"hider_outside_chance", chance}}, seed);
      const drone::ArenaParams& ap = g.env.arena().params();
      for (int h = 0; h < 2; ++h) {
        const btVector3 p = g.env.agent(HideAndSeek::kHider, h).drone->position();
        const float box = std::max(std::abs(p.x()), std::abs(p.z()));
        const bool in_room = box < ap.room_half;
        if (!in_room) {
          ++outside;
          EXPECT_LT(box, ap.room_half + 0.5f * ap.wall_thickness + 2.5f + 0.5f + 1e-4f)
              << "a hider outside starts in the band 2.5 m (plus its 0.5 m footprint) around the "
                 "room";
        }
      }
    }
    return outside;  // of 40 hiders
  };
  EXPECT_EQ(count_outside(1, -1), 0);
  EXPECT_EQ(count_outside(2, -1), 0);
  EXPECT_EQ(count_outside(1, 1), 40);
  EXPECT_EQ(count_outside(4, 0), 0);
  const int half = count_outside(2, 0.5f);
  EXPECT_GT(half, 10);
  EXPECT_LT(half, 30);
  const int level_own = count_outside(3, -1);
  EXPECT_GT(level_own, 10);
  EXPECT_LT(level_own, 30);
}

// prop_start_offset 0: the props of levels 1 and 2 stand in their doorways, and locking them closes
// the doorways; 1 (the default) leaves them at their own places; 0.5 half way
TEST(HideAndSeekTest, PropStartOffsetMovesPropsTowardsTheirDoorways) {
  for (float level : {1.f, 2.f}) {
    Game own({{"level", level}}, 3);
    Game half({{"level", level}, {"prop_start_offset", 0.5f}}, 3);
    Game in({{"level", level}, {"prop_start_offset", 0.f}}, 3);
    for (int i = 0; i < int(level); ++i) {
      const drone::Opening& door = in.env.arena().openings()[i];
      const btVector3 p = in.env.props()[i].position();
      EXPECT_NEAR(std::hypot(p.x() - door.centre.x(), p.z() - door.centre.z()), 0.35f, 0.02f);
      EXPECT_GT(drone::covered_fraction(door, *in.env.props()[i].body), 0.5f);  // covers it
      EXPECT_FALSE(in.env.props()[i].locked());
      const btVector3 far = own.env.props()[i].position();
      EXPECT_GT(std::hypot(far.x() - door.centre.x(), far.z() - door.centre.z()), 1.5f);
      const btVector3 mid = half.env.props()[i].position();
      const btVector3 expect = 0.5f * (p + far);
      EXPECT_NEAR(mid.x(), expect.x(), 0.02f);
      EXPECT_NEAR(mid.z(), expect.z(), 0.02f);
    }
    // a hider in front of each prop locks it where it stands: the doorways close
    auto& hider = *in.env.agent(HideAndSeek::kHider, 0).drone;
    for (int i = 0; i < int(level); ++i) {
      stand_behind(hider, in.env.props()[i], in.env.arena().openings()[i].normal);
      ASSERT_EQ(in.env.props().lock(hider, HideAndSeek::kHider), i) << "level " << level;
    }
    EXPECT_EQ(in.env.count_closed(), int(level)) << "level " << level;
    EXPECT_FLOAT_EQ(in.env.episode_metrics().at("prop_start_offset"), 0.0f);
    EXPECT_FLOAT_EQ(own.env.episode_metrics().at("prop_start_offset"), 1.0f);
  }
  // level 2: the yaw turns with the offset, from parallel to the wall (0) to the prop's own yaw
  {
    Game own({{"level", 2.f}}, 3), half({{"level", 2.f}, {"prop_start_offset", 0.5f}}, 3);
    const auto yaw_of = [](const drone::Prop& p) {  // about +y: x axis = (cos, 0, -sin)
      const btVector3 x = p.body->getWorldTransform().getBasis().getColumn(0);
      return static_cast<float>(std::atan2(-x.z(), x.x()));
    };
    float own_yaw = yaw_of(own.env.props()[0]);
    own_yaw -= 3.14159265f * std::round(own_yaw / 3.14159265f);
    EXPECT_NEAR(yaw_of(half.env.props()[0]), 0.5f * own_yaw, 1e-3f);
  }
  // levels 3 and 4 ignore the parameter and say so in the metric
  {
    Game g({{"level", 3.f}, {"prop_start_offset", 0.f}}, 3);
    EXPECT_FLOAT_EQ(g.env.episode_metrics().at("prop_start_offset"), 1.0f);
  }
}

// doorway_swap_chance: with chance 1 level 1's doorway is the one in the +z wall, its prop starts
// beside it and locking the prop there closes it; with 0.5 about half the episodes swap; 0 (the
// default) draws nothing, so the episodes are those of a run without the parameter
TEST(HideAndSeekTest, DoorwaySwapChancePutsLevelOnesDoorwayInEitherWall) {
  Game in({{"level", 1.f}, {"doorway_swap_chance", 1.f}, {"prop_start_offset", 0.f}}, 3);
  const drone::Opening& door = in.env.arena().openings()[0];
  EXPECT_TRUE(door.open);
  EXPECT_GT(door.centre.z(), 0.0f);
  EXPECT_GT(drone::covered_fraction(door, *in.env.props()[0].body), 0.5f);
  auto& hider = *in.env.agent(HideAndSeek::kHider, 0).drone;
  stand_behind(hider, in.env.props()[0], door.normal);
  ASSERT_EQ(in.env.props().lock(hider, HideAndSeek::kHider), 0);
  EXPECT_EQ(in.env.count_closed(), 1);

  Game half({{"level", 1.f}, {"doorway_swap_chance", 0.5f}}, 5);
  int swapped = 0;
  for (int episode = 0; episode < 100; ++episode) {
    half.harness.reset();
    const bool plus_z = half.env.arena().openings()[0].centre.z() > 0.0f;
    swapped += plus_z;
    // the prop starts beside the open doorway, on its side of the room
    ASSERT_EQ(half.env.props()[0].position().z() > 0.0f, plus_z) << "episode " << episode;
  }
  EXPECT_GT(swapped, 30);  // binomial(100, 0.5): 50 +- 5
  EXPECT_LT(swapped, 70);

  Game plain({{"level", 1.f}}, 7), zero({{"level", 1.f}, {"doorway_swap_chance", 0.f}}, 7);
  for (int episode = 0; episode < 5; ++episode) {
    plain.harness.reset();
    zero.harness.reset();
    EXPECT_LT(zero.env.arena().openings()[0].centre.z(), 0.0f);
    for (int h = 0; h < 2; ++h)
      ASSERT_EQ(zero.env.agent(HideAndSeek::kHider, h).drone->position(),
                plain.env.agent(HideAndSeek::kHider, h).drone->position());
  }
}

// prop_start_spread: that share of the episodes starts its props at an offset drawn from
// [0, prop_start_offset], the others at prop_start_offset; the metric says which
TEST(HideAndSeekTest, PropStartSpreadMixesEasierStartsIn) {
  Game g({{"level", 2.f}, {"prop_start_offset", 0.8f}, {"prop_start_spread", 0.5f}}, 5);
  int at_offset = 0, below = 0;
  std::vector<float> drawn;
  for (int episode = 0; episode < 200; ++episode) {
    g.harness.reset();
    const float t = g.env.episode_metrics().at("prop_start_offset");
    ASSERT_GE(t, 0.0f);
    ASSERT_LE(t, 0.8f);
    if (t == 0.8f) {
      ++at_offset;
    } else {
      ++below;
      drawn.push_back(t);
    }
  }
  EXPECT_GT(at_offset, 70);  // binomial(200, 0.5): 100 +- 7
  EXPECT_GT(below, 70);
  const float mean = std::accumulate(drawn.begin(), drawn.end(), 0.0f) / drawn.size();
  EXPECT_NEAR(mean, 0.4f, 0.06f);  // uniform on [0, 0.8]
  // without a spread every episode starts at the offset, and the same seed gives the same starts
  Game plain({{"level", 2.f}, {"prop_start_offset", 0.8f}}, 5);
  for (int episode = 0; episode < 20; ++episode) {
    plain.harness.reset();
    ASSERT_EQ(plain.env.episode_metrics().at("prop_start_offset"), 0.8f);
  }
  Game again({{"level", 2.f}, {"prop_start_offset", 0.8f}, {"prop_start_spread", 0.5f}}, 5);
  Game once_more({{"level", 2.f}, {"prop_start_offset", 0.8f}, {"prop_start_spread", 0.5f}}, 5);
  for (int episode = 0; episode < 10; ++episode) {
    again.harness.reset();
    once_more.harness.reset();
    ASSERT_EQ(again.env.props()[1].position(), once_more.env.props()[1].position());
  }
}

// prop_start_far_chance: that share of the episodes starts its props at an offset drawn from
// [prop_start_offset, prop_start_far_offset], the others at prop_start_offset
TEST(HideAndSeekTest, PropStartFarChanceMixesLongerPushesIn) {
  Game g({{"level", 1.f},
          {"prop_start_offset", 0.1f},
          {"prop_start_far_chance", 0.3f},
          {"prop_start_far_offset", 0.5f}},
         5);
  int at_offset = 0;
  std::vector<float> drawn;
  for (int episode = 0; episode < 300; ++episode) {
    g.harness.reset();
    const float t = g.env.episode_metrics().at("prop_start_offset");
    ASSERT_GE(t, 0.1f);
    ASSERT_LE(t, 0.5f);
    if (t == 0.1f)
      ++at_offset;
    else
      drawn.push_back(t);
  }
  EXPECT_NEAR(at_offset, 210, 30);  // binomial(300, 0.7): 210 +- 8
  const float mean = std::accumulate(drawn.begin(), drawn.end(), 0.0f) / drawn.size();
  EXPECT_NEAR(mean, 0.3f, 0.04f);  // uniform on [0.1, 0.5]
  // the far props really start farther from the doorway
  Game near({{"level", 1.f}, {"prop_start_offset", 0.1f}}, 5);
  Game far({{"level", 1.f}, {"prop_start_offset", 0.1f}, {"prop_start_far_chance", 1.f},
            {"prop_start_far_offset", 0.5f}},
           5);
  const btVector3 door = near.env.arena().openings()[0].centre;
  const auto distance = [&](Game& game) {
    const btVector3 d = game.env.props()[0].position() - door;
    return std::hypot(d.x(), d.z());
  };
  float near_sum = 0.0f, far_sum = 0.0f;
  for (int episode = 0; episode < 20; ++episode) {
    near.harness.reset();
    far.harness.reset();
    ASSERT_EQ(near.env.episode_metrics().at("prop_start_offset"), 0.1f);
    near_sum += distance(near);
    far_sum += distance(far);
  }
  EXPECT_GT(far_sum, near_sum + 20 * 0.2f);  // measured: 0.29 m farther on average
  // a far offset below the lesson's offset leaves every episode at the offset
  Game below({{"level", 1.f}, {"prop_start_offset", 0.3f}, {"prop_start_far_chance", 1.f},
              {"prop_start_far_offset", 0.1f}},
             5);
  for (int episode = 0; episode < 10; ++episode) {
    below.harness.reset();
    ASSERT_EQ(below.env.episode_metrics().at("prop_start_offset"), 0.3f);
  }
}

// prop_pairing 1 (level 2): the two own places go to the props so that the ways from doorway i to
// prop i are least in total, so a hider's own prop (its objects observation's first) is never
// the one across the room; 0 gives prop i the i-th place drawn, crossed about half the time
TEST(HideAndSeekTest, PropPairingGivesEachDoorwayTheNearerPlace) {
  const auto way = [](Game& g, int prop, int door) {
    const btVector3 p = g.env.props()[prop].position();
    const btVector3 c = g.env.arena().openings()[door].centre;
    return std::hypot(p.x() - c.x(), p.z() - c.z());
  };
  const auto crossed = [&](Game& g) {
    return way(g, 1, 0) + way(g, 0, 1) < way(g, 0, 0) + way(g, 1, 1);
  };
  Game plain({{"level", 2.f}}, 7), paired({{"level", 2.f}, {"prop_pairing", 1.f}}, 7);
  int crossed_plain = 0;
  for (int episode = 0; episode < 100; ++episode) {
    plain.harness.reset();
    paired.harness.reset();
    crossed_plain += crossed(plain);
    ASSERT_FALSE(crossed(paired)) << "episode " << episode;
    for (int i = 0; i < 2; ++i) {  // the same kind of place: at least 2.5 m from every opening
      ASSERT_GE(way(paired, i, 0), 2.5f);
      ASSERT_GE(way(paired, i, 1), 2.5f);
    }
    ASSERT_GT((paired.env.props()[0].position() - paired.env.props()[1].position()).length(),
              1.7f);
  }
  EXPECT_GT(crossed_plain, 30);  // binomial(100, 0.5)
  // the offset still moves each prop from its own doorway: at 0 both stand in theirs
  Game in({{"level", 2.f}, {"prop_pairing", 1.f}, {"prop_start_offset", 0.f}}, 7);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(way(in, i, i), 0.35f, 0.02f);
    EXPECT_GT(drone::covered_fraction(in.env.arena().openings()[i], *in.env.props()[i].body),
              0.5f);
  }
  // level 1 has one prop and one doorway: nothing to pair, the same episodes
  Game one({{"level", 1.f}}, 7), one_paired({{"level", 1.f}, {"prop_pairing", 1.f}}, 7);
  EXPECT_EQ(one.env.props()[0].position(), one_paired.env.props()[0].position());
}

TEST(HideAndSeekTest, SeekersDoNotMoveInThePrepPhase) {
  Game g({{"level", 4.f}, {"num_seekers", 4.f}, {"episode_frames", 600.f}});
  std::vector<btVector3> start;
  for (int s = 0; s < 4; ++s) start.push_back(g.env.agent(HideAndSeek::kSeeker, s).drone->position());
  // full thrust for everyone; hiders fly into whatever is ahead
  g.set_all(1.0f);
  while (g.env.in_prep()) {
    g.harness.step();
    for (int s = 0; s < 4; ++s)
      ASSERT_LT((g.env.agent(HideAndSeek::kSeeker, s).drone->position() - start[s]).length(), 1e-6f)
          << "seeker " << s << " moved at frame " << g.env.frame();
  }
  EXPECT_FLOAT_EQ(g.harness.buffers(0).observations[0][13], 0.0f);  // prep flag off now
  for (int i = 0; i < 5; ++i) g.harness.step();
  float moved = 0;
  for (int s = 0; s < 4; ++s)
    moved += (g.env.agent(HideAndSeek::kSeeker, s).drone->position() - start[s]).length();
  EXPECT_GT(moved, 0.5f);  // and they fly once it is over
}

// the clock observation (vector [12]) runs over the episode, or over clock_frames when that is
// set: a shortened episode with clock_frames at the full length reads like a full one's start
TEST(HideAndSeekTest, ClockFramesSetsTheClockObservationsScale) {
  Game own({{"level", 1.f}, {"episode_frames", 600.f}, {"decision_period", 6.f}});
  Game fixed({{"level", 1.f}, {"episode_frames", 600.f}, {"decision_period", 6.f},
              {"clock_frames", 3000.f}});
  for (Game* g : {&own, &fixed}) {
    g->set_all(0.0f);
    for (int i = 0; i < 50; ++i) g->harness.step();  // 300 frames
    ASSERT_EQ(g->env.frame(), 300);
  }
  EXPECT_FLOAT_EQ(own.hiders().observations[0][12], 0.5f);
  EXPECT_FLOAT_EQ(fixed.hiders().observations[0][12], 0.1f);
  // clipped at 1 once an episode is longer than the clock
  Game short_clock({{"level", 1.f}, {"episode_frames", 600.f}, {"decision_period", 6.f},
                    {"clock_frames", 120.f}});
  short_clock.set_all(0.0f);
  for (int i = 0; i < 30; ++i) short_clock.harness.step();
  EXPECT_FLOAT_EQ(short_clock.hiders().observations[0][12], 1.0f);
}

// the strategy of that name the env declares, or nullptr
const StrategySpec* declared_strategy(const HideAndSeek& env, const std::string& name) {
  const auto& strategies = env.spec().strategies;
  const auto it = std::find_if(strategies.begin(), strategies.end(),
                               [&](const StrategySpec& s) { return s.name == name; });
  return it != strategies.end() ? &*it : nullptr;
}

// shelter is dated at level 2 and above, with the props at their own places, in full games with
// shared props only: a lesson that shortens the test phase at the own places, or keeps each hider
// to its own prop, does not count
TEST(HideAndSeekTest, ShelterCountsFullGamesAtTheOwnPlacesFromLevelTwo) {
  HideAndSeek env;
  const StrategySpec* shelter = declared_strategy(env, "shelter");
  ASSERT_NE(shelter, nullptr);
  EXPECT_EQ(shelter->describe_conditions(),
            "level >= 2 and prop_start_offset >= 1 and episode_frames >= 3072 and "
            "shared_props >= 1");
}

// chasing is dated in full games only: a short test phase (a lesson's or a turn's) gives the
// seekers less time to tag, and its episodes would pull the tag rate down
TEST(HideAndSeekTest, ChasingCountsFullGamesOnly) {
  HideAndSeek env;
  const StrategySpec* chasing = declared_strategy(env, "running_and_chasing");
  ASSERT_NE(chasing, nullptr);
  EXPECT_EQ(chasing->metric, "tag_rate");
  EXPECT_EQ(chasing->behavior, "Seeker");
  EXPECT_EQ(chasing->describe_conditions(), "episode_frames >= 3072");
}

TEST(HideAndSeekTest, SeekersCannotGrabOrLock) {
  Game g({{"level", 1.f}});
  const uint8_t* seeker_mask = g.seekers().action_mask.data();
  EXPECT_EQ(std::vector<int>(seeker_mask, seeker_mask + 5), std::vector<int>({1, 0, 1, 0, 0}));
  // a seeker put next to the prop that asks to grab and lock anyway changes nothing
  auto& seeker = *g.env.agent(HideAndSeek::kSeeker, 0).drone;
  const btVector3 prop = g.env.props()[0].position();
  btTransform pose = seeker.body().getWorldTransform();
  pose.setOrigin(prop + btVector3(0, 0, 1.0f));
  pose.setRotation(btQuaternion(btVector3(0, 1, 0), 3.14159265f));  // facing -z, the prop
  seeker.body().setWorldTransform(pose);
  g.set_all(0.0f, 1, 1);
  g.harness.step();
  EXPECT_FALSE(g.env.props()[0].locked());
  EXPECT_EQ(g.env.props()[0].held_by, nullptr);
}

TEST(HideAndSeekTest, TagEndsTheEpisodeWithRewards) {
  Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 2.f}, {"episode_frames", 300.f}});
  g.set_all(0.0f);
  while (g.env.in_prep()) g.harness.step();
  // put seeker 0 right next to the hider
  auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
  auto& seeker = *g.env.agent(HideAndSeek::kSeeker, 0).drone;
  btTransform pose = seeker.body().getWorldTransform();
  pose.setOrigin(hider.position() + btVector3(0.75f, 0, 0));
  seeker.body().setWorldTransform(pose);
  g.harness.step();
  EXPECT_EQ(g.hiders().step_type[0], StepType::kLast);
  EXPECT_EQ(g.hiders().terminated[0], 1);
  EXPECT_LE(g.hiders().reward[0], -1.0f + 0.01f);
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(g.seekers().step_type[s], StepType::kLast);
    EXPECT_EQ(g.seekers().terminated[s], 1);
    EXPECT_FLOAT_EQ(g.seekers().group_reward[s], 1.0f);
  }
  const auto m = g.env.episode_metrics();
  EXPECT_EQ(m.at("tag_rate"), 1.0f);
  EXPECT_EQ(m.at("tagged"), 1.0f);
}

TEST(HideAndSeekTest, NoTagInThePrepPhase) {
  Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}});
  auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
  auto& seeker = *g.env.agent(HideAndSeek::kSeeker, 0).drone;
  btTransform pose = hider.body().getWorldTransform();
  pose.setOrigin(seeker.position() + btVector3(0.75f, 0, 0));
  hider.body().setWorldTransform(pose);
  g.set_all(0.0f);
  g.harness.step();
  EXPECT_EQ(g.hiders().step_type[0], StepType::kMid);
  EXPECT_EQ(g.hiders().reward[0], 0.0f);  // nothing is paid in the prep phase
}

TEST(HideAndSeekTest, HidingPaysPerTestPhaseFrame) {
  // level 1, one hider in the room, one seeker outside facing away: the hider is hidden
  Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}, {"prep_fraction", 0.f}});
  g.set_all(0.0f);
  bool seen = g.env.hider_seen(0);
  g.harness.step();
  if (!seen && !g.env.hider_seen(0)) {
    EXPECT_NEAR(g.hiders().reward[0], 3 * 0.001f, 1e-6f);
    EXPECT_EQ(g.seekers().reward[0], 0.0f);
  }
  // now put the seeker in the room facing the hider: 3 frames seen
  auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
  auto& seeker = *g.env.agent(HideAndSeek::kSeeker, 0).drone;
  btTransform pose = seeker.body().getWorldTransform();
  const btVector3 at = hider.position() + btVector3(0, 0, hider.position().z() > 0 ? -2.0f : 2.0f);
  pose.setOrigin(at);
  const btVector3 to = hider.position() - at;
  pose.setRotation(btQuaternion(btVector3(0, 1, 0), std::atan2(to.x(), to.z())));
  seeker.body().setWorldTransform(pose);
  g.harness.step();
  EXPECT_NEAR(g.seekers().reward[0], 3 * 0.001f, 1e-6f);
  EXPECT_EQ(g.hiders().reward[0], 0.0f);
}

// moves the prop flat over doorway 0 and the first hider in front of it, facing it
void place_prop_in_doorway_and_hider_before_it(Game& g) {
  const drone::Opening& door = g.env.arena().openings()[0];
  auto& props = g.env.props();
  btTransform prop_pose = props[0].body->getWorldTransform();
  btVector3 centre = door.centre - door.normal * 0.25f;
  centre.setY(props[0].half.y() + 0.02f);
  prop_pose.setOrigin(centre);
  prop_pose.setRotation(btQuaternion::getIdentity());
  props[0].body->setWorldTransform(prop_pose);
  auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
  btTransform pose = hider.body().getWorldTransform();
  pose.setOrigin(centre - door.normal * 1.2f + btVector3(0, 0, 0));
  pose.setRotation(btQuaternion(btVector3(0, 1, 0), std::atan2(door.normal.x(), door.normal.z())));
  hider.body().setWorldTransform(pose);
}

TEST(HideAndSeekTest, LockedPropClosesTheDoorwayOnce) {
  Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}});
  EXPECT_EQ(g.env.count_closed(), 0);
  place_prop_in_doorway_and_hider_before_it(g);
  auto& props = g.env.props();
  g.set_all(0.0f, 0, 1);
  g.harness.step();
  ASSERT_TRUE(props[0].locked());
  EXPECT_TRUE(g.env.opening_closed(0));
  EXPECT_NEAR(g.hiders().reward[0], 0.1f, 1e-6f);
  g.set_all(0.0f);
  g.harness.step();
  EXPECT_EQ(g.hiders().reward[0], 0.0f);  // paid once
  // unlocked and locked again: nothing taken back, nothing paid again
  g.set_all(0.0f, 0, 2);
  g.harness.step();
  ASSERT_FALSE(props[0].locked());
  EXPECT_EQ(g.hiders().reward[0], 0.0f);
  g.set_all(0.0f, 0, 1);
  g.harness.step();
  ASSERT_TRUE(g.env.opening_closed(0));
  EXPECT_EQ(g.hiders().reward[0], 0.0f);
  while (g.env.in_prep()) g.harness.step();
  const auto m = g.env.episode_metrics();
  EXPECT_EQ(m.at("fort_rate"), 1.0f);
  EXPECT_EQ(m.at("openings_closed"), 1.0f);
}

// the hiders' masks and vector [18, 20) say what grab, lock and unlock would act on
TEST(HideAndSeekTest, MasksAndObservationSayWhatAPropActionWouldDo) {
  Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}});
  const auto mask = [&] {
    const uint8_t* m = g.hiders().action_mask.data();
    return std::vector<int>(m, m + 5);
  };
  const auto flags = [&] {
    const float* v = g.hiders().observations[0].data();
    return std::vector<float>{v[18], v[19]};
  };
  auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
  // far from the prop: only release and none
  btTransform pose = hider.body().getWorldTransform();
  const drone::Opening& door = g.env.arena().openings()[0];
  pose.setOrigin(door.centre - door.normal * 6.0f);
  hider.body().setWorldTransform(pose);
  g.set_all(0.0f);
  g.harness.step();
  EXPECT_EQ(mask(), std::vector<int>({1, 0, 1, 0, 0}));
  EXPECT_EQ(flags(), std::vector<float>({0.0f, 0.0f}));
  // before the free prop: hold and lock, not unlock
  place_prop_in_doorway_and_hider_before_it(g);
  g.set_all(0.0f);
  g.harness.step();
  EXPECT_EQ(mask(), std::vector<int>({1, 1, 1, 1, 0}));
  EXPECT_EQ(flags(), std::vector<float>({1.0f, 0.0f}));
  // locked: unlock only
  g.set_all(0.0f, 0, 1);
  g.harness.step();
  ASSERT_TRUE(g.env.props()[0].locked());
  EXPECT_EQ(mask(), std::vector<int>({1, 0, 1, 0, 1}));
  EXPECT_EQ(flags(), std::vector<float>({0.0f, 1.0f}));
  // holding it: hold stays allowed
  g.set_all(0.0f, 0, 2);
  g.harness.step();
  g.set_all(0.0f, 1, 0);
  g.harness.step();
  ASSERT_GE(g.env.props().held_by(hider), 0);
  EXPECT_EQ(mask(), std::vector<int>({1, 1, 1, 1, 0}));
  // the seeker's masks never allow a prop action
  const uint8_t* m = g.seekers().action_mask.data();
  EXPECT_EQ(std::vector<int>(m, m + 5), std::vector<int>({1, 0, 1, 0, 0}));
}

TEST(HideAndSeekTest, WithoutPropCuesHidersMayChooseAnyPropAction) {
  Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}, {"prop_cues", 0.f}});
  place_prop_in_doorway_and_hider_before_it(g);
  g.set_all(0.0f, 0, 1);
  g.harness.step();
  ASSERT_TRUE(g.env.props()[0].locked());  // the prop actions themselves are unchanged
  const uint8_t* m = g.hiders().action_mask.data();
  EXPECT_EQ(std::vector<int>(m, m + 5), std::vector<int>({1, 1, 1, 1, 1}));
  EXPECT_EQ(g.hiders().observations[0][18], 0.0f);
  EXPECT_EQ(g.hiders().observations[0][19], 0.0f);
}

// "objects": props, openings and the teammate where they are relative to the agent, what state
// they are in, and the agent's slot; all zeros with object_obs 0
TEST(HideAndSeekTest, ObjectsObservationPlacesPropsOpeningsAndTheTeammate) {
  constexpr int kOpenings = HideAndSeek::kMaxProps * HideAndSeek::kPropFloats;
  constexpr int kMate = kOpenings + drone::kNumOpenings * HideAndSeek::kOpeningFloats;
  constexpr float kScale = 1.0f / 24.0f;  // positions / (2 half_size)
  Game g({{"level", 1.f}, {"num_hiders", 2.f}, {"num_seekers", 1.f}});
  ASSERT_EQ(g.env.spec().behaviors[0].observations[1].name, "objects");
  ASSERT_EQ(g.env.spec().behaviors[0].observations[1].size(), HideAndSeek::kObjectsSize);
  const auto objects = [&](int row) {
    const float* o = g.hiders().observations[1].data() + row * HideAndSeek::kObjectsSize;
    return std::vector<float>(o, o + HideAndSeek::kObjectsSize);
  };
  place_prop_in_doorway_and_hider_before_it(g);
  auto& me = *g.env.agent(HideAndSeek::kHider, 0).drone;
  auto& mate = *g.env.agent(HideAndSeek::kHider, 1).drone;
  btTransform pose = mate.body().getWorldTransform();
  pose.setOrigin(me.position() + me.right() * 3.0f);
  mate.body().setWorldTransform(pose);
  // hider 0 takes hold of the prop it faces
  g.set_all(0.0f);
  g.hiders().discrete_actions[0] = 1;
  g.harness.step();
  ASSERT_GE(g.env.props().held_by(me), 0);
  std::vector<float> o = objects(0);
  const btVector3 to_prop = g.env.props()[0].position() - me.position();
  EXPECT_NEAR(o[0], to_prop.dot(me.right()) * kScale, 1e-3f);
  EXPECT_NEAR(o[2], to_prop.dot(me.forward()) * kScale, 1e-3f);
  EXPECT_GT(o[2], 0.8f * kScale);  // about 1.2 m ahead
  EXPECT_EQ(o[3], 1.0f);           // present
  EXPECT_EQ(o[4], 0.0f);           // not locked
  EXPECT_EQ(o[5], 0.0f);           // held, but by this hider
  EXPECT_NEAR(std::abs(o[7]), 1.0f, 0.05f);  // the panel faces the hider or turns its back: |cos| 1
  for (int i = 1; i < HideAndSeek::kMaxProps; ++i)
    EXPECT_EQ(o[i * HideAndSeek::kPropFloats + 3], 0.0f) << "level 1 has one prop";
  const drone::Opening& door = g.env.arena().openings()[0];
  EXPECT_NEAR(o[kOpenings + 2], (door.centre - me.position()).dot(me.forward()) * kScale, 1e-3f);
  EXPECT_EQ(o[kOpenings + 3], 1.0f);  // open at level 1
  EXPECT_EQ(o[kOpenings + 4], 0.0f);  // not closed
  for (int k = 1; k < drone::kNumOpenings; ++k)
    EXPECT_EQ(o[kOpenings + k * HideAndSeek::kOpeningFloats + 3], 0.0f) << "opening " << k;
  EXPECT_NEAR(o[kMate], (mate.position() - me.position()).dot(me.right()) * kScale, 1e-3f);
  EXPECT_GT(o[kMate], 2.5f * kScale);
  EXPECT_EQ(o[kMate + 3], 1.0f);
  EXPECT_EQ(o[kMate + 4], 1.0f);  // slot 0
  EXPECT_EQ(o[kMate + 5], 0.0f);
  // the teammate sees the prop held by another drone, and itself in slot 1
  std::vector<float> m = objects(1);
  EXPECT_EQ(m[5], 1.0f);
  EXPECT_EQ(m[kMate + 4], 0.0f);
  EXPECT_EQ(m[kMate + 5], 1.0f);
  // locked where it stands: the prop is locked and the doorway closed
  g.set_all(0.0f, 0, 1);
  g.harness.step();
  ASSERT_TRUE(g.env.opening_closed(0));
  o = objects(0);
  EXPECT_EQ(o[4], 1.0f);
  EXPECT_EQ(o[kOpenings + 4], 1.0f);
  // level 2: each hider's lists start with its own prop and opening (hider h: prop and opening h;
  // with owner_shift 1 the other's)
  for (const int shift : {0, 1}) {
    Game two({{"level", 2.f}, {"num_hiders", 2.f}, {"num_seekers", 1.f},
              {"owner_shift", float(shift)}});
    two.idle_step();
    for (int h = 0; h < 2; ++h) {
      const auto& d = *two.env.agent(HideAndSeek::kHider, h).drone;
      const float* o = two.hiders().observations[1].data() + h * HideAndSeek::kObjectsSize;
      for (int k = 0; k < 4; ++k) {
        const int own = k < 2 ? (k + h + shift) % 2 : k;
        const btVector3 to_opening = two.env.arena().openings()[own].centre - d.position();
        EXPECT_NEAR(o[kOpenings + k * HideAndSeek::kOpeningFloats + 2],
                    to_opening.dot(d.forward()) * kScale, 1e-3f)
            << "hider " << h << ", entry " << k << ", shift " << shift;
        if (k >= 2) continue;
        const btVector3 to_prop = two.env.props()[own].position() - d.position();
        EXPECT_NEAR(o[k * HideAndSeek::kPropFloats], to_prop.dot(d.right()) * kScale, 1e-3f)
            << "hider " << h << ", prop entry " << k << ", shift " << shift;
      }
    }
  }
  // object_obs 0: the paper's observations, nothing in "objects"
  Game off({{"level", 2.f}, {"object_obs", 0.f}});
  off.idle_step();
  for (float x : std::vector<float>(off.hiders().observations[1].begin(),
                                    off.hiders().observations[1].end()))
    ASSERT_EQ(x, 0.0f);
}

// hider_slot_obs 0: the hiders' objects end with zeros where their slot was, the seekers keep
// theirs, and nothing else of the observation changes
TEST(HideAndSeekTest, HiderSlotObsZeroLeavesOutOnlyTheHidersSlot) {
  constexpr int kSlot = HideAndSeek::kMaxProps * HideAndSeek::kPropFloats +
                        drone::kNumOpenings * HideAndSeek::kOpeningFloats + 4;
  Game with({{"level", 1.f}, {"num_hiders", 2.f}, {"num_seekers", 2.f}}, 3);
  Game without({{"level", 1.f}, {"num_hiders", 2.f}, {"num_seekers", 2.f}, {"hider_slot_obs", 0.f}},
               3);
  with.idle_step();
  without.idle_step();
  for (int h = 0; h < 2; ++h) {
    const float* a = with.hiders().observations[1].data() + h * HideAndSeek::kObjectsSize;
    const float* b = without.hiders().observations[1].data() + h * HideAndSeek::kObjectsSize;
    EXPECT_EQ(a[kSlot + h], 1.0f) << "hider " << h;
    for (int i = 0; i < HideAndSeek::kObjectsSize; ++i) {
      if (i >= kSlot)
        EXPECT_EQ(b[i], 0.0f) << "hider " << h << ", float " << i;
      else
        EXPECT_EQ(a[i], b[i]) << "hider " << h << ", float " << i;
    }
  }
  for (int k = 0; k < 2; ++k) {
    const float* b = without.seekers().observations[1].data() + k * HideAndSeek::kObjectsSize;
    EXPECT_EQ(b[kSlot + k], 1.0f) << "seeker " << k;
  }
  EXPECT_EQ(with.seekers().observations[1], without.seekers().observations[1]);
}

// each open opening's entry says, at a fine scale, how far its prop is from standing in it, and
// which way the opening and the panel face, all in the agent's frame
TEST(HideAndSeekTest, ObjectsObservationTellsHowFarEachPropIsFromStandingInItsOpening) {
  constexpr int kOpenings = HideAndSeek::kMaxProps * HideAndSeek::kPropFloats;
  constexpr int kStride = HideAndSeek::kOpeningFloats;
  constexpr float kInDoorway = 0.35f;  // m inside the wall where a prop stands in a doorway
  const auto soft = [](float m) { return m / (1.0f + std::abs(m)); };
  Game g({{"level", 2.f}, {"num_hiders", 2.f}, {"num_seekers", 1.f}});
  const drone::Opening& door = g.env.arena().openings()[0];
  const btVector3 along = door.normal.cross(btVector3(0, 1, 0));  // horizontal, along the wall
  const drone::Prop& prop = g.env.props()[0];
  // prop 0 standing in doorway 0, turned parallel to its wall, then 10 cm along the wall
  const auto place = [&](float shift) {
    btTransform pose = prop.body->getWorldTransform();
    btVector3 spot = door.centre - door.normal * kInDoorway + along * shift;
    spot.setY(prop.half.y() + 0.02f);
    pose.setOrigin(spot);
    pose.setRotation(btQuaternion(btVector3(0, 1, 0), std::atan2(door.normal.x(), door.normal.z())));
    prop.body->setWorldTransform(pose);
    g.idle_step();
  };
  const auto entry = [&](int hider, int k) {
    const float* o = g.hiders().observations[1].data() + hider * HideAndSeek::kObjectsSize;
    return std::vector<float>(o + kOpenings + k * kStride, o + kOpenings + (k + 1) * kStride);
  };
  place(0.0f);
  const auto& me = *g.env.agent(HideAndSeek::kHider, 0).drone;
  std::vector<float> o = entry(0, 0);  // hider 0's own opening is opening 0
  EXPECT_NEAR(o[5], 0.0f, 0.02f);
  EXPECT_NEAR(o[6], 0.0f, 0.02f);
  EXPECT_NEAR(o[7], door.normal.dot(me.right()), 1e-3f);
  EXPECT_NEAR(o[8], door.normal.dot(me.forward()), 1e-3f);
  EXPECT_NEAR(o[9], 1.0f, 0.01f);  // parallel to the wall
  EXPECT_NEAR(o[10], 0.0f, 0.1f);
  place(0.1f);
  o = entry(0, 0);
  // the prop has to go 10 cm back along the wall: -along, seen from the hider
  EXPECT_NEAR(o[5], soft(-0.1f * along.dot(me.right())), 0.01f);
  EXPECT_NEAR(o[6], soft(-0.1f * along.dot(me.forward())), 0.01f);
  EXPECT_GT(std::hypot(o[5], o[6]), 0.07f);
  // the other hider sees opening 0 as its second entry, with the same prop
  const auto& mate = *g.env.agent(HideAndSeek::kHider, 1).drone;
  const std::vector<float> m = entry(1, 1);
  EXPECT_NEAR(m[5], soft(-0.1f * along.dot(mate.right())), 0.01f);
  EXPECT_NEAR(m[8], door.normal.dot(mate.forward()), 1e-3f);
  // a prop far from its opening: squashed, but below 1 and pointing at it
  const drone::Opening& other = g.env.arena().openings()[1];
  btVector3 error = other.centre - other.normal * kInDoorway - g.env.props()[1].position();
  error.setY(0.0f);
  ASSERT_GT(error.length(), 1.0f);
  o = entry(0, 1);
  EXPECT_NEAR(o[5], soft(error.dot(me.right())), 0.01f);
  EXPECT_NEAR(o[6], soft(error.dot(me.forward())), 0.01f);
  // openings closed at the level have nothing past "open"
  for (int k = 2; k < drone::kNumOpenings; ++k)
    for (int i = 3; i < kStride; ++i) EXPECT_EQ(entry(0, k)[i], 0.0f) << k << " " << i;
}

TEST(HideAndSeekTest, FortRewardPaysEveryOpeningClosedWhenThePrepPhaseEnds) {
  for (const bool lock : {true, false}) {
    Game g({{"level", 1.f},
            {"num_hiders", 2.f},
            {"num_seekers", 1.f},
            {"close_reward", 0.f},
            {"hide_reward", 0.f},
            {"fort_reward", 0.7f},
            {"prep_fraction", 0.1f},
            {"episode_frames", 300.f}});
    place_prop_in_doorway_and_hider_before_it(g);
    g.set_all(0.0f, 0, lock ? 1 : 0);
    g.harness.step();
    float paid[2] = {0, 0};
    int paid_steps = 0;
    while (g.env.in_prep()) {
      g.set_all(0.0f);
      g.harness.step();
      paid_steps += g.hiders().reward[0] != 0.0f;
      for (int h = 0; h < 2; ++h) paid[h] += g.hiders().reward[h];
    }
    EXPECT_EQ(g.env.episode_metrics().at("fort_rate"), lock ? 1.0f : 0.0f);
    for (int h = 0; h < 2; ++h) EXPECT_NEAR(paid[h], lock ? 0.7f : 0.0f, 1e-6f) << "hider " << h;
    EXPECT_EQ(paid_steps, lock ? 1 : 0);  // once, at the decision the prep phase ends in
  }
}

TEST(HideAndSeekTest, HeldCloseRewardIsTakenBackWhenTheDoorwayOpens) {
  Game g({{"level", 1.f},
          {"num_hiders", 1.f},
          {"num_seekers", 1.f},
          {"close_reward", 0.5f},
          {"close_reward_mode", 1.f}});
  place_prop_in_doorway_and_hider_before_it(g);
  auto& props = g.env.props();
  float total = 0.0f;
  auto step = [&](int lock) {
    const float r = g.lock_step(lock);
    total += r;
    return r;
  };
  EXPECT_NEAR(step(1), 0.5f, 1e-6f);   // closed: paid
  EXPECT_EQ(step(0), 0.0f);            // still closed: nothing more
  EXPECT_NEAR(step(2), -0.5f, 1e-6f);  // unlocked: taken back
  ASSERT_FALSE(props[0].locked());
  EXPECT_FALSE(g.env.opening_closed(0));
  EXPECT_NEAR(step(1), 0.5f, 1e-6f);  // closed again: paid again
  EXPECT_NEAR(step(2), -0.5f, 1e-6f);
  EXPECT_NEAR(step(1), 0.5f, 1e-6f);
  EXPECT_NEAR(total, 0.5f, 1e-5f);  // what the hiders hold: one closed doorway
}

// unlock_cost: every unlock costs the hider that made it, so churning is no longer free
// latched_grab 1: a hold lasts through decisions whose grab choice is 0, until a lock lets the
// prop go; with 0 (the SPEC's) choosing 0 releases it
TEST(HideAndSeekTest, LatchedGrabKeepsTheHoldUntilALock) {
  for (const float latched : {0.f, 1.f}) {
    SCOPED_TRACE(latched);
    Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}, {"latched_grab", latched}});
    place_prop_in_doorway_and_hider_before_it(g);
    auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
    g.set_all(0.0f, 1, 0);
    g.harness.step();
    ASSERT_EQ(g.env.props().held_by(hider), 0);
    g.set_all(0.0f, 0, 0);
    g.harness.step();
    EXPECT_EQ(g.env.props().held_by(hider), latched == 1.f ? 0 : -1);
    g.set_all(0.0f, 1, 0);
    g.harness.step();
    g.set_all(0.0f, 0, 1);  // a lock lets go in both modes
    g.harness.step();
    EXPECT_TRUE(g.env.props()[0].locked());
    EXPECT_EQ(g.env.props().held_by(hider), -1);
    g.set_all(0.0f, 0, 2);  // and an unlock does not take hold again
    g.harness.step();
    EXPECT_FALSE(g.env.props()[0].locked());
    EXPECT_EQ(g.env.props().held_by(hider), -1);
  }
}

// regrip 1: a hider that locked its held prop (the latched grab's only way to let go) takes it back
// with unlock and hold in one decision, and its mask allows hold there; with 0 the same decision
// only unlocks and hold is masked
TEST(HideAndSeekTest, RegripTakesALockedPropBackInOneDecision) {
  for (const float regrip : {0.f, 1.f}) {
    SCOPED_TRACE(regrip);
    Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}, {"latched_grab", 1.f},
            {"regrip", regrip}});
    place_prop_in_doorway_and_hider_before_it(g);
    auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
    g.set_all(0.0f, 1, 0);
    g.harness.step();
    ASSERT_EQ(g.env.props().held_by(hider), 0);
    g.set_all(0.0f, 0, 1);
    g.harness.step();
    ASSERT_TRUE(g.env.props()[0].locked());
    ASSERT_EQ(g.env.props().held_by(hider), -1);
    const uint8_t* m = g.hiders().action_mask.data();
    EXPECT_EQ(std::vector<int>(m, m + 5), std::vector<int>({1, regrip == 1.f ? 1 : 0, 1, 0, 1}));
    g.set_all(0.0f, 1, 2);
    g.harness.step();
    EXPECT_FALSE(g.env.props()[0].locked());
    EXPECT_EQ(g.env.props().held_by(hider), regrip == 1.f ? 0 : -1);
    // a lock and a hold together still let go: the lock acts after the grab
    g.set_all(0.0f, 1, 1);
    g.harness.step();
    EXPECT_TRUE(g.env.props()[0].locked());
    EXPECT_EQ(g.env.props().held_by(hider), -1);
  }
}

// square_grab 1: a hider facing the doorway that grabs a panel turned 40 degrees to it (in the
// room, clear of the walls) holds it face-on within a few decisions; with 0 the panel keeps its
// turn
TEST(HideAndSeekTest, SquareGrabHoldsThePanelFaceOn) {
  for (const float square : {0.f, 1.f}) {
    SCOPED_TRACE(square);
    Game g({{"level", 1.f}, {"num_hiders", 1.f}, {"num_seekers", 1.f}, {"square_grab", square}});
    place_prop_in_doorway_and_hider_before_it(g);
    auto& props = g.env.props();
    // both moved 1.5 m into the room, clear of the walls, and the panel turned
    const btVector3 back = -1.5f * g.env.arena().openings()[0].normal;
    const float turned = 40.0f * 3.14159265f / 180.0f;
    btTransform pose = props[0].body->getWorldTransform();
    pose.setOrigin(pose.getOrigin() + back);
    pose.setRotation(btQuaternion(btVector3(0, 1, 0), turned));
    props[0].body->setWorldTransform(pose);
    auto& hider = g.env.agent(HideAndSeek::kHider, 0).drone->body();
    btTransform hider_pose = hider.getWorldTransform();
    hider_pose.setOrigin(hider_pose.getOrigin() + back);
    hider.setWorldTransform(hider_pose);
    for (int decision = 0; decision < 10; ++decision) {  // hold, no thrust
      g.set_all(0.0f, 1, 0);
      g.harness.step();
    }
    ASSERT_EQ(g.env.props().held_by(*g.env.agent(HideAndSeek::kHider, 0).drone), 0);
    // the panel's normal against the hider's forward (both horizontal): 0 or 180 degrees is
    // face-on; the hider itself may have turned a little as the panel swung
    const btVector3 normal = props[0].body->getWorldTransform().getBasis().getColumn(2);
    const btVector3 forward = g.env.agent(HideAndSeek::kHider, 0).drone->forward();
    const float to_hider = std::acos(std::min(1.0f, std::abs(normal.dot(forward))));
    const float hider_turned = std::acos(
        std::min(1.0f, std::abs(forward.dot(g.env.arena().openings()[0].normal))));
    std::printf("square_grab %.0f: panel %.1f degrees off face-on, hider turned %.1f degrees\n",
                square, to_hider * 180 / 3.14159265f, hider_turned * 180 / 3.14159265f);
    if (square == 1.f) {
      EXPECT_LT(to_hider, 2.0f * 3.14159265f / 180.0f);
    } else {
      EXPECT_GT(to_hider, 30.0f * 3.14159265f / 180.0f);
    }
  }
}

// sensor_obs 0: the rays and both grids are zeros; the vector and objects are unchanged
TEST(HideAndSeekTest, WithoutSensorsRaysAndGridsAreZeros) {
  Parameters p{{"level", 2.f}, {"num_hiders", 2.f}, {"num_seekers", 2.f}};
  Game with(p);
  p["sensor_obs"] = 0.f;
  Game without(p);
  for (int step = 0; step < 3; ++step) {
    for (Game* g : {&with, &without}) {
      g->set_all(0.5f);
      g->harness.step();
    }
  }
  for (auto team : {HideAndSeek::kHider, HideAndSeek::kSeeker}) {
    auto& a = with.harness.buffers(team);
    auto& b = without.harness.buffers(team);
    for (int o = 0; o < 5; ++o) {
      SCOPED_TRACE(o);
      const auto& x = a.observations[o];
      const auto& y = b.observations[o];
      if (o < 2) {
        EXPECT_EQ(x, y);  // the same episode, seen through the vector and objects
      } else {
        EXPECT_GT(std::accumulate(x.begin(), x.end(), 0.0), 0.0);
        EXPECT_TRUE(std::all_of(y.begin(), y.end(), [](float v) { return v == 0.0f; }));
      }
    }
  }
}

TEST(HideAndSeekTest, UnlockCostIsTakenPerUnlock) {
  Game g({{"level", 1.f},
          {"num_hiders", 1.f},
          {"num_seekers", 1.f},
          {"close_reward", 0.5f},
          {"close_reward_mode", 1.f},
          {"unlock_cost", 0.05f}});
  place_prop_in_doorway_and_hider_before_it(g);
  float total = 0.0f;
  auto step = [&](int lock) {
    const float r = g.lock_step(lock);
    total += r;
    return r;
  };
  EXPECT_NEAR(step(1), 0.5f, 1e-6f);
  EXPECT_NEAR(step(2), -0.55f, 1e-6f);  // opened by an unlock: taken back, and the cost
  EXPECT_NEAR(step(1), 0.5f, 1e-6f);
  EXPECT_NEAR(step(2), -0.55f, 1e-6f);
  EXPECT_NEAR(step(2), 0.0f, 1e-6f);  // nothing left to unlock: no cost
  EXPECT_NEAR(total, -0.1f, 1e-5f);
}

TEST(HideAndSeekTest, ShapedCloseRewardPaysForBringingAPropNear) {
  Game g({{"level", 1.f},
          {"num_hiders", 1.f},
          {"num_seekers", 1.f},
          {"close_reward", 0.5f},
          {"close_reward_mode", 2.f}});
  const drone::Opening& door = g.env.arena().openings()[0];
  auto& prop = g.env.props()[0];
  // puts the prop, unlocked, `d` metres inside the room from the doorway's centre
  auto move_prop = [&](float d) {
    btTransform pose = prop.body->getWorldTransform();
    btVector3 p = door.centre - door.normal * d;
    p.setY(door.centre.y());
    pose.setOrigin(p);
    prop.body->setWorldTransform(pose);
  };
  auto step = [&] { return g.idle_step(); };
  move_prop(4.0f);
  step();  // the teleport is paid for on this step: start from here
  const float at4 = (prop.position() - door.centre).length();
  move_prop(2.0f);
  const float paid = step();
  const float at2 = (prop.position() - door.centre).length();
  // 0.5 (close reward) x 0.5 (half for nearness) x (distance gained / 5 m)
  EXPECT_NEAR(paid, 0.5f * 0.5f * (at4 - at2) / 5.0f, 1e-4f);
  EXPECT_GT(paid, 0.0f);
  move_prop(4.0f);
  EXPECT_NEAR(step(), -paid, 1e-4f);  // taken back as it moves away
  move_prop(7.0f);
  step();
  move_prop(6.0f);
  EXPECT_EQ(step(), 0.0f);  // beyond 5 m nearness is 0
}

// lock_keeps_shaping: a prop locked short of the doorway keeps its nearness and cover shares, so
// locking and unlocking it pay nothing; by default the lock gives them back and the unlock pays
// them again
TEST(HideAndSeekTest, LockKeepsShapingMakesALockShortOfTheDoorwayFree) {
  const auto lock_and_unlock = [](float keeps) {
    Game g({{"level", 1.f},
            {"num_hiders", 1.f},
            {"num_seekers", 1.f},
            {"close_reward", 1.f},
            {"close_reward_mode", 2.f},
            {"prop_shaping", 0.5f},
            {"cover_shaping", 0.3f},
            {"lock_keeps_shaping", keeps}});
    // prop and hider as for closing, then both 1.5 m further in: the prop is near, not closing
    place_prop_in_doorway_and_hider_before_it(g);
    const drone::Opening& door = g.env.arena().openings()[0];
    for (btCollisionObject* body : {static_cast<btCollisionObject*>(g.env.props()[0].body),
                                    static_cast<btCollisionObject*>(
                                        &g.env.agent(HideAndSeek::kHider, 0).drone->body())}) {
      btTransform pose = body->getWorldTransform();
      pose.setOrigin(pose.getOrigin() - door.normal * 1.5f);
      body->setWorldTransform(pose);
    }
    g.idle_step();  // the move is paid for here
    EXPECT_EQ(g.idle_step(), 0.0f);
    const float locked = g.lock_step(1);
    EXPECT_TRUE(g.env.props()[0].locked());
    EXPECT_FALSE(g.env.opening_closed(0));
    const float unlocked = g.lock_step(2);
    EXPECT_FALSE(g.env.props()[0].locked());
    EXPECT_NEAR(locked + unlocked, 0.0f, 1e-4f);  // a potential: the round trip sums to 0
    return unlocked;
  };
  EXPECT_GT(lock_and_unlock(0.0f), 0.1f);  // the unlock pays back the nearness share
  EXPECT_EQ(lock_and_unlock(1.0f), 0.0f);
}

// cover_shaping: an unlocked prop pays as it comes to cover the doorway, in full once locking it
// would close it; turned away or locked short it pays nothing
// level 1, one hider and one seeker, a close reward of 1 of which only the cover share (0.5)
// shapes
Parameters cover_shaping_game(float cover_depth) {
  return {{"level", 1.f},
          {"num_hiders", 1.f},
          {"num_seekers", 1.f},
          {"close_reward", 1.f},
          {"close_reward_mode", 2.f},
          {"prop_shaping", 0.f},
          {"cover_shaping", 0.5f},
          {"cover_depth", cover_depth}};
}

// puts prop 0, at rest, centred `d` metres inside doorway 0's centre, turned `yaw` from flat
// against its wall
void move_first_prop(Game& g, float d, float yaw) {
  const drone::Opening& door = g.env.arena().openings()[0];
  auto& prop = g.env.props()[0];
  btTransform pose = prop.body->getWorldTransform();
  btVector3 p = door.centre - door.normal * d;
  p.setY(prop.half.y() + 0.02f);
  pose.setOrigin(p);
  pose.setRotation(btQuaternion(btVector3(0, 1, 0), yaw));
  prop.body->setWorldTransform(pose);
  prop.body->setLinearVelocity(btVector3(0, 0, 0));
  prop.body->setAngularVelocity(btVector3(0, 0, 0));
}

TEST(HideAndSeekTest, CoverShapingPaysForAPropCoveringTheDoorway) {
  Game g(cover_shaping_game(0.5f));
  const drone::Opening& door = g.env.arena().openings()[0];
  auto& prop = g.env.props()[0];
  const auto move_prop = [&](float d, float yaw) { move_first_prop(g, d, yaw); };
  move_prop(1.8f, 1.5708f);  // side on, short of the doorway: covers nothing
  g.idle_step();
  EXPECT_EQ(g.idle_step(), 0.0f);
  move_prop(0.25f, 0.0f);  // flat in the doorway: would close it
  ASSERT_GT(drone::covered_fraction(door, *prop.body), 0.5f);
  EXPECT_NEAR(g.idle_step(), 0.5f, 1e-4f);  // cover_shaping x close_reward
  move_prop(0.25f, 1.5708f);  // turned side on where it stands: the share is taken back
  const float turned = g.idle_step();
  const float cover = drone::covered_fraction(door, *prop.body);
  ASSERT_LT(cover, 0.5f);
  EXPECT_NEAR(turned, 0.5f * (cover / 0.5f - 1.0f), 1e-4f);
  EXPECT_LT(turned, -0.1f);
  move_prop(0.25f, 0.0f);
  g.idle_step();
  // locked there it closes the doorway: the rest of the opening's 1 is paid
  place_prop_in_doorway_and_hider_before_it(g);
  g.set_all(0.0f, 0, 1);
  g.harness.step();
  ASSERT_TRUE(g.env.opening_closed(0));
  EXPECT_NEAR(g.hiders().reward[0], 0.5f, 1e-4f);
}

// close_credit 1: each hider is paid the close reward of its own opening (hider h: h mod the open
// ones); 0, the paper's, pays every hider the whole team's
// cover_depth: a flat panel behind the doorway, deeper than the closing test looks, is paid part
// of the cover share, more the nearer it comes; the default pays nothing until it would close
TEST(HideAndSeekTest, CoverDepthPaysForAPanelLinedUpBehindTheDoorway) {
  const auto paid_at = [](float cover_depth, float d) {  // the shaping gained moving the panel
    Game g(cover_shaping_game(cover_depth));
    move_first_prop(g, d, 0.0f);  // centred d inside, flat against the wall
    return g.idle_step();  // the prop started in its own place, where it covers nothing
  };
  // centred 1 m inside, its face is 0.9 m in: each ray counts (1.5 - 0.9) / (1.5 - 0.5) = 0.6, and
  // a panel lined up behind holds half of that share: 0.5 x 0.6 x cover_shaping 0.5 = 0.15
  EXPECT_EQ(paid_at(0.5f, 1.0f), 0.0f);
  EXPECT_NEAR(paid_at(1.5f, 1.0f), 0.15f, 1e-3f);
  EXPECT_NEAR(paid_at(1.5f, 1.2f), 0.10f, 1e-3f);  // face 1.1 m in: 0.4
  EXPECT_EQ(paid_at(1.5f, 1.7f), 0.0f);             // face 1.6 m in: past cover_depth
  EXPECT_NEAR(paid_at(1.5f, 0.25f), 0.5f, 1e-4f);  // where it would close: all of it, as before
  EXPECT_NEAR(paid_at(0.5f, 0.25f), 0.5f, 1e-4f);
}

TEST(HideAndSeekTest, OwnCloseCreditPaysEachHiderForItsOwnOpening) {
  // the props standing in their doorways; hider 0 locks the prop in the level's last doorway
  // (level 2: doorway 1, hider 1's own; level 1: doorway 0, both hiders' own)
  struct Paid {
    float hider0, hider1;
  };
  const auto lock_last_doorway = [](float level, float credit, float shift = 0.f) {
    Game g({{"level", level},
            {"prop_start_offset", 0.f},
            {"close_reward", 0.5f},
            {"close_reward_mode", 2.f},
            {"close_credit", credit},
            {"owner_shift", shift}},
           3);
    g.idle_step();
    const int door = int(level) - 1;
    auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
    stand_behind(hider, g.env.props()[door], g.env.arena().openings()[door].normal);
    EXPECT_EQ(g.env.props().lock(hider, HideAndSeek::kHider), door);
    g.idle_step();
    EXPECT_TRUE(g.env.opening_closed(door));
    return Paid{g.hiders().reward[0], g.hiders().reward[1]};
  };
  const Paid team = lock_last_doorway(2.f, 0.f), own = lock_last_doorway(2.f, 1.f);
  EXPECT_GT(team.hider0, 0.2f);  // the rest of doorway 1's share, 0.5 x (1 - prop nearness / 2)
  EXPECT_FLOAT_EQ(team.hider1, team.hider0);
  // the same world, the team's reward split: doorway 1's part to hider 1, doorway 0's (its prop
  // only settling) to hider 0
  EXPECT_NEAR(own.hider0 + own.hider1, team.hider0, 1e-5f);
  EXPECT_NEAR(own.hider0, 0.0f, 1e-3f);
  // owner_shift 1 hands doorway 1 to hider 0
  const Paid shifted = lock_last_doorway(2.f, 1.f, 1.f);
  EXPECT_NEAR(shifted.hider0, own.hider1, 1e-5f);
  EXPECT_NEAR(shifted.hider1, own.hider0, 1e-5f);
  // level 1: the one doorway is both hiders' own
  const Paid one_team = lock_last_doorway(1.f, 0.f), one_own = lock_last_doorway(1.f, 1.f);
  EXPECT_GT(one_own.hider0, 0.2f);
  EXPECT_FLOAT_EQ(one_own.hider0, one_team.hider0);
  EXPECT_FLOAT_EQ(one_own.hider1, one_team.hider1);
  EXPECT_FLOAT_EQ(one_own.hider1, one_own.hider0);
}

// shared_props 0: a hider's grab, lock and unlock pass over its teammate's prop (level 2: prop
// i goes with doorway i, hider h's is (h + owner_shift) mod 2), and its mask says so; at level 1
// the one prop is both hiders'
TEST(HideAndSeekTest, UnsharedPropsKeepAHiderOffItsTeammatesProp) {
  struct Tried {
    bool grab_allowed, lock_allowed, closed, unlock_allowed, unlocked;
  };
  // hider `who` stands behind the prop in doorway `door` (props in their doorways), reads its
  // mask, then locks; afterwards the prop is locked for it and it tries to unlock
  const auto try_prop = [](float level, float shared, int who, int door, float shift = 0.f) {
    Game g({{"level", level},
            {"prop_start_offset", 0.f},
            {"shared_props", shared},
            {"owner_shift", shift}},
           5);
    auto& hider = *g.env.agent(HideAndSeek::kHider, who).drone;
    stand_behind(hider, g.env.props()[door], g.env.arena().openings()[door].normal);
    g.idle_step();
    Tried t{};
    const uint8_t* m = g.hiders().action_mask.data() + who * 5;  // [grab 2, lock 3]
    t.grab_allowed = m[1] == 1;
    t.lock_allowed = m[3] == 1;
    g.set_all(0.0f);
    g.hiders().discrete_actions[who * 2 + 1] = 1;  // lock
    g.harness.step();
    t.closed = g.env.opening_closed(door);
    if (!g.env.props()[door].locked()) {
      EXPECT_EQ(g.env.props().lock(hider, HideAndSeek::kHider), door);  // as the teammate would
    }
    g.idle_step();
    t.unlock_allowed = m[4] == 1;
    g.set_all(0.0f);
    g.hiders().discrete_actions[who * 2 + 1] = 2;  // unlock
    g.harness.step();
    t.unlocked = !g.env.props()[door].locked();
    return t;
  };
  // level 2, hider 0 at doorway 1 (its teammate's): nothing it may do there
  const Tried mate = try_prop(2.f, 0.f, 0, 1);
  EXPECT_FALSE(mate.grab_allowed);
  EXPECT_FALSE(mate.lock_allowed);
  EXPECT_FALSE(mate.closed);
  EXPECT_FALSE(mate.unlock_allowed);
  EXPECT_FALSE(mate.unlocked);
  // the same with shared props (the paper's), at its own doorway, and with the jobs swapped
  for (const Tried& t : {try_prop(2.f, 1.f, 0, 1), try_prop(2.f, 0.f, 0, 0),
                         try_prop(2.f, 0.f, 1, 1), try_prop(2.f, 0.f, 0, 1, 1.f)}) {
    EXPECT_TRUE(t.grab_allowed);
    EXPECT_TRUE(t.lock_allowed);
    EXPECT_TRUE(t.closed);
    EXPECT_TRUE(t.unlock_allowed);
    EXPECT_TRUE(t.unlocked);
  }
  EXPECT_FALSE(try_prop(2.f, 0.f, 1, 0).closed);  // hider 1 at hider 0's doorway
  EXPECT_FALSE(try_prop(2.f, 0.f, 1, 1, 1.f).closed);  // swapped: doorway 1 is hider 0's
  // level 1: the one prop is both hiders'
  EXPECT_TRUE(try_prop(1.f, 0.f, 0, 0).closed);
  EXPECT_TRUE(try_prop(1.f, 0.f, 1, 0).closed);
}

// hider `who` locks the prop standing in doorway 0, then the prep phase runs out idle; the
// episode's metrics
EpisodeMetrics lock_doorway_then_end_prep(Game& g, int who) {
  stand_behind(*g.env.agent(HideAndSeek::kHider, who).drone, g.env.props()[0],
               g.env.arena().openings()[0].normal);
  g.idle_step();
  g.set_all(0.0f);
  g.hiders().discrete_actions[who * 2 + 1] = 1;  // lock
  g.harness.step();
  EXPECT_TRUE(g.env.opening_closed(0));
  g.set_all(0.0f);
  while (g.env.in_prep()) g.harness.step();
  return g.env.episode_metrics();
}

// each hider's own metrics: at level 2 with the props in their doorways, the hider that locks
// its own prop has its doorway closed and was not idle; its teammate, which did nothing, the
// other way round; with owner_shift 1 the same lock is the teammate's doorway
TEST(HideAndSeekTest, PerHiderMetricsTellWhoClosedItsOwnDoorwayAndWhoIdled) {
  for (const float shift : {0.f, 1.f}) {
    Game g({{"level", 2.f},
            {"prop_start_offset", 0.f},
            {"owner_shift", shift},
            {"episode_frames", 120.f},
            {"prep_fraction", 0.5f}},
           5);
    const auto m = lock_doorway_then_end_prep(g, 0);
    ASSERT_FALSE(g.env.opening_closed(1));
    EXPECT_EQ(m.at("hider0_idle"), 0.0f) << "shift " << shift;
    EXPECT_EQ(m.at("hider1_idle"), 1.0f) << "shift " << shift;
    EXPECT_EQ(m.at("hider0_closed_own"), shift == 0.f ? 1.0f : 0.0f) << "shift " << shift;
    EXPECT_EQ(m.at("hider1_closed_own"), shift == 0.f ? 0.0f : 1.0f) << "shift " << shift;
    EXPECT_EQ(m.at("fort_rate"), 0.0f);
  }
  // level 1: the one doorway is both hiders', so one lock closes it for both
  Game one({{"level", 1.f}, {"prop_start_offset", 0.f}, {"episode_frames", 120.f},
            {"prep_fraction", 0.5f}},
           5);
  const auto m = lock_doorway_then_end_prep(one, 1);
  EXPECT_EQ(m.at("hider0_closed_own"), 1.0f);
  EXPECT_EQ(m.at("hider1_closed_own"), 1.0f);
  EXPECT_EQ(m.at("hider0_idle"), 1.0f);
  EXPECT_EQ(m.at("hider1_idle"), 0.0f);
}

// how far each hider's building got: at level 2 with the props in their doorways, hider 0 locks
// its prop and unlocks it again (closed once, not at the end, still covering), hider 1 does
// nothing (its prop stands in its doorway unlocked: covered, never closed); with the props at
// their own places nothing covers a doorway and the nearest prop is at least 2.5 m away
TEST(HideAndSeekTest, PerHiderMetricsTellHowFarEachHidersBuildingGot) {
  Game g({{"level", 2.f}, {"prop_start_offset", 0.f}, {"episode_frames", 120.f},
          {"prep_fraction", 0.5f}},
         5);
  stand_behind(*g.env.agent(HideAndSeek::kHider, 0).drone, g.env.props()[0],
               g.env.arena().openings()[0].normal);
  g.idle_step();
  g.set_all(0.0f);
  g.hiders().discrete_actions[1] = 1;  // hider 0 locks
  g.harness.step();
  ASSERT_TRUE(g.env.opening_closed(0));
  g.set_all(0.0f);
  g.hiders().discrete_actions[1] = 2;  // and unlocks
  g.harness.step();
  ASSERT_FALSE(g.env.opening_closed(0));
  g.set_all(0.0f);
  while (g.env.in_prep()) g.harness.step();
  const auto m = g.env.episode_metrics();
  EXPECT_EQ(m.at("hider0_closed_own_once"), 1.0f);
  EXPECT_EQ(m.at("hider0_closed_own"), 0.0f);
  EXPECT_EQ(m.at("hider0_covered_own"), 1.0f);
  EXPECT_EQ(m.at("hider1_closed_own_once"), 0.0f);
  EXPECT_EQ(m.at("hider1_covered_own"), 1.0f);
  EXPECT_LT(m.at("hider0_own_gap"), 1.0f);
  EXPECT_LT(m.at("hider1_own_gap"), 1.0f);

  Game far({{"level", 2.f}, {"prop_start_offset", 1.f}, {"episode_frames", 120.f},
            {"prep_fraction", 0.5f}},
           5);
  far.set_all(0.0f);
  while (far.env.in_prep()) far.harness.step();
  const auto f = far.env.episode_metrics();
  for (const char* h : {"hider0", "hider1"}) {
    EXPECT_EQ(f.at(std::string(h) + "_closed_own_once"), 0.0f) << h;
    EXPECT_EQ(f.at(std::string(h) + "_covered_own"), 0.0f) << h;
    EXPECT_GE(f.at(std::string(h) + "_own_gap"), 2.4f) << h;
  }
}

TEST(HideAndSeekTest, ReachShapingPaysForAHiderComingNearTheProp) {
  Game g({{"level", 1.f},
          {"num_hiders", 1.f},
          {"num_seekers", 1.f},
          {"close_reward", 0.5f},
          {"close_reward_mode", 2.f},
          {"reach_shaping", 0.25f},
          {"shaping_range", 4.f}});
  const drone::Opening& door = g.env.arena().openings()[0];
  const btVector3 prop = g.env.props()[0].position();
  auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
  // puts the hider `d` metres from the prop, towards the room's centre, at the prop's height
  auto move_hider = [&](float d) {
    btTransform pose = hider.body().getWorldTransform();
    pose.setOrigin(prop - door.normal * d);
    hider.body().setWorldTransform(pose);
    hider.body().setLinearVelocity(btVector3(0, 0, 0));
  };
  auto step = [&] { return g.idle_step(); };
  move_hider(3.0f);
  step();  // the teleport is paid for on this step: start from here
  const float at3 = (hider.position() - g.env.props()[0].position()).length();
  move_hider(1.5f);
  const float paid = step();
  const float at15 = (hider.position() - g.env.props()[0].position()).length();
  // 0.5 (close reward) x 0.25 (reach share) x (distance gained / 4 m); the prop did not move
  EXPECT_NEAR(paid, 0.5f * 0.25f * (at3 - at15) / 4.0f, 1e-4f);
  EXPECT_GT(paid, 0.0f);
  move_hider(3.0f);
  EXPECT_NEAR(step(), -paid, 1e-4f);  // taken back as it leaves
  move_hider(5.0f);
  step();
  move_hider(4.5f);
  EXPECT_NEAR(step(), 0.0f, 1e-6f);  // beyond the range nearness is 0
}

// push_shaping: a hider is paid for coming to the place behind the prop, where the prop is between
// it and the doorway, and not for standing as near the prop on the doorway's side
TEST(HideAndSeekTest, PushShapingPaysForAHiderBehindThePropNotBeforeIt) {
  Game g({{"level", 1.f},
          {"num_hiders", 1.f},
          {"num_seekers", 1.f},
          {"close_reward", 0.5f},
          {"close_reward_mode", 2.f},
          {"prop_shaping", 0.f},
          {"push_shaping", 0.25f},
          {"shaping_range", 4.f}});
  const drone::Opening& door = g.env.arena().openings()[0];
  move_first_prop(g, 3.0f, 0.0f);  // 3 m in front of the doorway, inside the room
  const btVector3 prop = g.env.props()[0].position();
  const btVector3 inward = -door.normal;  // from the doorway into the room
  auto& hider = *g.env.agent(HideAndSeek::kHider, 0).drone;
  // puts the hider `d` metres from the prop's centre, further into the room (d < 0: on the
  // doorway's side), at the prop's height
  auto move_hider = [&](float d) {
    btTransform pose = hider.body().getWorldTransform();
    pose.setOrigin(prop + inward * d);
    hider.body().setWorldTransform(pose);
    hider.body().setLinearVelocity(btVector3(0, 0, 0));
  };
  // the place push_shaping pays for: kGrabStandoff (1.1 m) behind the prop, seen from the doorway
  const float standoff = HideAndSeek::kGrabStandoff;
  const auto from_push_place = [&] {
    btVector3 away = g.env.props()[0].position() - door.centre;
    away.setY(0.0f);
    return (hider.position() - (g.env.props()[0].position() + away.normalized() * standoff))
        .length();
  };
  move_hider(standoff + 2.0f);  // 2 m past the place
  g.idle_step();                // the teleport is paid for on this step: start from here
  const float far = from_push_place();
  move_hider(standoff);
  const float paid = g.idle_step();
  const float near = from_push_place();
  // 0.5 (close reward) x 0.25 (push share) x (distance gained / 4 m)
  EXPECT_NEAR(paid, 0.5f * 0.25f * (far - near) / 4.0f, 1e-4f);
  EXPECT_GT(paid, 0.05f);
  // as near the prop, on the doorway's side: 2.2 m from the place, paid back accordingly
  move_hider(-standoff);
  const float before = g.idle_step();
  EXPECT_NEAR(before, -0.5f * 0.25f * (from_push_place() - near) / 4.0f, 1e-4f);
  EXPECT_LT(before, -0.05f);
}

TEST(HideAndSeekTest, BakerPresetIsZeroSumPerDecision) {
  Game g({{"level", 2.f}, {"reward_preset", 1.f}, {"prep_fraction", 0.1f}, {"episode_frames", 300.f}});
  g.set_all(0.3f);
  int test_steps = 0;
  while (!g.over()) {
    const bool prep = g.env.in_prep();
    g.harness.step();
    const float h = g.hiders().reward[0];
    if (prep && g.env.in_prep()) {
      EXPECT_EQ(h, 0.0f);
      continue;
    }
    if (g.env.in_prep()) continue;
    ++test_steps;
    EXPECT_TRUE(h == 1.0f || h == -1.0f) << h;
    EXPECT_EQ(g.hiders().reward[1], h);
    EXPECT_EQ(g.seekers().group_reward[0], -h);
    EXPECT_EQ(g.seekers().reward[0], 0.0f);
  }
  EXPECT_GT(test_steps, 50);
}

TEST(HideAndSeekTest, SameSeedSameEpisode) {
  auto run = [](uint64_t seed) {
    Game g({{"level", 4.f}, {"episode_frames", 240.f}, {"prep_fraction", 0.2f}}, seed);
    std::vector<float> trace;
    for (int i = 0; i < 80 && !g.over(); ++i) {
      g.script(HideAndSeek::kHider);
      g.script(HideAndSeek::kSeeker);
      g.harness.step();
      trace.insert(trace.end(), g.hiders().observations[0].begin(), g.hiders().observations[0].end());
    }
    return trace;
  };
  EXPECT_EQ(run(7), run(7));
  EXPECT_NE(run(7), run(8));
}

// in how many of 20 episodes (seeds 1-20) the scripted hiders close every opening of `level` in
// the prep phase
int scripted_forts(float level, float doorway_swap_chance = 0.0f) {
  int closed = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    Game g({{"level", level}, {"doorway_swap_chance", doorway_swap_chance}}, seed);
    g.set_all(0.0f);
    while (g.env.in_prep() && !g.over()) {
      g.script(HideAndSeek::kHider);
      g.harness.step();
    }
    closed += g.env.episode_metrics().at("fort_rate") == 1.0f;
  }
  return closed;
}

// the scripted policies: hiders close the doorway, seekers catch a still hider (issue 4 asks for
// >= 80% of 20 episodes each; rlt_cli_test checks the same through `rlt eval`)
TEST(HideAndSeekTest, ScriptedHiderClosesTheDoorway) {
  const int closed = scripted_forts(1);
  EXPECT_GE(closed, 16) << closed << " of 20";
  const int swapped = scripted_forts(1, 1.0f);  // the doorway in the +z wall
  EXPECT_GE(swapped, 16) << swapped << " of 20";
}

// at level 2 each scripted hider keeps its own doorway until it is closed: when the first was
// closed, the other's turn moved to it, and it stood still holding its panel at its doorway
TEST(HideAndSeekTest, ScriptedHidersCloseBothDoorwaysAtLevel2) {
  const int closed = scripted_forts(2);
  EXPECT_GE(closed, 16) << closed << " of 20";
}

TEST(HideAndSeekTest, ScriptedSeekerTagsAStillHider) {
  int tagged = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    Game g({{"level", 1.f}}, seed);
    g.set_all(0.0f);
    while (!g.over()) {
      g.script(HideAndSeek::kSeeker);
      g.harness.step();
    }
    tagged += g.env.episode_metrics().at("tag_rate") == 1.0f;
  }
  EXPECT_GE(tagged, 16) << tagged << " of 20";
}

TEST(HideAndSeekTest, RecordingHoldsTheOpeningsTheConesAndEveryRewardPaid) {
  Game g({{"level", 1.f}, {"episode_frames", 1500.f}}, 3);
  g.env.set_recording(true);
  g.harness.reset();
  std::map<int, double> paid, group_paid;  // by agent id, from the step buffers
  while (!g.over()) {
    g.script(HideAndSeek::kHider);
    g.script(HideAndSeek::kSeeker);
    g.harness.step();
    for (auto* b : {&g.hiders(), &g.seekers()})
      for (int r = 0; r < b->rows; ++r)
        if (b->step_type[r] != StepType::kAbsent) {
          paid[b->agent_id[r]] += b->reward[r];
          group_paid[b->agent_id[r]] += b->group_reward[r];
        }
  }
  EpisodeRecording rec;
  ASSERT_TRUE(g.env.take_recording(rec));
  std::map<int, double> recorded, group_recorded;
  for (const RecordedFrame& f : rec.frames)
    for (size_t id = 0; id < f.rewards.size(); ++id) {
      recorded[int(id)] += f.rewards[id];
      group_recorded[int(id)] += f.group_rewards[id];
    }
  ASSERT_FALSE(paid.empty());
  double total = 0;
  for (const auto& [id, sum] : paid) {
    EXPECT_NEAR(recorded[id], sum, 1e-4) << "agent " << id;
    EXPECT_NEAR(group_recorded[id], group_paid[id], 1e-4) << "agent " << id;
    total += std::abs(sum) + std::abs(group_paid[id]);
  }
  EXPECT_GT(total, 0.1);  // the scripted hider closes the doorway: rewards were paid
  // level 1: the first doorway open, the rest filled
  ASSERT_EQ(rec.openings.size(), 4u);
  EXPECT_EQ(rec.openings[0].kind, "doorway");
  EXPECT_TRUE(rec.openings[0].open);
  EXPECT_FALSE(rec.openings[1].open);
  EXPECT_EQ(rec.openings[2].kind, "window");
  for (const RecordedBody& b : rec.bodies) {
    const bool drone = b.kind == "hider" || b.kind == "seeker";
    EXPECT_EQ(b.vision_range > 0, drone) << b.kind;
    if (drone) { EXPECT_GT(b.vision_cone_degrees, 0); }
  }
}

}  // namespace
}  // namespace rlt
