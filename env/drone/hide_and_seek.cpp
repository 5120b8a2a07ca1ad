#include "env/drone/hide_and_seek.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "env/drone/drone_task.h"
#include "env/drone/hide_and_seek_scripted.h"
#include "env/drone/vision.h"
#include "rl/env_api/uniform_random.h"

namespace rlt {

using drone::kNumOpenings;

namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kSpawnHeight = 1.0f;  // drones start at this height (m)
constexpr int kSpawnAttempts = 2000;
constexpr float kClosedCover = 0.5f;  // an opening is closed when more than half is covered
constexpr float kCoverReach = 2.0f;   // m: a prop centred farther from an opening cannot cover it

// a prop standing in a doorway: its centre this far inside the wall's centre plane (the panel,
// 0.2 m thick, clears the wall's inner face and covers the doorway for covered_fraction)
constexpr float kInDoorway = 0.35f;
// footprint radii used to keep spawns apart (m)
constexpr float kDroneFootprint = 0.5f;
constexpr float kPropFootprint = 0.85f;
constexpr float kObstacleFootprint = 0.65f;

float clip1(float x) { return std::clamp(x, -1.0f, 1.0f); }

// metres squashed into (-1, 1): 0.1 m is 0.09, 1 m is 0.5, 5 m is 0.83
float soft_metres(float x) { return x / (1.0f + std::abs(x)); }

// A panel's orientation about the vertical, as cos and sin of twice the angle of its normal from
// `zero` (towards `quarter`, a right angle on): a panel looks the same turned half way round, so
// twice the angle has no jump. False (both left alone) when the normal is vertical.
struct DoubledAngle {
  float cos2 = 0.0f, sin2 = 0.0f;
};
bool doubled_angle(const btVector3& normal, const btVector3& zero, const btVector3& quarter,
                   DoubledAngle* out) {
  const float c = normal.dot(zero), s = normal.dot(quarter);
  const float norm = c * c + s * s;
  if (norm <= 1e-6f) return false;
  out->cos2 = clip1((c * c - s * s) / norm);  // rounding can take them a hair past 1
  out->sin2 = clip1(2 * s * c / norm);
  return true;
}

// a prop standing in `door` (unlocked, covering it, parallel to its wall), on the floor at prop_y
btVector3 standing_in(const drone::Opening& door, float prop_y) {
  const btVector3 p = door.centre - door.normal * kInDoorway;
  return btVector3(p.x(), prop_y, p.z());
}

// a floor point drawn in the room, at least 1 m from its inner faces (`inner` m from the centre)
btVector3 room_point(std::mt19937_64& engine, float inner, float prop_y) {
  return btVector3(uniform(engine, -inner + 1.0, inner - 1.0), prop_y,
                   uniform(engine, -inner + 1.0, inner - 1.0));
}

// a level-2 prop's own place keeps 2.5 m across the floor from every opening
bool far_from_openings(const btVector3& p, const std::vector<drone::Opening>& openings) {
  bool far = true;
  for (const auto& o : openings) {
    const btVector3 d = p - o.centre;
    far = far && (d.x() * d.x() + d.z() * d.z() >= 2.5f * 2.5f);
  }
  return far;
}

const char* kind_name(drone::Tag tag) {
  switch (tag) {
    case drone::kWall: return "wall";
    case drone::kProp: return "prop";
    case drone::kObstacle: return "obstacle";
    case drone::kHider: return "hider";
    case drone::kSeeker: return "seeker";
  }
  return "unknown";
}

}  // namespace

// the parameters of one episode, read and checked at reset
struct HideAndSeek::Settings {
  int decision_period = 3;
  int episode_frames = kFullEpisodeFrames;
  float prep_fraction = 0.4f;
  // frames over which the clock observation (vector [12]) runs from 0 to 1; 0 = episode_frames.
  // A fixed clock makes a shortened episode look like the start of a full one to the agents
  int clock_frames = 0;
  int reward_preset = 0;  // 0 paper, 1 baker
  float hide_reward = 0.001f;
  float close_reward = 0.1f;
  // 0 (the paper): close_reward the first time an opening becomes closed; 1 (held): whenever one
  // becomes closed, and taken back whenever it opens again; 2 (held and shaped): 1, plus the
  // shaping terms below (see opening_potential)
  int close_reward_mode = 0;
  float prop_shaping = 0.5f;   // mode 2: share held for a prop near an open opening
  float reach_shaping = 0.0f;  // mode 2: share held for a hider near that prop
  float cover_shaping = 0.0f;  // mode 2: share held for an unlocked prop covering the opening
  float push_shaping = 0.0f;   // mode 2: share held for a hider behind that prop (it pushes it)
  float shaping_range = 5.0f;  // m: nearness is 1 - distance / shaping_range, 0 beyond
  // m inside the wall's centre plane: a panel lined up behind an opening holds up to half the
  // cover share, graded from the closing test's 0.5 m (in full) down to 0 this deep; 0.5 = none
  float cover_depth = 0.5f;
  // mode 2: 1 = a locked prop short of closing keeps the shares it held unlocked (locking and
  // unlocking it pay nothing); 0 = only unlocked props hold shares
  bool lock_keeps_shaping = false;
  // 0 (the paper): every hider is paid the close reward of every opening; 1 (own): hider h only
  // that of its own opening, h mod the open ones (the one its objects observation lists first),
  // and every hider that of an opening no hider owns
  int close_credit = 0;
  // 1 (the paper's): a hider may grab, lock and unlock any prop; 0: only its own props, owned
  // as close_credit owns openings (prop i goes with opening i)
  bool shared_props = true;
  float fort_reward = 0.0f;    // per opening closed when the prep phase ends, to every hider
  float unlock_cost = 0.0f;    // taken from a hider per prop it unlocks
  float tagged_reward = -1.0f;
  float seen_reward = 0.001f;
  float unseen_reward = 0.0f;  // per seeker and test-phase frame in which no hider is seen
  bool assault_weighting = false;
  float tag_reward = 1.0f;
  bool end_on_tag = true;
  float tag_distance = 0.1f;
  float vision_range = drone::kDefaultVisionRange;
  float vision_cone = drone::kDefaultConeDegrees;
  float hider_outside_chance = 0.0f;  // chance that a hider starts just outside the room
  float prop_start_offset = 1.0f;     // levels 1-2: 0 = props start in the doorways, 1 = own place
  float prop_start_spread = 0.0f;     // chance that an episode's offset is uniform in [0, offset]
  float prop_start_far_chance = 0.0f;  // chance that it is uniform in [offset, far offset] instead
  float prop_start_far_offset = 1.0f;
  // level 2: 0 = prop i gets the i-th own place drawn; 1 = the places go to the props so that the
  // ways from doorway i to prop i are least in total (paired_level2_starts)
  int prop_pairing = 0;
  int owner_shift = 0;
  // chance that an episode's doorways trade walls (ArenaParams::doorways_swapped): level 1's one
  // doorway is then in the +z wall
  float doorway_swap_chance = 0.0f;
  bool prop_cues = true;  // vector [18, 20) and the hiders' masks say what prop actions would do
  bool object_obs = true;  // the "objects" observation (else zeros)
  bool sensor_obs = true;  // the rays and both grids (else zeros)
  bool hider_slot_obs = true;  // a hider's objects end with its slot one-hot (else zeros)
  bool latched_grab = false;  // grab option 0 keeps a held prop; only a lock lets it go
  bool square_grab = false;   // a grab swings the panel face-on to the drone (PropParams)
  bool regrip = false;  // a decision's unlock acts before its grab: unlock and hold take it back
};

namespace {
// surface points for the grids; the static ones are kept inside the arena's inner volume
drone::SurfacePointsParams surface_points_params() {
  const drone::ArenaParams arena;
  drone::SurfacePointsParams p;
  const float h = arena.half_size + 0.01f;
  p.static_keep_min = btVector3(-h, -0.01f, -h);
  p.static_keep_max = btVector3(h, arena.height + 0.01f, h);
  return p;
}
std::vector<int> grid_shape(const drone::GridSensor& g) {
  return {g.lat_cells(), g.lon_cells(), drone::kNumTags};
}
}  // namespace

