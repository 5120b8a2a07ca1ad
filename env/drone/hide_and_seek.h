// HideAndSeek: drones that hide and seek in a Bullet world with a room, props and obstacles
// (SPEC.md section 6; metrics of section 8). Built from the drone pieces of env/drone/:
// BulletWorld, Arena, DroneBody, PropSet and obstacles, RaySensor, vision (sees, assault_horizon).
//
// Behaviors: "Hider" (2 slots, group 0, agent id = slot) and "Seeker" (4 slots, group 1, agent id =
// 2 + slot); `num_hiders` (1-2) and `num_seekers` (1-4) pick how many are used, the other slots
// stay kAbsent. Both have the same action spec:
//   continuous 4 in [-1, 1]: forward thrust, strafe (to the right), vertical thrust, yaw rate;
//   discrete branch "grab" {0 release, 1 hold}, branch "lock" {0 none, 1 lock, 2 unlock}.
// Masks (1 = allowed) allow only what would act on a prop now: hold when the drone holds a prop or
// one it could grab is in reach and in front, lock when an unlocked prop is, unlock when a prop the
// hiders locked is; seekers cannot grab or lock (only option 0 of both branches). The env ignores a
// forbidden option (for hiders it would fail anyway). Grab and lock act once, at the start of a
// decision (PropSet rules: reach 1.5 m, a 60-degree front cone; hold keeps a held prop; a hider
// that locks the prop it holds lets go of it; only the locking team may unlock). With
// `latched_grab` 1 grab option 0 keeps a held prop instead of releasing it, so a hold lasts until
// a lock lets it go (default 0: held only while chosen, the SPEC's). Policies that choose hold and
// release by turns drop the prop every other decision and take it again at a drifted pose. With
// `square_grab` 1 a grab swings the panel face-on to the drone (PropParams::square_hold), so a
// hider facing a doorway holds its panel parallel to it, whichever way the panel lay (default 0:
// the panel keeps the pose it was grabbed at). With `regrip` 1 a decision's unlock acts before its
// grab, so unlock and hold together take a locked prop straight back into the hand, and the mask
// allows hold before a prop the hider may unlock (default 0: the grab comes first and finds the
// prop still locked; with the latched grab a hider that locked to let go needs two decisions).
//
// Time: physics at 50 Hz; an agent decides every `decision_period` (3) frames and its thrust is
// repeated for those frames. An episode lasts at most `episode_frames` (3072) frames; the first
// round(prep_fraction * episode_frames) frames (40%: 1228) are the prep phase, in which seekers are
// frozen (zero linear and angular factors: they neither fly nor get pushed) but observe.
//
// Start (seeded): the arena of `level` (1-4; arena.h), with chance `doorway_swap_chance` (default
// 0) its two doorways trading walls (ArenaParams::doorways_swapped: doorway 0, and so level 1's
// one doorway and its prop, in the +z wall), hiders inside the room or, each with chance
// `hider_outside_chance`, within 2.5 m outside it (-1, the default: the level's own chance, 0 at
// levels 1 and 2 and 0.5 at levels 3 and 4), seekers outside the room at least 2 m from its
// walls, all at 1 m height with random yaw; props per level: 1: one, next to doorway 0, parallel to
// its wall; 2: two, in the room at least 2.5 m from every opening; 3: three anywhere in the room;
// 4: four anywhere in the arena; random yaw from level 2 on. At levels 1 and 2, `prop_start_offset`
// t in [0, 1] (default 1) moves prop i the fraction t of the way from standing in doorway i
// (unlocked, covering it, parallel to its wall: locking it closes the doorway) to that start, for
// a curriculum that teaches locking before dragging (level 2: the prop's yaw turns the same
// fraction of the way from parallel to the wall to its random yaw); with chance
// `prop_start_spread` (default 0) an episode's offset is drawn uniformly from [0, t] instead, so
// that easier starts stay in the mix while the rest start at t, and otherwise with chance
// `prop_start_far_chance` (default 0) from [t, max(t, `prop_start_far_offset`)] (default 1), so
// that some episodes ask for the longer push of later lessons; with `prop_pairing` 1 (default
// 0) the two level-2 start places are drawn first and prop i gets the one that keeps the ways from
// each doorway to its prop least in total (the panels are alike: only which is whose changes, so
// hider h's own prop is never the one across the room); the shelter strategy counts
// only episodes whose props started at their own places (metric prop_start_offset 1: t = 1, or
// level 3 or 4, where the parameter does nothing). Obstacles (level 3: 3, level 4: 5) at random
// free places on the floor. Every spawn keeps clear of walls and of earlier spawns.
//
// Seeing (each physics frame): seeker s sees hider h when sees(world, s, h) of vision.h (135-degree
// cone, `vision_range` 20 m, unobstructed line of sight). A hider is hidden when no seeker sees it.
// Tagging (test phase only): a seeker whose centre is within 2 drone radii + `tag_distance` (0.1 m)
// of a hider's centre tags it. A tagged hider gets its penalty, leaves (kLast, terminated) and its
// body is removed. With `end_on_tag` = 1 (default) the first tag ends the episode for everyone
// (terminated); otherwise it ends when every hider is tagged, or at the frame limit (truncated).
// Closing: opening o (open at the level) is closed while a locked prop covers more than half of it
// (covered_fraction of arena.h); checked at every decision.
//
// Rewards, `reward_preset` 0 = the paper's (sizes are parameters, defaults in brackets):
//   hider (reward): + hide_reward (0.001; level 4: hide_reward_level4 0.0005) per test-phase frame
//     in which no seeker sees it; + close_reward (0.1) the first time in the episode each opening
//     becomes closed (every hider in the game gets it: the room is shared); + tagged_reward (-1)
//     when tagged. With `close_reward_mode` 1 (held) the close reward is paid whenever an opening
//     becomes closed and taken back whenever it opens again (a potential: the hiders hold
//     close_reward per closed opening, so a fort kept to the end pays and locking, unlocking and
//     locking again pays nothing more). With 2 (held and shaped) they also hold, for each open
//     opening that is not closed, the close reward times prop_shaping (0.5) times how near the
//     nearest prop is to its centre, plus reach_shaping (0) times how near the nearest hider is to
//     that prop, plus push_shaping (0) times how near the nearest hider is to the place
//     kGrabStandoff (1.1 m) behind that prop on the horizontal line from the opening's centre
//     through it (where a hider has the prop between itself and the opening and pushes it
//     there), plus cover_shaping (0) times the largest share of the opening an unlocked prop
//     covers, over the share that closes it (capped at 1: a prop that would close it if locked;
//     with `cover_depth` d above its default 0.5 m, the closing test's depth, at least half the
//     graded share of a prop lined up behind it: rays reach d inside the wall's centre plane,
//     and a face met deeper than 0.5 m counts less, down to 0 at d, so pushing a panel up to
//     the doorway pays on the way);
//     nearness is 1 - distance / shaping_range (5 m), 0 beyond. Potential-based shaping (Ng,
//     Harada and Russell 1999): it pays for each link of the chain reach, drag, cover, lock and
//     takes it back when undone; the four shares together are at most 1, what a closed opening
//     holds. Only unlocked props hold shares, so a hider that locks a prop short
//     of closing gives its share back and is paid it again for the unlock; with
//     `lock_keeps_shaping` 1 a locked prop holds the same shares as an unlocked one, and a lock
//     or an unlock changes the reward only when it closes or opens the opening. Trained hiders
//     paid by the default lock and unlock tens of times per prep phase; with 1 they did so about
//     a quarter as often but learned the lessons more slowly (docs/results, eleventh section).
//     With `close_credit` 1 (own; 0, the default, is the paper's team reward) hider h is paid
//     only the close reward of its own opening, h mod the number of open ones (the one its
//     objects observation lists first), and every hider that of an opening no hider owns: at
//     level 2 each of two hiders answers for one doorway, at level 1 both for the one.
//     With `shared_props` 0 (1, the default, is the paper's: any hider may move any prop) a
//     hider's grab, lock and unlock act only on its own props, owned as the openings are (prop
//     i goes with opening i; the prop its objects observation lists first): at level 2 each of
//     two hiders may take only the prop of its own doorway, at level 1 both the one, and the
//     masks and vector [18, 20) say so. It narrows the game for a curriculum's lessons (a
//     teammate's prop can still be pushed); shelter counts only games with shared props.
//     + fort_reward (0) per opening closed when the prep phase ends (the fort the seekers meet:
//     the close reward pays the closing, this the keeping; a quick unlock and relock pays again).
//     - unlock_cost (0) from a hider for every prop it unlocks: the held close reward refunds an
//     unlock on the next relock, so without a cost locking and unlocking again and again costs
//     nothing and the lock at the end of the prep phase falls where the churn stops.
//   seeker: reward + seen_reward (0.001) per test-phase frame per hider it sees, times the
//     assault-horizon signal clipped to [0, 1] when `assault_weighting` = 1; + unseen_reward (0;
//     negative for the constant penalty of RQ3) per test-phase frame in which no seeker sees any
//     hider; group_reward + tag_reward (1) per tagged hider.
// `reward_preset` 1 = "baker" (OpenAI's zero-sum team reward): at the end of every test-phase
//   decision each hider gets +1 when every hider is hidden, -1 otherwise, and each seeker gets the
//   opposite as group_reward; no other reward, and nobody is tagged.
// The seen-based rewards (hide, seen, baker) are paid in the test phase only: in the prep phase the
// seekers cannot act.
//
// Observations, the same four for both behaviors, every value in [-1, 1] (vector) or [0, 1]:
//  "vector" [20]: [0, 3) position: x / half_size, 2 y / height - 1, z / half_size;
//    [3, 6) velocity / max_speed; [6, 9) forward vector (unit, horizontal); [9, 11) sin and cos of
//    yaw; [11] dragging flag (holds a prop); [12] frame / episode_frames (or / clock_frames when
//    that is set, clipped at 1); [13] prep-phase flag;
//    [14, 17) the nearest opponent this agent sees (hider: seekers in its own cone, seeker: hiders)
//    relative to it in its own frame (right, up, forward) / vision_range; [17] 1 when one is seen
//    (else the three values before are 0); [18] 1 when an unlocked prop is in reach and in front
//    (lock would lock it), [19] 1 when a prop the hiders locked is (a hider's unlock would unlock
//    it): neither the rays nor the grids tell a locked prop from a free one, and without these a
//    hider in front of a prop cannot know whether to lock or leave it (`prop_cues` 0: both 0, and
//    the hiders' masks allow every option, as for the paper's agents). Values are clipped to
//    [-1, 1].
//  "objects" [84] (`object_obs` 1, the default; 0: all zeros, the paper's observations): what
//    OpenAI's agents observe of the world's entities, in the agent's own frame (right, up,
//    forward), positions / (2 half_size): per prop entry k < 4 (8 floats; 0 past the level's
//    props): relative centre [3], present, locked, held by another drone, and sin and cos of twice
//    the angle from the agent's forward to the panel's normal (a panel looks the same turned by
//    180 degrees); per opening entry k < 4 (11 floats): relative centre [3], open at the level,
//    closed now, and for an open one with a prop of its own index (the prop entry k that
//    own_first pairs with it; else 0): how far that prop is from standing in it (where a prop
//    locked unturned closes it), along the agent's right and forward, as x / (1 + |x|) of the
//    metres (0.1 m is 0.09: the shared scale of 1/24 per metre cannot tell a prop 10 cm short from
//    one in place), the opening's outward normal along the agent's right and forward, and cos and
//    sin of twice the angle from that normal to the panel's (1, 0: parallel to the wall);
//    the nearest teammate: relative centre [3] and present; the agent's slot one-hot
//    [4]. Each agent's own first: with n props (and n open openings, n = level), entry k < n is
//    prop (and opening) (k + slot) mod n, in arena.h's order, entries from n on are the rest in
//    order; so hiders that learned at level 1 to take the first prop to the first opening take
//    different props to different openings at level 2 (with one list for all they went for the
//    same prop). `owner_shift` s (0-3, default 0) makes it prop (k + slot + s) mod n, and so
//    hands each hider another's prop and opening (at level 2, s = 1 swaps them): with a trained
//    policy it tells a weak hider from a hard doorway.
//    The rays and grids see panels and holes only as "prop" and "wall" hits around the agent;
//    with these the hiders learn to bring a prop to a doorway far sooner (docs/results).
//  "rays" [119]: RaySensor with its defaults (17 rays over 360 degrees, 20 m, sphere radius 0.3);
//    it and both grids are zeros with `sensor_obs` 0 (default 1), and are then not computed.
//  "spatial_grid" [6, 12, 5] and "frontal_grid" [9, 8, 5]: GridSensor's spatial() and frontal()
//    presets (grid_sensor.h) over the surface points of every body (walls at 1 m, bodies at 0.3 m;
//    the floor and ceiling are not detectable: the vector carries the height), the agent's own
//    body left out.
//
// Metrics of an episode (SPEC section 8): tag_rate (1 when a hider was tagged), seen_fraction
// (share of test-phase frames in which some hider was seen), fort_rate (1 when every open opening
// was closed at the end of the prep phase), openings_closed (how many then), hidden_fraction (share
// of test-phase frames in which every hider in the game was hidden), tagged (count) and
// prop_start_offset (the offset the props started at: the episode's t at levels 1-2, else 1).
// Recording (set_recording): every body of the world with its pose at every frame, and the events
// grab, release, lock, unlock (body: the hider, other: the prop), tag (body: the hider), closed
// (other: the opening's index, 0-3 as in arena.h) and prep_end.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "env/drone/arena.h"
#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"
#include "env/drone/grid_sensor.h"
#include "env/drone/prop.h"
#include "env/drone/ray_sensor.h"
#include "env/drone/shape_snapshot.h"
#include "env/drone/surface_points.h"
#include "rl/env_api/env.h"
#include "rl/env_api/recording.h"

namespace rlt {

class HideAndSeek : public Env {
 public:
  enum Team { kHider = 0, kSeeker = 1 };
  static constexpr int kMaxHiders = 2;
  static constexpr int kMaxSeekers = 4;
  static constexpr int kVectorSize = 20;
  static constexpr int kMaxProps = 4;  // level 4
  static constexpr int kPropFloats = 8;
  static constexpr int kOpeningFloats = 11;
  // "objects": props, openings, the nearest teammate, own slot (see the header comment)
  static constexpr int kObjectsSize =
      kMaxProps * kPropFloats + drone::kNumOpenings * kOpeningFloats + 4 + kMaxSeekers;
  static constexpr int kFullEpisodeFrames = 3072;  // the game's `episode_frames` (SPEC section 4)
  static constexpr int kMaxEpisodeFrames = 6144;  // largest `episode_frames`
  static constexpr int kGrabBranch = 0;           // options: 0 release, 1 hold
  static constexpr int kLockBranch = 1;           // options: 0 none, 1 lock, 2 unlock
  // m, drone centre to prop centre where a hider grabs a panel face-on: the scripted hider's
  // approach, and push_shaping's place behind a prop
  static constexpr float kGrabStandoff = 1.1f;

  // one agent's drone and its state in the episode
  struct Agent {
    Team team = kHider;
    int slot = 0;
    bool present = false;                  // slot in use and not tagged
    std::unique_ptr<drone::DroneBody> drone;  // null when absent
    std::array<float, 4> thrust{};         // the decision's continuous action, held for its frames
  };