HideAndSeek::HideAndSeek()
    : settings_(std::make_unique<Settings>()),
      spatial_grid_(drone::GridSensorParams::spatial()),
      frontal_grid_(drone::GridSensorParams::frontal()),
      points_(surface_points_params()) {
  spec_.name = "HideAndSeek";
  BehaviorSpec hider;
  hider.name = "Hider";
  hider.observations.push_back({"vector", {kVectorSize}, ObservationKind::kVector, -1.f, 1.f});
  hider.observations.push_back({"objects", {kObjectsSize}, ObservationKind::kVector, -1.f, 1.f});
  hider.observations.push_back({"rays", {rays_.size()}, ObservationKind::kVector, 0.f, 1.f});
  hider.observations.push_back(
      {"spatial_grid", grid_shape(spatial_grid_), ObservationKind::kGrid, 0.f, 1.f});
  hider.observations.push_back(
      {"frontal_grid", grid_shape(frontal_grid_), ObservationKind::kGrid, 0.f, 1.f});
  hider.action.continuous_size = 4;
  hider.action.discrete_branches = {2, 3};
  hider.agent_slots = kMaxHiders;
  BehaviorSpec seeker = hider;
  seeker.name = "Seeker";
  seeker.agent_slots = kMaxSeekers;
  spec_.behaviors = {hider, seeker};
  spec_.max_episode_steps = kMaxEpisodeFrames;  // decision_period 1
  spec_.default_parameters = {
      {"level", 1.f},
      {"num_hiders", 2.f},
      {"num_seekers", 2.f},
      {"episode_frames", float(kFullEpisodeFrames)},
      {"decision_period", 3.f},
      {"prep_fraction", 0.4f},
      {"clock_frames", 0.f},
      {"reward_preset", 0.f},
      {"hide_reward", 0.001f},
      {"hide_reward_level4", 0.0005f},
      {"close_reward", 0.1f},
      {"close_reward_mode", 0.f},
      {"prop_shaping", 0.5f},
      {"reach_shaping", 0.f},
      {"cover_shaping", 0.f},
      {"push_shaping", 0.f},
      {"shaping_range", 5.f},
      {"cover_depth", 0.5f},
      {"lock_keeps_shaping", 0.f},
      {"close_credit", 0.f},
      {"shared_props", 1.f},
      {"fort_reward", 0.f},
      {"unlock_cost", 0.f},
      {"tagged_reward", -1.f},
      {"seen_reward", 0.001f},
      {"unseen_reward", 0.f},
      {"assault_weighting", 0.f},
      {"tag_reward", 1.f},
      {"end_on_tag", 1.f},
      {"tag_distance", 0.1f},
      {"vision_range", drone::kDefaultVisionRange},
      {"vision_cone", drone::kDefaultConeDegrees},
      {"hider_outside_chance", -1.f},
      {"prop_start_offset", 1.f},
      {"prop_start_spread", 0.f},
      {"prop_start_far_chance", 0.f},
      {"prop_start_far_offset", 1.f},
      {"prop_pairing", 0.f},
      {"owner_shift", 0.f},
      {"doorway_swap_chance", 0.f},
      {"prop_cues", 1.f},
      {"object_obs", 1.f},
      {"sensor_obs", 1.f},
      {"hider_slot_obs", 1.f},
      {"latched_grab", 0.f},
      {"square_grab", 0.f},
      {"regrip", 0.f},
  };
  // SPEC section 8: both strategies are dated in games of the full length (a curriculum or a
  // team's turn may shorten the test phase; a shorter one leaves the seekers less time to tag):
  // the game SPEC section 4 describes. Chasing is dated in seeker steps, shelter in hider steps
  // and only counts at level 2 and above (level 1's single doorway is the curriculum's first
  // lesson) with the props starting at their own places (prop_start_offset 1: not placed in the
  // openings for the hiders) where any hider may move any prop (the paper's shared_props: a
  // lesson may narrow it)
  spec_.strategies = {
      {"running_and_chasing", "tag_rate", "Seeker", 0.5f, 100,
       {{"episode_frames", float(kFullEpisodeFrames)}}},
      {"shelter", "fort_rate", "Hider", 0.5f, 100,
       {{"level", 2.f},
        {"prop_start_offset", 1.f},
        {"episode_frames", float(kFullEpisodeFrames)},
        {"shared_props", 1.f}}},
  };
  world_ = std::make_unique<drone::BulletWorld>();
}

HideAndSeek::~HideAndSeek() {
  // the prop set releases its constraints before the world goes
  props_.reset();
  for (Agent& a : agents_) a.drone.reset();
}

void HideAndSeek::seed(uint64_t seed) { engine_.seed(seed); }

namespace {

// where spawns may go: inside the room, outside it, or a band just outside it
enum class Region { kRoom, kOutside, kNearOutside, kAnywhere };

struct Footprint {
  float x, z, r;
};

class SpawnPlanner {
 public:
  SpawnPlanner(const drone::ArenaParams& arena, std::mt19937_64& engine)
      : arena_(arena), engine_(engine) {}

  // a free (x, z) for a footprint of radius r in `region`; throws when none is found
  btVector3 place(Region region, float r, float y) {
    const float wall = 0.5f * arena_.wall_thickness;
    const float inner = arena_.room_half - wall;  // inner face of the room's walls
    const float outer = arena_.room_half + wall;  // outer face
    const float bound = arena_.half_size;
    for (int attempt = 0; attempt < kSpawnAttempts; ++attempt) {
      float x, z;
      if (region == Region::kRoom) {
        x = uniform(engine_, -inner + r, inner - r);
        z = uniform(engine_, -inner + r, inner - r);
      } else {
        const float lim = region == Region::kNearOutside ? outer + 2.5f + r : bound - r;
        x = uniform(engine_, -lim, lim);
        z = uniform(engine_, -lim, lim);
        const float box = std::max(std::abs(x), std::abs(z));
        const float clearance = region == Region::kOutside ? 2.0f : 0.1f;
        if (region != Region::kAnywhere && box < outer + r + clearance) continue;
        // anywhere: not across a room wall
        if (region == Region::kAnywhere && box > inner - r && box < outer + r) continue;
        if (std::abs(x) > bound - r || std::abs(z) > bound - r) continue;
      }
      if (free(x, z, r)) {
        taken_.push_back({x, z, r});
        return btVector3(x, y, z);
      }
    }
    throw std::runtime_error("HideAndSeek: no free spawn place found (too many bodies?)");
  }
  void take(float x, float z, float r) { taken_.push_back({x, z, r}); }

 private:
  bool free(float x, float z, float r) const {
    for (const Footprint& f : taken_) {
      const float dx = f.x - x, dz = f.z - z;
      if (dx * dx + dz * dz < (f.r + r) * (f.r + r)) return false;
    }
    return true;
  }

  const drone::ArenaParams& arena_;
  std::mt19937_64& engine_;
  std::vector<Footprint> taken_;
};

}  // namespace

std::vector<btVector3> HideAndSeek::paired_level2_starts(float offset, float prop_y,
                                                        float inner) {
  // the same places as prop_pairing 0 (in the room, at least 2.5 m from every opening, the props'
  // start spots clear of each other), drawn for both props before either is given one; the
  // panels are alike and their yaws are drawn afterwards, so the pairing changes which prop the
  // objects observation calls each hider's own, not the world the hiders start in
  const auto& openings = arena_->openings();
  const auto own_place = [&] {
    for (int attempt = 0;; ++attempt) {
      const btVector3 p = room_point(engine_, inner, prop_y);
      if (far_from_openings(p, openings)) return p;
      if (attempt > kSpawnAttempts) throw std::runtime_error("HideAndSeek: no prop place");
    }
  };
  const btVector3 door[2] = {standing_in(openings[0], prop_y), standing_in(openings[1], prop_y)};
  for (int attempt = 0;; ++attempt) {
    std::vector<btVector3> place = {own_place(), own_place()};  // [2]
    const float kept = (place[0] - door[0]).length() + (place[1] - door[1]).length();
    const float swapped = (place[1] - door[0]).length() + (place[0] - door[1]).length();
    if (swapped < kept) std::swap(place[0], place[1]);
    std::vector<btVector3> start(2);  // [2] prop i: offset of the way from doorway i to its place
    for (int i = 0; i < 2; ++i)
      start[i] = offset < 1.0f ? door[i] + offset * (place[i] - door[i]) : place[i];
    if ((start[0] - start[1]).length() > 2 * kPropFootprint) return start;
    if (attempt > kSpawnAttempts) throw std::runtime_error("HideAndSeek: no prop place");
  }
}