  HideAndSeek();
  ~HideAndSeek() override;

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override;
  void reset(StepView& out) override;
  void step(StepView& io) override;
  EpisodeMetrics episode_metrics() const override;
  bool write_scripted_actions(int behavior, BehaviorView& view) override;
  uint64_t physics_frames() const override { return total_frames_; }
  void set_recording(bool on) override { recording_on_ = on; }
  bool take_recording(EpisodeRecording& out) override;

  // state of the current episode, for tests and scripted policies
  drone::BulletWorld& world() { return *world_; }
  const drone::Arena& arena() const { return *arena_; }
  drone::PropSet& props() { return *props_; }
  const std::vector<btRigidBody*>& obstacles() const { return obstacles_; }
  Agent& agent(Team team, int slot) { return agents_[team == kHider ? slot : kMaxHiders + slot]; }
  const Agent& agent(Team team, int slot) const {
    return agents_[team == kHider ? slot : kMaxHiders + slot];
  }
  int num_agents(Team team) const { return num_agents_[team]; }
  long frame() const { return frame_; }
  long prep_frames() const { return prep_frames_; }
  bool in_prep() const { return frame_ < prep_frames_; }
  int level() const { return level_; }
  // whether open opening `o` is closed by a locked prop now, that for every opening, and how
  // many open ones are
  bool opening_closed(int o) const;
  // whether over half of open opening `o` is covered by a prop within reach of it, a locked one
  // with `locked_only` (what opening_closed asks), else any
  bool opening_covered(int o, bool locked_only) const;
  std::array<bool, drone::kNumOpenings> closed_openings() const;
  int count_closed() const;
  // true when some seeker in the game sees hider `h` now
  bool hider_seen(int h) const;

 private:
  struct Settings;
  void build_episode();
  // level 2 with prop_pairing 1: where props 0 and 1 start, given prop_start_offset `offset`,
  // the props' centre height and the room's inner half-size
  std::vector<btVector3> paired_level2_starts(float offset, float prop_y, float inner);
  // whether hider slot `hider` owns opening (or prop) `index` of the level's n: the one numbered
  // (hider + owner_shift) mod n, and every one past the hiders' count (nobody's, so everyone's)
  bool owns(int hider, int index, int n) const;
  // the props this agent's grab, lock and unlock may act on (PropSet's mask): a hider's own
  // with shared_props 0, else all
  unsigned props_allowed(const Agent& agent) const;
  // true when the agent unlocked a prop
  bool apply_grab_and_lock(Agent& agent, const int* discrete);
  void run_frame(StepView& io);
  void tag(Agent& hider, StepView& io);
  void check_openings(StepView& io);
  // at the end of the prep phase, how far each hider's building got (closed_own_in_prep_,
  // covered_own_at_prep_end_, own_gap_at_prep_end_); `closed`: closed_openings() then
  void measure_own_openings(const std::array<bool, drone::kNumOpenings>& closed);
  // close_reward_mode 1: the number of closed openings; 2: plus, per open opening not closed,
  // prop_shaping n(d) + reach_shaping n(e) + push_shaping n(b) + cover_shaping min(1, c / 0.5),
  // with d the distance from its centre to the nearest prop's, e from that prop's to the nearest
  // hider's, b from the place behind that prop (kGrabStandoff further from the opening) to the
  // nearest hider's, c the largest share an unlocked prop covers and n(x) = max(0, 1 - x /
  // shaping_range)
  // (`closed`: opening_closed of each opening, computed once by the caller)
  struct Potential {
    float total = 0.0f;                                  // summed as it is built
    std::array<float, drone::kNumOpenings> of_opening{};  // each opening's part
  };
  Potential opening_potential(const std::array<bool, drone::kNumOpenings>& closed) const;
  void pay_baker_rewards(StepView& io);
  void write_observation(BehaviorView& view, const Agent& agent);
  void write_objects(float* out, const Agent& agent) const;  // out: [kObjectsSize]
  void write_mask(BehaviorView& view, const Agent& agent) const;
  void end_episode(StepView& io, bool terminated);
  void record_frame();
  // the rewards of the decision just taken, on its last recorded frame
  void record_rewards(StepView& io);
  // the sensors' copies of the world (and closed_now_), refreshed once per step before
  // observations are written
  void update_sensor_scene();
  // an event for the recording: `body` did it to `other` (or to the thing numbered `index`)
  void record_event(const char* type, const btCollisionObject* body,
                    const btCollisionObject* other, int index = -1);
  static int agent_id(const Agent& a) { return a.team == kHider ? a.slot : kMaxHiders + a.slot; }