void HideAndSeek::build_episode() {
  Settings& s = *settings_;
  level_ = drone::int_parameter(*this, "level", drone::kMinLevel, drone::kMaxLevel);
  num_agents_[kHider] = drone::int_parameter(*this, "num_hiders", 1, kMaxHiders);
  num_agents_[kSeeker] = drone::int_parameter(*this, "num_seekers", 1, kMaxSeekers);
  s.decision_period = drone::int_parameter(*this, "decision_period", 1, drone::kMaxDecisionPeriod);
  s.episode_frames = drone::int_parameter(*this, "episode_frames", 30, kMaxEpisodeFrames);
  s.prep_fraction = drone::float_parameter(*this, "prep_fraction", 0.0f, 0.9f);
  s.clock_frames = drone::int_parameter(*this, "clock_frames", 0, kMaxEpisodeFrames);
  s.reward_preset = drone::int_parameter(*this, "reward_preset", 0, 1);
  s.hide_reward = level_ == 4 ? parameter("hide_reward_level4") : parameter("hide_reward");
  s.close_reward = parameter("close_reward");
  s.close_reward_mode = drone::int_parameter(*this, "close_reward_mode", 0, 2);
  s.prop_shaping = drone::float_parameter(*this, "prop_shaping", 0.0f, 1.0f);
  s.reach_shaping = drone::float_parameter(*this, "reach_shaping", 0.0f, 1.0f);
  s.cover_shaping = drone::float_parameter(*this, "cover_shaping", 0.0f, 1.0f);
  s.push_shaping = drone::float_parameter(*this, "push_shaping", 0.0f, 1.0f);
  const float shares = s.prop_shaping + s.reach_shaping + s.cover_shaping + s.push_shaping;
  if (shares > 1.0f)
    throw std::invalid_argument(
        "HideAndSeek: parameters prop_shaping + reach_shaping + cover_shaping + push_shaping must "
        "be at most 1 (a closed opening holds 1), got " +
        std::to_string(shares));
  s.cover_depth = drone::float_parameter(*this, "cover_depth", 0.5f, 3.0f);
  s.shaping_range = drone::float_parameter(*this, "shaping_range", 0.1f, 50.0f);
  s.lock_keeps_shaping = drone::int_parameter(*this, "lock_keeps_shaping", 0, 1) == 1;
  s.close_credit = drone::int_parameter(*this, "close_credit", 0, 1);
  s.shared_props = drone::int_parameter(*this, "shared_props", 0, 1) == 1;
  s.tagged_reward = parameter("tagged_reward");
  s.seen_reward = parameter("seen_reward");
  s.unseen_reward = parameter("unseen_reward");
  s.assault_weighting = drone::int_parameter(*this, "assault_weighting", 0, 1) == 1;
  s.tag_reward = parameter("tag_reward");
  s.end_on_tag = drone::int_parameter(*this, "end_on_tag", 0, 1) == 1;
  s.tag_distance = drone::float_parameter(*this, "tag_distance", 0.0f, 2.0f);
  s.vision_range = drone::float_parameter(*this, "vision_range", 0.1f, 100.0f);
  s.vision_cone = drone::float_parameter(*this, "vision_cone", 1.0f, 360.0f);
  s.prop_start_offset = drone::float_parameter(*this, "prop_start_offset", 0.0f, 1.0f);
  s.prop_start_spread = drone::float_parameter(*this, "prop_start_spread", 0.0f, 1.0f);
  s.prop_start_far_chance = drone::float_parameter(*this, "prop_start_far_chance", 0.0f, 1.0f);
  s.prop_start_far_offset = drone::float_parameter(*this, "prop_start_far_offset", 0.0f, 1.0f);
  s.prop_pairing = drone::int_parameter(*this, "prop_pairing", 0, 1);
  s.owner_shift = drone::int_parameter(*this, "owner_shift", 0, 3);
  s.doorway_swap_chance = drone::float_parameter(*this, "doorway_swap_chance", 0.0f, 1.0f);
  s.prop_cues = drone::int_parameter(*this, "prop_cues", 0, 1) == 1;
  s.object_obs = drone::int_parameter(*this, "object_obs", 0, 1) == 1;
  s.sensor_obs = drone::int_parameter(*this, "sensor_obs", 0, 1) == 1;
  s.hider_slot_obs = drone::int_parameter(*this, "hider_slot_obs", 0, 1) == 1;
  s.latched_grab = drone::int_parameter(*this, "latched_grab", 0, 1) == 1;
  s.square_grab = drone::int_parameter(*this, "square_grab", 0, 1) == 1;
  s.regrip = drone::int_parameter(*this, "regrip", 0, 1) == 1;
  // -1: the level's own (0 at levels 1 and 2, 0.5 at 3 and 4)
  const float outside = parameter("hider_outside_chance");
  if (outside != -1.0f && !(outside >= 0.0f && outside <= 1.0f))
    throw std::invalid_argument(
        "HideAndSeek: parameter hider_outside_chance must be -1 (the "
        "level's own) or in [0, 1], got " +
        std::to_string(outside));
  s.hider_outside_chance = outside == -1.0f ? (level_ >= 3 ? 0.5f : 0.0f) : outside;
  s.fort_reward = parameter("fort_reward");
  s.unlock_cost = drone::float_parameter(*this, "unlock_cost", 0.0f, 10.0f);
  for (const char* name : {"hide_reward", "hide_reward_level4", "close_reward", "fort_reward",
                           "tagged_reward", "seen_reward", "unseen_reward", "tag_reward"}) {
    if (!std::isfinite(parameter(name)))
      throw std::invalid_argument("HideAndSeek: parameter " + std::string(name) +
                                  " must be finite");
  }
  prep_frames_ = std::lround(s.prep_fraction * s.episode_frames);

  // a fresh world: bodies added in the same order give the same trajectory
  props_.reset();
  for (Agent& a : agents_) a.drone.reset();
  obstacles_.clear();
  world_->reset();
  drone::ArenaParams arena_params;
  arena_params.level = level_;
  // the engine is only drawn from when the chance is on, so runs without it keep their episodes
  arena_params.doorways_swapped =
      s.doorway_swap_chance > 0.0f && uniform01(engine_) < s.doorway_swap_chance;
  arena_ = std::make_unique<drone::Arena>(*world_, arena_params);
  drone::PropParams prop_params;
  prop_params.square_hold = s.square_grab;
  props_ = std::make_unique<drone::PropSet>(*world_, prop_params);

  SpawnPlanner planner(arena_params, engine_);
  const auto& openings = arena_->openings();
  const float prop_y = props_->params().half.y() + 0.01f;
  const float wall = 0.5f * arena_params.wall_thickness;
  const float inner = arena_params.room_half - wall;
  const int num_props = level_;
  // levels 1 and 2, prop_start_offset t < 1: prop i starts the fraction t of the way from standing
  // in doorway i (unlocked, covering it, parallel to its wall) to its own start place
  // (prop_start_spread: this episode's t drawn uniformly from [0, t] instead, with that chance;
  // else prop_start_far_chance: from [t, max(t, prop_start_far_offset)], with that chance; the
  // engine is only drawn from for a chance that is on, so runs without them keep their episodes)
  float offset = s.prop_start_offset;
  const auto chance = [&](float p) {
    return level_ <= 2 && p > 0.0f && uniform(engine_, 0.0, 1.0) < static_cast<double>(p);
  };
  if (chance(s.prop_start_spread)) {
    offset = static_cast<float>(uniform(engine_, 0.0, static_cast<double>(offset)));
  } else if (chance(s.prop_start_far_chance)) {
    const float far = std::max(offset, s.prop_start_far_offset);
    offset = static_cast<float>(
        uniform(engine_, static_cast<double>(offset), static_cast<double>(far)));
  }
  episode_offset_ = level_ <= 2 ? offset : 1.0f;
  const auto in_doorway = [&](int i) { return standing_in(openings[i], prop_y); };
  if (level_ == 1) {
    // next to doorway 0, inside the room, parallel to its wall, beside the doorway
    const drone::Opening& door = openings[0];
    const btVector3 across = btVector3(0, 1, 0).cross(door.normal);
    btVector3 p = door.centre - door.normal * 1.2f + across * 1.6f;
    if (offset < 1.0f) p = in_doorway(0) + offset * (p - in_doorway(0));
    props_->add(btVector3(p.x(), prop_y, p.z()), 0.0f);
    planner.take(p.x(), p.z(), kPropFootprint);
  } else {
    // prop_pairing 1, level 2: both own places are drawn first and then given to the props so
    // that the ways from each doorway to its prop's place are least in total
    std::vector<btVector3> paired;
    if (level_ == 2 && s.prop_pairing == 1) paired = paired_level2_starts(offset, prop_y, inner);
    for (int i = 0; i < num_props; ++i) {
      btVector3 p;
      if (!paired.empty()) {
        p = paired[i];
        planner.take(p.x(), p.z(), kPropFootprint);
      } else if (level_ == 2) {
        // in the room, at least 2.5 m from every opening
        for (int attempt = 0;; ++attempt) {
          p = room_point(engine_, inner, prop_y);
          const bool far = far_from_openings(p, openings);
          if (offset < 1.0f) p = in_doorway(i) + offset * (p - in_doorway(i));
          bool clear = true;
          for (int j = 0; j < props_->size(); ++j)
            clear = clear && (p - (*props_)[j].position()).length() > 2 * kPropFootprint;
          if (far && clear) break;
          if (attempt > kSpawnAttempts) throw std::runtime_error("HideAndSeek: no prop place");
        }
        planner.take(p.x(), p.z(), kPropFootprint);
      } else {
        p = planner.place(level_ == 3 ? Region::kRoom : Region::kAnywhere, kPropFootprint, prop_y);
      }
      float yaw = static_cast<float>(uniform(engine_, -kPi, kPi));
      if (level_ == 2 && offset < 1.0f) {
        // turned the same fraction of the way from parallel to the doorway's wall (-z, +z: yaw
        // 0) to its own yaw, the short way round (a panel turned by pi is the same panel)
        const float half_turn = yaw - kPi * std::round(yaw / kPi);  // in [-pi/2, pi/2]
        yaw = offset * half_turn;
      }
      props_->add(p, yaw);
    }
  }
  const int num_obstacles = level_ == 3 ? 3 : level_ == 4 ? 5 : 0;
  drone::ObstacleParams obstacle;
  for (int i = 0; i < num_obstacles; ++i) {
    const btVector3 p = planner.place(Region::kAnywhere, kObstacleFootprint, obstacle.half.y());
    obstacles_.push_back(
        drone::add_obstacle(*world_, p, static_cast<float>(uniform(engine_, -kPi, kPi)), obstacle));
  }
  for (int t = 0; t < 2; ++t) {
    for (int slot = 0; slot < (t == kHider ? kMaxHiders : kMaxSeekers); ++slot) {
      Agent& a = agent(static_cast<Team>(t), slot);
      a.team = static_cast<Team>(t);
      a.slot = slot;
      a.present = slot < num_agents_[t];
      a.thrust = {};
      if (!a.present) continue;
      Region region = Region::kOutside;
      if (t == kHider) {
        region = Region::kRoom;
        if (s.hider_outside_chance > 0.0f && uniform01(engine_) < s.hider_outside_chance)
          region = Region::kNearOutside;
      }
      const btVector3 p = planner.place(region, kDroneFootprint, kSpawnHeight);
      const float yaw = static_cast<float>(uniform(engine_, -kPi, kPi));
      a.drone = std::make_unique<drone::DroneBody>(*world_, p, yaw,
                                                   t == kHider ? drone::kHider : drone::kSeeker);
    }
  }

  frame_ = 0;
  over_ = false;
  ever_closed_ = {};
  tagged_ = 0;
  test_frames_ = seen_frames_ = hidden_frames_ = 0;
  closed_at_prep_end_ = 0;
  fort_ = false;
  closed_own_at_prep_end_.fill(false);
  handled_in_prep_.fill(false);
  closed_own_in_prep_.fill(false);
  covered_own_at_prep_end_.fill(false);
  own_gap_at_prep_end_.fill(0.0f);
  if (s.close_reward_mode != 0) {  // the potential where the props start
    potential_ = opening_potential(closed_openings());
  }
  // seekers are frozen in the prep phase
  const bool prep = prep_frames_ > 0;
  for (int slot = 0; slot < num_agents_[kSeeker]; ++slot) {
    btRigidBody& body = agent(kSeeker, slot).drone->body();
    body.setLinearFactor(prep ? btVector3(0, 0, 0) : btVector3(1, 1, 1));
    body.setAngularFactor(prep ? btVector3(0, 0, 0) : btVector3(0, 1, 0));
  }

  if (recording_on_) {
    recording_ = EpisodeRecording();
    recording_.env = spec_.name;
    recording_.frame_rate = 1.0f / world_->dt();
    const auto& objects = world_->world().getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) {
      const btCollisionObject* o = objects[i];
      RecordedBody body;
      body.kind = kind_name(drone::tag_of(*o));
      body.dynamic = !o->isStaticObject();
      const btCollisionShape* shape = o->getCollisionShape();
      if (shape->getShapeType() == SPHERE_SHAPE_PROXYTYPE) {
        body.shape = "sphere";
        const float d = 2 * static_cast<const btSphereShape*>(shape)->getRadius();
        body.size = {d, d, d};
      } else {
        body.shape = "box";
        const btVector3 h = static_cast<const btBoxShape*>(shape)->getHalfExtentsWithMargin();
        body.size = {2 * h.x(), 2 * h.y(), 2 * h.z()};
      }
      for (const Agent& a : agents_)
        if (a.drone && &a.drone->body() == o) {
          body.agent_id = agent_id(a);
          body.vision_cone_degrees = settings_->vision_cone;
          body.vision_range = settings_->vision_range;
        }
      recording_.bodies.push_back(body);
      recorded_objects_.push_back(o);
      recorded_initial_.push_back(o);
    }
    for (const drone::Opening& o : arena_->openings()) {
      RecordedOpening opening;
      opening.kind = o.kind == drone::Opening::kDoorway ? "doorway" : "window";
      opening.centre = {float(o.centre.x()), float(o.centre.y()), float(o.centre.z())};
      opening.normal = {float(o.normal.x()), float(o.normal.y()), float(o.normal.z())};
      opening.width = o.width;
      opening.height = o.height;
      opening.open = o.open;
      recording_.openings.push_back(opening);
    }
    pending_events_.clear();
    record_frame();
  }
}