  EnvSpec spec_;
  std::mt19937_64 engine_;
  std::unique_ptr<Settings> settings_;
  drone::RaySensor rays_;
  drone::GridSensor spatial_grid_;
  drone::GridSensor frontal_grid_;
  drone::SurfacePoints points_;   // for the grids, updated before observations are written
  drone::ShapeSnapshot shapes_;   // for the rays, captured with points_

  std::unique_ptr<drone::BulletWorld> world_;
  std::unique_ptr<drone::Arena> arena_;
  std::unique_ptr<drone::PropSet> props_;
  std::vector<btRigidBody*> obstacles_;
  std::array<Agent, kMaxHiders + kMaxSeekers> agents_;  // hiders, then seekers

  int num_agents_[2] = {2, 2};
  int level_ = 1;
  long frame_ = 0;
  uint64_t total_frames_ = 0;  // since construction
  long prep_frames_ = 0;
  bool over_ = false;
  std::array<bool, drone::kNumOpenings> ever_closed_{};
  Potential potential_;  // close_reward_mode 1-2: opening_potential() at the last decision
  float episode_offset_ = 1.0f;  // the props' start offset this episode (1 at levels 3-4)
  std::array<bool, drone::kNumOpenings> closed_now_{};  // for "objects", at update_sensor_scene

  // metrics
  int tagged_ = 0;
  long test_frames_ = 0;
  long seen_frames_ = 0;
  long hidden_frames_ = 0;
  int closed_at_prep_end_ = 0;
  bool fort_ = false;
  // [hider slot]: every opening it is paid for (owns) closed when the prep phase ended; it
  // grabbed or locked a prop during the prep phase
  std::array<bool, kMaxHiders> closed_own_at_prep_end_{};
  std::array<bool, kMaxHiders> handled_in_prep_{};
  // [hider slot], where its building got to: every opening it owns closed at some decision of
  // the prep phase; covered over half by a prop, locked or not, when the prep phase ended; the
  // farthest of its openings from the prop nearest to it then (m)
  std::array<bool, kMaxHiders> closed_own_in_prep_{};
  std::array<bool, kMaxHiders> covered_own_at_prep_end_{};
  std::array<float, kMaxHiders> own_gap_at_prep_end_{};
  bool last_all_hidden_ = true;  // at the last test-phase frame (baker reward)

  // recording
  bool recording_on_ = false;
  EpisodeRecording recording_;
  std::vector<RecordedEvent> pending_events_;  // of the frame being run
  std::vector<const btCollisionObject*> recorded_initial_;  // [bodies] as the episode started
  std::vector<const btCollisionObject*> recorded_objects_;  // [bodies] null once removed
};

}  // namespace rlt