void HideAndSeek::reset(StepView& out) {
  recorded_objects_.clear();
  recorded_initial_.clear();
  build_episode();
  update_sensor_scene();
  for (int t = 0; t < 2; ++t) {
    BehaviorView& view = out[t];
    for (int slot = 0; slot < view.slots(); ++slot) {
      const Agent& a = agent(static_cast<Team>(t), slot);
      if (!a.present) continue;
      view.step_type(slot) = StepType::kFirst;
      view.agent_id(slot) = agent_id(a);
      view.group_id(slot) = t;
      write_observation(view, a);
      write_mask(view, a);
    }
  }
}

bool HideAndSeek::owns(int hider, int index, int n) const {
  return index >= num_agents_[kHider] || (hider + settings_->owner_shift) % n == index;
}

unsigned HideAndSeek::props_allowed(const Agent& a) const {
  if (a.team != kHider || settings_->shared_props) return drone::kAllProps;
  unsigned allowed = 0;
  const int n = props_->size();
  for (int i = 0; i < n && i < 32; ++i)
    if (owns(a.slot, i, n)) allowed |= 1u << i;
  return allowed;
}

bool HideAndSeek::apply_grab_and_lock(Agent& a, const int* discrete) {
  if (a.team != kHider) return false;  // the mask forbids it; ignore a forbidden choice
  drone::DroneBody& d = *a.drone;
  const unsigned allowed = props_allowed(a);
  const int team = static_cast<int>(kHider);
  const auto unlock = [&] {
    const int i = props_->unlock(d, team, allowed);
    if (i >= 0) record_event("unlock", &d.body(), (*props_)[i].body);
    return i >= 0;
  };
  // with regrip the unlock comes first, so a hold in the same decision can take the freed prop
  const bool unlock_first = settings_->regrip && discrete[kLockBranch] == 2;
  bool unlocked = unlock_first && unlock();
  const int before = props_->held_by(d);
  if (discrete[kGrabBranch] == 1) {
    const int got = props_->grab(d, allowed);
    if (got >= 0 && got != before) {
      record_event("grab", &d.body(), (*props_)[got].body);
      handled_in_prep_[a.slot] = handled_in_prep_[a.slot] || in_prep();
    }
  } else if (before >= 0 && !settings_->latched_grab) {
    props_->release(d);
    record_event("release", &d.body(), (*props_)[before].body);
  }
  if (discrete[kLockBranch] == 1) {
    const int i = props_->lock(d, team, allowed);
    if (i >= 0) {
      record_event("lock", &d.body(), (*props_)[i].body);
      handled_in_prep_[a.slot] = handled_in_prep_[a.slot] || in_prep();
    }
  } else if (discrete[kLockBranch] == 2 && !unlock_first) {
    unlocked = unlock();
  }
  return unlocked;
}

void HideAndSeek::record_event(const char* type, const btCollisionObject* body,
                               const btCollisionObject* other, int index) {
  if (!recording_on_) return;
  auto find = [&](const btCollisionObject* o) {
    for (size_t i = 0; i < recorded_initial_.size(); ++i)
      if (o != nullptr && recorded_initial_[i] == o) return static_cast<int>(i);
    return -1;
  };
  RecordedEvent e;
  e.type = type;
  e.body = find(body);
  e.other = other != nullptr ? find(other) : index;
  pending_events_.push_back(e);
}

bool HideAndSeek::hider_seen(int h) const {
  const Agent& hider = agent(kHider, h);
  if (!hider.present) return false;
  for (int s = 0; s < num_agents_[kSeeker]; ++s) {
    const Agent& seeker = agent(kSeeker, s);
    if (seeker.present && drone::sees(*world_, seeker.drone->body(), hider.drone->body(),
                                      settings_->vision_cone, settings_->vision_range))
      return true;
  }
  return false;
}

void HideAndSeek::measure_own_openings(const std::array<bool, kNumOpenings>& closed) {
  const int num_open = arena_->num_open();
  const auto nearest_prop = [&](int o) {  // m from the opening's centre
    float nearest = std::numeric_limits<float>::infinity();
    for (int i = 0; i < props_->size(); ++i)
      nearest = std::min(nearest, ((*props_)[i].position() - arena_->openings()[o].centre).length());
    return nearest;
  };
  for (int h = 0; h < kMaxHiders; ++h) {
    if (!agent(kHider, h).present) continue;
    bool once = true, cover = true;
    float gap = 0.0f;
    for (int o = 0; o < num_open; ++o) {
      if (!owns(h, o, num_open)) continue;
      once = once && (ever_closed_[o] || closed[o]);
      cover = cover && (closed[o] || opening_covered(o, false));
      gap = std::max(gap, nearest_prop(o));
    }
    closed_own_in_prep_[h] = once;
    covered_own_at_prep_end_[h] = cover;
    own_gap_at_prep_end_[h] = std::isfinite(gap) ? gap : 0.0f;
  }
}

bool HideAndSeek::opening_closed(int o) const { return opening_covered(o, true); }

bool HideAndSeek::opening_covered(int o, bool locked_only) const {
  const drone::Opening& opening = arena_->openings()[o];
  if (!opening.open) return false;
  for (int i = 0; i < props_->size(); ++i) {
    const drone::Prop& prop = (*props_)[i];
    if (locked_only && !prop.locked()) continue;
    const btVector3 d = prop.position() - opening.centre;
    if (d.length() > kCoverReach) continue;  // too far to cover it
    if (drone::covered_fraction(opening, *prop.body) > kClosedCover) return true;
  }
  return false;
}

std::array<bool, kNumOpenings> HideAndSeek::closed_openings() const {
  std::array<bool, kNumOpenings> closed{};
  for (int o = 0; o < kNumOpenings; ++o) closed[o] = opening_closed(o);
  return closed;
}

int HideAndSeek::count_closed() const {
  const std::array<bool, kNumOpenings> closed = closed_openings();
  return static_cast<int>(std::count(closed.begin(), closed.end(), true));
}

void HideAndSeek::tag(Agent& hider, StepView& io) {
  const Settings& s = *settings_;
  BehaviorView& hv = io[kHider];
  hv.reward(hider.slot) += s.tagged_reward;
  hv.terminated(hider.slot) = 1;
  hv.step_type(hider.slot) = StepType::kLast;
  update_sensor_scene();
  write_observation(hv, hider);
  BehaviorView& sv = io[kSeeker];
  for (int slot = 0; slot < num_agents_[kSeeker]; ++slot)
    if (agent(kSeeker, slot).present) sv.group_reward(slot) += s.tag_reward;
  record_event("tag", &hider.drone->body(), nullptr);
  props_->release(*hider.drone);
  for (size_t i = 0; i < recorded_objects_.size(); ++i)
    if (recorded_objects_[i] == &hider.drone->body()) recorded_objects_[i] = nullptr;
  world_->remove_body(&hider.drone->body());
  hider.drone.reset();
  hider.present = false;
  ++tagged_;
}

void HideAndSeek::run_frame(StepView& io) {
  const Settings& s = *settings_;
  for (Agent& a : agents_) {
    if (!a.present) continue;
    if (a.team == kSeeker && in_prep()) continue;  // frozen
    a.drone->apply_action(a.thrust[0], a.thrust[1], a.thrust[2], a.thrust[3]);
  }
  world_->step_frame();
  ++frame_;
  ++total_frames_;
  if (frame_ == prep_frames_) {
    // the prep phase ends: measure the fort, free the seekers
    const std::array<bool, kNumOpenings> closed = closed_openings();
    const int num_open = arena_->num_open();
    closed_at_prep_end_ = static_cast<int>(std::count(closed.begin(), closed.end(), true));
    fort_ = closed_at_prep_end_ == num_open;
    for (int h = 0; h < kMaxHiders; ++h) {
      bool all = agent(kHider, h).present;
      for (int o = 0; o < num_open && all; ++o) all = !owns(h, o, num_open) || closed[o];
      closed_own_at_prep_end_[h] = all;
    }
    measure_own_openings(closed);
    // the fort the seekers will meet: what keeping the openings closed through the prep is for
    if (s.reward_preset == 0 && s.fort_reward != 0.0f && closed_at_prep_end_ > 0) {
      for (int h = 0; h < kMaxHiders; ++h)
        if (agent(kHider, h).present)
          io[kHider].reward(h) += s.fort_reward * static_cast<float>(closed_at_prep_end_);
    }
    for (int slot = 0; slot < num_agents_[kSeeker]; ++slot) {
      btRigidBody& body = agent(kSeeker, slot).drone->body();
      body.setLinearFactor(btVector3(1, 1, 1));
      body.setAngularFactor(btVector3(0, 1, 0));
    }
    record_event("prep_end", nullptr, nullptr);
  }
  if (in_prep()) return;

  // test phase: tags, then seeing
  bool tagged_now = false;
  for (int h = 0; h < kMaxHiders; ++h) {
    Agent& hider = agent(kHider, h);
    if (!hider.present || s.reward_preset == 1) continue;
    const btVector3 p = hider.drone->position();
    const float reach = 2 * hider.drone->params().radius + s.tag_distance;
    for (int k = 0; k < num_agents_[kSeeker]; ++k) {
      const Agent& seeker = agent(kSeeker, k);
      if ((seeker.drone->position() - p).length() <= reach) {
        tag(hider, io);
        tagged_now = true;
        break;
      }
    }
  }
  ++test_frames_;
  bool any_seen = false, all_hidden = true;
  for (int h = 0; h < kMaxHiders; ++h) {
    Agent& hider = agent(kHider, h);
    if (!hider.present) continue;
    bool seen = false;
    for (int k = 0; k < num_agents_[kSeeker]; ++k) {
      const Agent& seeker = agent(kSeeker, k);
      if (!drone::sees(*world_, seeker.drone->body(), hider.drone->body(), s.vision_cone,
                       s.vision_range))
        continue;
      seen = true;
      if (s.reward_preset == 0) {
        float w = 1.0f;
        if (s.assault_weighting)
          w = std::clamp(drone::assault_horizon(seeker.drone->forward(), seeker.drone->position(),
                                                hider.drone->position()),
                         0.0f, 1.0f);
        io[kSeeker].reward(k) += s.seen_reward * w;
      }
    }
    any_seen = any_seen || seen;
    all_hidden = all_hidden && !seen;
    if (!seen && s.reward_preset == 0) io[kHider].reward(h) += s.hide_reward;
  }
  if (!any_seen && !tagged_now && s.reward_preset == 0 && s.unseen_reward != 0.0f)
    for (int k = 0; k < num_agents_[kSeeker]; ++k) io[kSeeker].reward(k) += s.unseen_reward;
  // a tag counts as seen (the tagged hider has just left)
  seen_frames_ += any_seen || tagged_now;
  hidden_frames_ += all_hidden && !tagged_now;
  last_all_hidden_ = all_hidden;
}

HideAndSeek::Potential HideAndSeek::opening_potential(
    const std::array<bool, kNumOpenings>& closed) const {
  // one per closed opening; with mode 2, for an open opening, prop_shaping times how near the
  // nearest prop is, reach_shaping times how near the nearest hider is to that prop,
  // push_shaping times how near the nearest hider is to the place behind it (the prop between
  // the hider and the opening) and cover_shaping times how much of it an unlocked prop covers
  const Settings& s = *settings_;
  const auto nearness = [&](float d) { return std::max(0.0f, 1.0f - d / s.shaping_range); };
  Potential potential;
  const auto hold = [&](int o, float share) {
    potential.total += share;
    potential.of_opening[o] += share;
  };
  for (int o = 0; o < kNumOpenings; ++o) {
    const drone::Opening& opening = arena_->openings()[o];
    if (!opening.open) continue;
    if (closed[o]) {
      hold(o, 1.0f);
      continue;
    }
    if (s.close_reward_mode != 2) continue;
    // by default only unlocked props count: one locked short of closing must be unlocked before
    // it helps, so locking it there takes its share back (and unlocking pays it again); with
    // lock_keeps_shaping a lock changes the potential only when it closes the opening
    const auto counts = [&](const drone::Prop& prop) {
      return s.lock_keeps_shaping || !prop.locked();
    };
    int nearest_prop = -1;
    float nearest = std::numeric_limits<float>::infinity();
    for (int i = 0; i < props_->size(); ++i) {
      if (!counts((*props_)[i])) continue;
      const float d = ((*props_)[i].position() - opening.centre).length();
      if (d < nearest) nearest = d, nearest_prop = i;
    }
    if (nearest_prop < 0) continue;
    hold(o, s.prop_shaping * nearness(nearest));
    if (s.cover_shaping != 0.0f) {
      // the unlocked prop covering most of it, full once locking it would close the opening;
      // with cover_depth past the closing test's depth, up to half for one lined up behind it
      // (the graded share: full within the closing depth, fading to 0 at cover_depth)
      float cover = 0.0f, behind = 0.0f;
      for (int i = 0; i < props_->size() && cover < kClosedCover; ++i) {
        const drone::Prop& prop = (*props_)[i];
        if (!counts(prop) || (prop.position() - opening.centre).length() > kCoverReach) continue;
        const drone::CoverShares shares = drone::cover_shares(opening, *prop.body, s.cover_depth);
        cover = std::max(cover, shares.covered);
        behind = std::max(behind, shares.graded);
      }
      hold(o, s.cover_shaping * std::max(std::min(1.0f, cover / kClosedCover), 0.5f * behind));
    }
    if (s.reach_shaping == 0.0f && s.push_shaping == 0.0f) continue;
    const btVector3 prop = (*props_)[nearest_prop].position();
    // where a hider pushes that prop towards the opening from: kGrabStandoff behind it on the
    // line from the opening's centre through the prop (horizontal), at the prop's height
    btVector3 away = prop - opening.centre;
    away.setY(0.0f);
    if (away.length2() < 1e-6f) away = -opening.normal;
    const btVector3 push_point = prop + away.normalized() * kGrabStandoff;
    float hider = std::numeric_limits<float>::infinity();
    float pusher = std::numeric_limits<float>::infinity();
    for (int h = 0; h < kMaxHiders; ++h) {
      const Agent& a = agent(kHider, h);
      if (!a.present) continue;
      hider = std::min(hider, (a.drone->position() - prop).length());
      pusher = std::min(pusher, (a.drone->position() - push_point).length());
    }
    hold(o, s.reach_shaping * nearness(hider));
    hold(o, s.push_shaping * nearness(pusher));
  }
  return potential;
}

void HideAndSeek::check_openings(StepView& io) {
  const Settings& s = *settings_;
  // each opening's state, computed once (covered_fraction casts rays): a held reward needs every
  // opening, the paper's only those not closed yet
  std::array<bool, kNumOpenings> closed{};
  for (int o = 0; o < kNumOpenings; ++o)
    if (s.close_reward_mode != 0 || !ever_closed_[o]) closed[o] = opening_closed(o);
  float reward = 0.0f;  // the team's close reward this decision
  std::array<float, kNumOpenings> of_opening{};  // its part for each opening
  if (s.close_reward_mode == 0) {
    // the paper: paid the first time an opening becomes closed
    for (int o = 0; o < kNumOpenings; ++o) {
      if (ever_closed_[o] || !closed[o]) continue;
      reward += s.close_reward;
      of_opening[o] = s.close_reward;
    }
  } else {
    // held (and shaped): the change of a potential, so that reopening costs at once and going
    // back and forth gains nothing
    const Potential potential = opening_potential(closed);
    reward = s.close_reward * (potential.total - potential_.total);
    for (int o = 0; o < kNumOpenings; ++o)
      of_opening[o] = s.close_reward * (potential.of_opening[o] - potential_.of_opening[o]);
    potential_ = potential;
  }
  for (int o = 0; o < kNumOpenings; ++o) {
    if (ever_closed_[o] || !closed[o]) continue;
    ever_closed_[o] = true;
    record_event("closed", nullptr, nullptr, o);
  }
  if (s.reward_preset != 0) return;
  const int num_open = arena_->num_open();
  for (int h = 0; h < kMaxHiders; ++h) {
    if (!agent(kHider, h).present) continue;
    float paid = reward;
    if (s.close_credit == 1) {
      // opening o is owned by the hiders with (h + owner_shift) mod num_open = o, if there are any
      paid = 0.0f;
      for (int o = 0; o < num_open; ++o)
        if (owns(h, o, num_open)) paid += of_opening[o];
    }
    if (paid != 0.0f) io[kHider].reward(h) += paid;
  }
}

void HideAndSeek::pay_baker_rewards(StepView& io) {
  const float r = last_all_hidden_ ? 1.0f : -1.0f;
  for (int h = 0; h < kMaxHiders; ++h)
    if (agent(kHider, h).present) io[kHider].reward(h) += r;
  for (int k = 0; k < num_agents_[kSeeker]; ++k)
    if (agent(kSeeker, k).present) io[kSeeker].group_reward(k) -= r;
}

void HideAndSeek::step(StepView& io) {
  const Settings& s = *settings_;
  // agents that left last step are gone now
  for (int t = 0; t < 2; ++t)
    for (int slot = 0; slot < io[t].slots(); ++slot)
      if (io[t].step_type(slot) == StepType::kLast) io[t].step_type(slot) = StepType::kAbsent;

  for (Agent& a : agents_) {
    if (!a.present) continue;
    BehaviorView& view = io[a.team];
    const float* c = view.continuous_action(a.slot);
    for (int k = 0; k < 4; ++k) a.thrust[k] = std::isfinite(c[k]) ? clip1(c[k]) : 0.0f;
    if (apply_grab_and_lock(a, view.discrete_action(a.slot)) && s.reward_preset == 0)
      view.reward(a.slot) -= s.unlock_cost;
  }
  for (int f = 0; f < s.decision_period && !over_; ++f) {
    const int before = tagged_;
    run_frame(io);
    if (tagged_ > before && s.end_on_tag) over_ = true;
    if (tagged_ == num_agents_[kHider]) over_ = true;
    if (recording_on_) record_frame();
    if (frame_ >= s.episode_frames) break;
  }
  check_openings(io);
  if (s.reward_preset == 1 && !in_prep()) pay_baker_rewards(io);
  if (recording_on_) record_rewards(io);
  update_sensor_scene();

  const bool truncated = !over_ && frame_ >= s.episode_frames;
  if (over_ || truncated) {
    end_episode(io, /*terminated=*/over_);
    return;
  }
  for (Agent& a : agents_) {
    if (!a.present) continue;
    BehaviorView& view = io[a.team];
    view.step_type(a.slot) = StepType::kMid;
    write_observation(view, a);
    write_mask(view, a);
  }
}

void HideAndSeek::end_episode(StepView& io, bool terminated) {
  over_ = true;
  for (Agent& a : agents_) {
    if (!a.present) continue;
    BehaviorView& view = io[a.team];
    view.step_type(a.slot) = StepType::kLast;
    view.terminated(a.slot) = terminated ? 1 : 0;
    write_observation(view, a);
  }
  if (recording_on_) {
    for (const auto& [k, v] : episode_metrics()) recording_.metrics.emplace_back(k, v);
  }
}

void HideAndSeek::write_mask(BehaviorView& view, const Agent& a) const {
  uint8_t* m = view.action_mask(a.slot);  // [2 + 3]
  // only what would act on a prop now: hold keeps a held prop or grabs one in reach and in front,
  // lock needs an unlocked prop there, unlock one the hiders locked; seekers may do none of it
  // (prop_cues 0: hiders may choose every option, as the paper's agents)
  const bool hider = a.team == kHider;
  const bool cues = settings_->prop_cues;
  const drone::DroneBody& d = *a.drone;
  const unsigned allowed = props_allowed(a);
  m[0] = 1;
  const bool unlockable = props_->unlockable(d, kHider, allowed) >= 0;
  // with regrip, hold is also allowed before a prop the hider may unlock (unlock and hold together
  // take it back)
  m[1] = hider && (!cues || props_->held_by(d) >= 0 || props_->grabbable(d, allowed) >= 0 ||
                   (settings_->regrip && unlockable));
  m[2] = 1;
  m[3] = hider && (!cues || props_->lockable(d, allowed) >= 0);
  m[4] = hider && (!cues || unlockable);
}

void HideAndSeek::write_observation(BehaviorView& view, const Agent& a) {
  const Settings& s = *settings_;
  const drone::DroneBody& d = *a.drone;
  const drone::ArenaParams& ap = arena_->params();
  float* v = view.observation(a.slot, 0);  // [kVectorSize]
  const btVector3 p = d.position();
  const btVector3 vel = d.velocity() / d.params().max_speed;
  const btVector3 fwd = d.forward();
  const float yaw = d.yaw();
  v[0] = clip1(p.x() / ap.half_size);
  v[1] = clip1(2 * p.y() / ap.height - 1);
  v[2] = clip1(p.z() / ap.half_size);
  v[3] = clip1(vel.x());
  v[4] = clip1(vel.y());
  v[5] = clip1(vel.z());
  v[6] = clip1(fwd.x());
  v[7] = clip1(fwd.y());
  v[8] = clip1(fwd.z());
  v[9] = std::sin(yaw);
  v[10] = std::cos(yaw);
  v[11] = props_->held_by(d) >= 0 ? 1.0f : 0.0f;
  const int clock = s.clock_frames > 0 ? s.clock_frames : s.episode_frames;
  v[12] = clip1(static_cast<float>(frame_) / clock);
  v[13] = in_prep() ? 1.0f : 0.0f;
  // the nearest opponent this agent sees
  const Team other = a.team == kHider ? kSeeker : kHider;
  float best = INFINITY;
  btVector3 rel(0, 0, 0);
  for (int k = 0; k < (other == kHider ? kMaxHiders : kMaxSeekers); ++k) {
    const Agent& o = agent(other, k);
    if (!o.present) continue;
    const btVector3 delta = o.drone->position() - p;
    const float dist = delta.length();
    if (dist >= best) continue;
    if (!drone::sees(*world_, d.body(), o.drone->body(), s.vision_cone, s.vision_range)) continue;
    best = dist;
    rel = delta;
  }
  const bool seen = std::isfinite(best);
  v[14] = seen ? clip1(rel.dot(d.right()) / s.vision_range) : 0.0f;
  v[15] = seen ? clip1(rel.y() / s.vision_range) : 0.0f;
  v[16] = seen ? clip1(rel.dot(fwd) / s.vision_range) : 0.0f;
  v[17] = seen ? 1.0f : 0.0f;
  // what the lock branch could do now (the vision of the props cannot tell locked from unlocked)
  const unsigned allowed = props_allowed(a);
  v[18] = s.prop_cues && props_->lockable(d, allowed) >= 0 ? 1.0f : 0.0f;
  v[19] = s.prop_cues && props_->unlockable(d, kHider, allowed) >= 0 ? 1.0f : 0.0f;
  write_objects(view.observation(a.slot, 1), a);
  float* outs[3] = {view.observation(a.slot, 2), view.observation(a.slot, 3),
                    view.observation(a.slot, 4)};
  if (!s.sensor_obs) {
    const int sizes[3] = {rays_.size(), spatial_grid_.size(), frontal_grid_.size()};
    for (int k = 0; k < 3; ++k) std::fill(outs[k], outs[k] + sizes[k], 0.0f);
    return;
  }
  rays_.observe(shapes_, d.body(), outs[0]);
  const drone::GridSensor* grids[2] = {&spatial_grid_, &frontal_grid_};
  drone::GridSensor::observe_many(grids, outs + 1, 2, points_, points_.body_index(d.body()),
                                  d.body().getWorldTransform());
}

void HideAndSeek::write_objects(float* out, const Agent& a) const {
  std::fill(out, out + kObjectsSize, 0.0f);
  if (!settings_->object_obs) return;
  const drone::DroneBody& d = *a.drone;
  const btVector3 p = d.position();
  const btVector3 right = d.right();
  const btVector3 fwd = d.forward();
  const float scale = 1.0f / (2.0f * arena_->params().half_size);
  // a world point relative to the agent, in its frame (right, up, forward) and scaled
  auto relative = [&](const btVector3& point, float* o) {
    const btVector3 delta = point - p;
    o[0] = clip1(delta.dot(right) * scale);
    o[1] = clip1(delta.y() * scale);
    o[2] = clip1(delta.dot(fwd) * scale);
  };
  // each agent's own first: entry k is prop (k + slot + owner_shift) mod n of the level's n (and
  // so for the openings), so teammates that learned to take the first prop to the first opening
  // take different ones
  const int num_props = std::min(props_->size(), kMaxProps);
  const int num_open = arena_->num_open();
  const int shift = settings_->owner_shift;
  const auto own_first = [&](int k, int n) { return k < n ? (k + a.slot + shift) % n : k; };
  for (int k = 0; k < num_props; ++k) {
    const drone::Prop& prop = (*props_)[own_first(k, num_props)];
    float* o = out + k * kPropFloats;
    relative(prop.position(), o);
    o[3] = 1.0f;
    o[4] = prop.locked() ? 1.0f : 0.0f;
    o[5] = prop.held_by != nullptr && prop.held_by != &d.body() ? 1.0f : 0.0f;
    // the panel's normal (its local z) against the agent's forward, as twice the angle
    DoubledAngle turn;
    if (doubled_angle(prop.normal(), fwd, right, &turn)) {
      o[6] = turn.sin2;
      o[7] = turn.cos2;
    }
  }
  float* openings = out + kMaxProps * kPropFloats;
  for (int k = 0; k < kNumOpenings; ++k) {
    const int index = own_first(k, num_open);
    const drone::Opening& opening = arena_->openings()[index];
    float* o = openings + k * kOpeningFloats;
    relative(opening.centre, o);
    o[3] = opening.open ? 1.0f : 0.0f;
    o[4] = closed_now_[index] ? 1.0f : 0.0f;
    if (!opening.open || index >= num_props) continue;
    // its prop (the one of the same index: own_first pairs them) against the spot where that
    // prop would stand in it, at a scale that tells centimetres apart near it
    const drone::Prop& prop = (*props_)[index];
    const btVector3 error = standing_in(opening, prop.position().y()) - prop.position();
    o[5] = soft_metres(error.dot(right));
    o[6] = soft_metres(error.dot(fwd));
    o[7] = clip1(opening.normal.dot(right));
    o[8] = clip1(opening.normal.dot(fwd));
    // the panel's normal against the opening's, as twice the angle: (1, 0) parallel to its wall
    DoubledAngle turn;
    const btVector3 along_wall = opening.normal.cross(btVector3(0, 1, 0));
    if (doubled_angle(prop.normal(), opening.normal, along_wall, &turn)) {
      o[9] = turn.cos2;
      o[10] = turn.sin2;
    }
  }
  float* mate = openings + kNumOpenings * kOpeningFloats;  // [4]
  float best = INFINITY;
  const int slots = a.team == kHider ? kMaxHiders : kMaxSeekers;
  for (int k = 0; k < slots; ++k) {
    const Agent& o = agent(a.team, k);
    if (!o.present || k == a.slot) continue;
    const float dist = (o.drone->position() - p).length();
    if (dist >= best) continue;
    best = dist;
    relative(o.drone->position(), mate);
    mate[3] = 1.0f;
  }
  float* slot = mate + 4;  // [kMaxSeekers]
  // without it two hiders with the same view act alike: level 1's one prop cannot teach one
  // slot to leave the work to the other
  if (a.team == kSeeker || settings_->hider_slot_obs) slot[a.slot] = 1.0f;
}

void HideAndSeek::update_sensor_scene() {
  for (int o = 0; o < kNumOpenings; ++o)
    closed_now_[o] = settings_->object_obs && opening_closed(o);
  if (!settings_->sensor_obs) return;  // nobody reads them
  points_.update(*world_);
  shapes_.capture(world_->world());
}

void HideAndSeek::record_frame() {
  RecordedFrame frame;
  frame.poses.resize(recorded_objects_.size());
  frame.present.resize(recorded_objects_.size());
  for (size_t i = 0; i < recorded_objects_.size(); ++i) {
    const btCollisionObject* o = recorded_objects_[i];
    if (o == nullptr) continue;
    const btTransform& t = o->getWorldTransform();
    const btQuaternion q = t.getRotation();
    frame.poses[i] = {float(t.getOrigin().x()), float(t.getOrigin().y()), float(t.getOrigin().z()),
                      float(q.x()), float(q.y()), float(q.z()), float(q.w())};
    frame.present[i] = 1;
  }
  frame.events = pending_events_;
  pending_events_.clear();
  recording_.frames.push_back(std::move(frame));
}

void HideAndSeek::record_rewards(StepView& io) {
  if (recording_.frames.empty()) return;
  RecordedFrame& frame = recording_.frames.back();  // the decision's last frame
  std::vector<float> rewards(agents_.size(), 0.0f), group(agents_.size(), 0.0f);  // [agents]
  bool any = false;
  for (const Agent& a : agents_) {
    if (!a.drone) continue;
    const int id = agent_id(a);
    if (id < 0 || id >= int(rewards.size())) continue;
    rewards[id] = io[a.team].reward(a.slot);
    group[id] = io[a.team].group_reward(a.slot);
    any = any || rewards[id] != 0.0f || group[id] != 0.0f;
  }
  if (!any) return;
  frame.rewards = std::move(rewards);
  frame.group_rewards = std::move(group);
}

bool HideAndSeek::take_recording(EpisodeRecording& out) {
  if (!recording_on_ || !over_ || recording_.frames.empty()) return false;
  out = std::move(recording_);
  recording_ = EpisodeRecording();
  return true;
}

EpisodeMetrics HideAndSeek::episode_metrics() const {
  static_assert(kMaxHiders == 2, "one pair of per-hider metrics for each hider slot");
  const float test = static_cast<float>(std::max<long>(test_frames_, 1));
  // (a hider tagged later in the test phase has left, but it played the prep phase)
  const auto idle = [&](int h) { return h < num_agents_[kHider] && !handled_in_prep_[h]; };
  return {{"tag_rate", tagged_ > 0 ? 1.0f : 0.0f},
          {"seen_fraction", seen_frames_ / test},
          {"hidden_fraction", hidden_frames_ / test},
          {"fort_rate", fort_ ? 1.0f : 0.0f},
          {"openings_closed", static_cast<float>(closed_at_prep_end_)},
          {"tagged", static_cast<float>(tagged_)},
          // the offset the props started at (levels 1 and 2; else 1)
          {"prop_start_offset", episode_offset_},
          // each hider apart (0 for an absent one): every opening it is paid for closed at the
          // end of the prep phase, and no prop grabbed or locked in it
          {"hider0_closed_own", closed_own_at_prep_end_[0] ? 1.0f : 0.0f},
          {"hider1_closed_own", closed_own_at_prep_end_[1] ? 1.0f : 0.0f},
          {"hider0_idle", idle(0) ? 1.0f : 0.0f},
          {"hider1_idle", idle(1) ? 1.0f : 0.0f},
          // where each hider's building got to: its openings closed at some decision of the
          // prep phase; covered over half by a prop, locked or not, at its end; and the
          // distance then from its openings to the nearest prop (m; the largest of its openings)
          {"hider0_closed_own_once", closed_own_in_prep_[0] ? 1.0f : 0.0f},
          {"hider1_closed_own_once", closed_own_in_prep_[1] ? 1.0f : 0.0f},
          {"hider0_covered_own", covered_own_at_prep_end_[0] ? 1.0f : 0.0f},
          {"hider1_covered_own", covered_own_at_prep_end_[1] ? 1.0f : 0.0f},
          {"hider0_own_gap", own_gap_at_prep_end_[0]},
          {"hider1_own_gap", own_gap_at_prep_end_[1]}};
}

bool HideAndSeek::write_scripted_actions(int behavior, BehaviorView& view) {
  return drone::write_scripted_hide_and_seek_actions(*this, static_cast<Team>(behavior), view);
}

}  // namespace rlt
