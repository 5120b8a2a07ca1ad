#include "env/toy/pursuit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rl/env_api/uniform_random.h"

namespace rlt {

namespace {

constexpr double kTagDistance = 2 * Pursuit::kRadius;
constexpr double kSpawnClearance = Pursuit::kRadius + 0.05;  // from walls, at spawn
constexpr double kSeekerSpawnDistance = 3.0;                 // from every hider, at spawn
constexpr int kSpawnAttempts = 1000;
constexpr int kSubsteps = 2;

// unit directions of the rays: 0, 45, ..., 315 degrees from +x
constexpr double kDiag = 0.7071067811865476;
constexpr double kRayDirs[Pursuit::kRays][2] = {{1, 0},          {kDiag, kDiag}, {0, 1},
                                                {-kDiag, kDiag}, {-1, 0},        {-kDiag, -kDiag},
                                                {0, -1},         {kDiag, -kDiag}};

// acceleration direction of each discrete option
constexpr double kMoves[Pursuit::kActions][2] = {{0, 0}, {0, 1}, {0, -1}, {-1, 0}, {1, 0}};

// Entry parameter of the segment p + t d, t in [t0, t1], into `w`; -1 when it misses (slabs).
double segment_hits_box(double px, double py, double dx, double dy, double t0, double t1,
                        const Pursuit::Wall& w) {
  const double lo[2] = {w.cx - w.hx, w.cy - w.hy};
  const double hi[2] = {w.cx + w.hx, w.cy + w.hy};
  const double p[2] = {px, py};
  const double d[2] = {dx, dy};
  for (int a = 0; a < 2; ++a) {
    if (d[a] == 0.0) {
      if (p[a] < lo[a] || p[a] > hi[a]) return -1;
      continue;
    }
    double ta = (lo[a] - p[a]) / d[a];
    double tb = (hi[a] - p[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return -1;
  }
  return t0;
}

}  // namespace

Pursuit::Pursuit() {
  BehaviorSpec hider;
  hider.name = "Hider";
  hider.observations.push_back({"state", {kObservationSize}, ObservationKind::kVector, -1.f, 1.f});
  hider.action.discrete_branches = {kActions};
  hider.agent_slots = kMaxHiders;
  BehaviorSpec seeker = hider;
  seeker.name = "Seeker";
  seeker.agent_slots = kMaxSeekers;
  spec_.name = "Pursuit";
  spec_.behaviors = {hider, seeker};
  spec_.max_episode_steps = kMaxEpisodeLength;
  spec_.default_parameters = {
      {"num_hiders", 1.f},       {"num_seekers", 2.f},    {"prep_fraction", 0.3f},
      {"episode_length", 100.f}, {"level", 1.f},          {"end_on_tag", 1.f},
      {"hide_reward", 0.005f},   {"seen_reward", 0.005f}, {"vision_range", 10.f}};
}

void Pursuit::seed(uint64_t seed) { engine_.seed(seed); }

std::vector<Pursuit::Wall> Pursuit::level_walls(int level) {
  const double t = kWallHalfThickness;
  std::vector<Wall> walls = {{0.0, 0.0, t, 2.5}};       // level 1: x = 0, y in [-2.5, 2.5]
  if (level >= 2) walls.push_back({0.0, 0.0, 2.5, t});  // the plus: y = 0, x in [-2.5, 2.5]
  if (level >= 3) {
    walls.push_back({-3.75, 2.5, 1.25, t});  // y = 2.5, x in [-5, -2.5]
    walls.push_back({3.75, -2.5, 1.25, t});  // y = -2.5, x in [2.5, 5]
  }
  return walls;
}

bool Pursuit::overlaps_wall(double x, double y, double clearance) const {
  for (const Wall& w : walls_) {
    const double qx = std::clamp(x, w.cx - w.hx, w.cx + w.hx);
    const double qy = std::clamp(y, w.cy - w.hy, w.cy + w.hy);
    if (std::hypot(x - qx, y - qy) < clearance) return true;
  }
  return false;
}

bool Pursuit::line_of_sight(double x0, double y0, double x1, double y1) const {
  for (const Wall& w : walls_)
    if (segment_hits_box(x0, y0, x1 - x0, y1 - y0, 0.0, 1.0, w) >= 0) return false;
  return true;
}

bool Pursuit::sees(int seeker, int hider) const {
  const Body& s = bodies_[kSeeker][seeker];
  const Body& h = bodies_[kHider][hider];
  if (!s.present || !h.present) return false;
  if (std::hypot(h.x - s.x, h.y - s.y) > vision_range_) return false;
  return line_of_sight(s.x, s.y, h.x, h.y);
}

double Pursuit::ray_distance(double x, double y, double dx, double dy, double max) const {
  double best = max;
  // border
  if (dx > 0) best = std::min(best, (kHalfSize - x) / dx);
  if (dx < 0) best = std::min(best, (-kHalfSize - x) / dx);
  if (dy > 0) best = std::min(best, (kHalfSize - y) / dy);
  if (dy < 0) best = std::min(best, (-kHalfSize - y) / dy);
  // walls
  for (const Wall& w : walls_) {
    const double t = segment_hits_box(x, y, dx, dy, 0.0, best, w);
    if (t >= 0) best = t;
  }
  return std::max(best, 0.0);
}

void Pursuit::move(Body& b, double ax, double ay) {
  // velocity: accelerate, damp, cap
  b.vx = kDamping * (b.vx + kAccel * ax * kDt);
  b.vy = kDamping * (b.vy + kAccel * ay * kDt);
  const double speed = std::hypot(b.vx, b.vy);
  if (speed > kMaxSpeed) {
    b.vx *= kMaxSpeed / speed;
    b.vy *= kMaxSpeed / speed;
  }

  // position, in substeps shorter than the radius; slide along walls and the border
  const double h = kDt / kSubsteps;
  for (int k = 0; k < kSubsteps; ++k) {
    b.x += b.vx * h;
    b.y += b.vy * h;
    for (const Wall& w : walls_) {
      const double qx = std::clamp(b.x, w.cx - w.hx, w.cx + w.hx);
      const double qy = std::clamp(b.y, w.cy - w.hy, w.cy + w.hy);
      double nx = b.x - qx, ny = b.y - qy;
      const double dist = std::hypot(nx, ny);
      if (dist >= kRadius) continue;
      if (dist > 1e-12) {
        nx /= dist;
        ny /= dist;
        b.x = qx + nx * kRadius;
        b.y = qy + ny * kRadius;
      } else {
        // centre inside the box: out through the nearest face
        const double pen[4] = {b.x - (w.cx - w.hx), (w.cx + w.hx) - b.x, b.y - (w.cy - w.hy),
                               (w.cy + w.hy) - b.y};
        const int face = static_cast<int>(std::min_element(pen, pen + 4) - pen);
        nx = face == 0 ? -1 : face == 1 ? 1 : 0;
        ny = face == 2 ? -1 : face == 3 ? 1 : 0;
        if (nx != 0) b.x = (nx < 0 ? w.cx - w.hx : w.cx + w.hx) + nx * kRadius;
        if (ny != 0) b.y = (ny < 0 ? w.cy - w.hy : w.cy + w.hy) + ny * kRadius;
      }
      const double vn = b.vx * nx + b.vy * ny;
      if (vn < 0) {
        b.vx -= vn * nx;
        b.vy -= vn * ny;
      }
    }
    const double lim = kHalfSize - kRadius;
    if (b.x < -lim) b.x = -lim, b.vx = std::max(b.vx, 0.0);
    if (b.x > lim) b.x = lim, b.vx = std::min(b.vx, 0.0);
    if (b.y < -lim) b.y = -lim, b.vy = std::max(b.vy, 0.0);
    if (b.y > lim) b.y = lim, b.vy = std::min(b.vy, 0.0);
  }
}

void Pursuit::write_observation(BehaviorView& view, Team team, int slot) const {
  const Body& me = bodies_[team][slot];
  const Team other_team = team == kHider ? kSeeker : kHider;
  const int opponents = team == kHider ? kMaxSeekers : kMaxHiders;
  const int mates = team == kHider ? kMaxHiders : kMaxSeekers;
  float* obs = view.observation(slot, 0);  // [30]
  std::fill(obs, obs + kObservationSize, 0.f);

  // own state and time
  obs[0] = static_cast<float>(me.x / kHalfSize);
  obs[1] = static_cast<float>(me.y / kHalfSize);
  obs[2] = static_cast<float>(me.vx / kMaxSpeed);
  obs[3] = static_cast<float>(me.vy / kMaxSpeed);
  obs[4] = static_cast<float>(elapsed_) / static_cast<float>(episode_length_);
  obs[5] = in_prep() ? 1.f : 0.f;
  int k = 6;

  // another agent as (unit direction, distance / arena diagonal, 1)
  auto write_other = [&](const Body& b, float* out) {
    const double dx = b.x - me.x, dy = b.y - me.y;
    const double d = std::hypot(dx, dy);
    if (d > 1e-9) {
      out[0] = static_cast<float>(dx / d);
      out[1] = static_cast<float>(dy / d);
    }
    out[2] = static_cast<float>(d / kDiagonal);
    out[3] = 1.f;
  };
  // opponents, zeros when not seen
  for (int o = 0; o < opponents; ++o, k += 4) {
    const bool visible = team == kHider ? sees(o, slot) : sees(slot, o);
    if (visible) write_other(bodies_[other_team][o], obs + k);
  }
  // teammates after me in slot order, zeros when absent
  for (int m = 1; m < mates; ++m, k += 4) {
    const Body& b = bodies_[team][(slot + m) % mates];
    if (b.present) write_other(b, obs + k);
  }
  // rays to walls and the border
  for (int r = 0; r < kRays; ++r, ++k)
    obs[k] = static_cast<float>(
        ray_distance(me.x, me.y, kRayDirs[r][0], kRayDirs[r][1], kRayLength) / kRayLength);
}

void Pursuit::write_mask(BehaviorView& view, Team team, int slot) const {
  uint8_t* mask = view.action_mask(slot);  // [5]
  const bool frozen = team == kSeeker && in_prep();
  for (int a = 0; a < kActions; ++a) mask[a] = (a == 0 || !frozen) ? 1 : 0;
}

void Pursuit::reset(StepView& out) {
  // settings
  num_agents_[kHider] =
      std::clamp(static_cast<int>(std::lround(parameter("num_hiders"))), 1, kMaxHiders);
  num_agents_[kSeeker] =
      std::clamp(static_cast<int>(std::lround(parameter("num_seekers"))), 1, kMaxSeekers);
  episode_length_ =
      std::clamp(static_cast<int>(std::lround(parameter("episode_length"))), 10, kMaxEpisodeLength);
  const double prep_fraction = std::clamp(static_cast<double>(parameter("prep_fraction")), 0., 1.);
  prep_steps_ = static_cast<int>(std::lround(prep_fraction * episode_length_));
  end_on_tag_ = parameter("end_on_tag") >= 0.5f;
  vision_range_ = std::max(0.0, static_cast<double>(parameter("vision_range")));
  hide_reward_ = parameter("hide_reward");
  seen_reward_ = parameter("seen_reward");
  walls_ = level_walls(std::clamp(static_cast<int>(std::lround(parameter("level"))), 1, 3));

  // spawns: uniform, clear of walls and of agents placed before; seekers away from hiders
  const double lim = kHalfSize - kRadius;
  for (auto& team : bodies_)
    for (Body& b : team) b = Body{};
  for (int team : {kHider, kSeeker}) {
    for (int s = 0; s < num_agents_[team]; ++s) {
      Body& b = bodies_[team][s];
      for (int attempt = 0; attempt < kSpawnAttempts; ++attempt) {
        b.x = uniform(engine_, -lim, lim);
        b.y = uniform(engine_, -lim, lim);
        bool ok = !overlaps_wall(b.x, b.y, kSpawnClearance);
        for (int t2 = kHider; t2 <= team && ok; ++t2) {
          const double min_dist = t2 == team ? kTagDistance + 0.1 : kSeekerSpawnDistance;
          for (int s2 = 0; s2 < (t2 == team ? s : num_agents_[t2]) && ok; ++s2)
            ok = std::hypot(b.x - bodies_[t2][s2].x, b.y - bodies_[t2][s2].y) >= min_dist;
        }
        if (ok) break;
      }
      b.present = true;
    }
  }
  elapsed_ = 0;
  tagged_ = 0;
  test_steps_ = 0;
  seen_steps_ = 0;

  for (int team : {kHider, kSeeker}) {
    BehaviorView& view = out[team];
    for (int s = 0; s < view.slots(); ++s) {
      if (!bodies_[team][s].present) continue;
      view.step_type(s) = StepType::kFirst;
      view.agent_id(s) = team == kHider ? s : kMaxHiders + s;
      view.group_id(s) = team;
      view.reward(s) = 0.f;
      view.group_reward(s) = 0.f;
      view.terminated(s) = 0;
      write_observation(view, static_cast<Team>(team), s);
      write_mask(view, static_cast<Team>(team), s);
    }
  }
}

void Pursuit::step(StepView& io) {
  // who acts; the others stay absent until the next reset
  std::array<std::array<bool, kMaxSeekers>, 2> acting{};  // [team][slot]
  for (int team : {kHider, kSeeker}) {
    BehaviorView& view = io[team];
    for (int s = 0; s < view.slots(); ++s) {
      acting[team][s] = needs_action(view.step_type(s));
      if (acting[team][s]) continue;
      view.step_type(s) = StepType::kAbsent;
      view.agent_id(s) = -1;
    }
  }

  // moves; seekers stay frozen during the prep phase
  const bool prep = in_prep();
  for (int team : {kHider, kSeeker}) {
    BehaviorView& view = io[team];
    for (int s = 0; s < view.slots(); ++s) {
      if (!acting[team][s]) continue;
      Body& b = bodies_[team][s];
      if (team == kSeeker && prep) {
        b.vx = b.vy = 0;
        continue;
      }
      const int action = view.discrete_action(s)[0];
      if (action < 0 || action >= kActions)
        throw std::invalid_argument("Pursuit: action " + std::to_string(action) + " of " +
                                    view.spec().name + " slot " + std::to_string(s) +
                                    " is outside [0, 5)");
      move(b, kMoves[action][0], kMoves[action][1]);
    }
  }
  ++elapsed_;

  // tags, then sight, in the test phase
  std::array<bool, kMaxHiders> tagged_now{};
  int tags = 0, seen = 0;
  bool hider_in_game = false;
  if (!prep) {
    for (int h = 0; h < kMaxHiders; ++h) {
      Body& hb = bodies_[kHider][h];
      if (!hb.present) continue;
      hider_in_game = true;
      for (int s = 0; s < kMaxSeekers && !tagged_now[h]; ++s) {
        const Body& sb = bodies_[kSeeker][s];
        tagged_now[h] = sb.present && std::hypot(hb.x - sb.x, hb.y - sb.y) < kTagDistance;
      }
      if (tagged_now[h]) {
        hb.present = false;
        ++tags;
      }
    }
    tagged_ += tags;
  }
  std::array<bool, kMaxHiders> hidden{};
  for (int h = 0; h < kMaxHiders; ++h) {
    if (!bodies_[kHider][h].present) continue;
    bool seen_by_any = false;
    for (int s = 0; s < kMaxSeekers; ++s) seen_by_any = seen_by_any || sees(s, h);
    seen += seen_by_any;
    hidden[h] = !seen_by_any;
  }
  if (!prep && hider_in_game) {
    ++test_steps_;
    seen_steps_ += (tags + seen) > 0;
  }

  // end of the episode
  bool hiders_left = false;
  for (int h = 0; h < kMaxHiders; ++h) hiders_left = hiders_left || bodies_[kHider][h].present;
  const bool all_tagged = end_on_tag_ && !hiders_left;
  const bool timeout = elapsed_ >= episode_length_;

  // step data
  for (int team : {kHider, kSeeker}) {
    BehaviorView& view = io[team];
    for (int s = 0; s < view.slots(); ++s) {
      if (!acting[team][s]) continue;
      write_observation(view, static_cast<Team>(team), s);
      write_mask(view, static_cast<Team>(team), s);
      if (team == kHider) {
        if (tagged_now[s]) view.reward(s) = -1.f;
        if (!prep && hidden[s]) view.reward(s) = hide_reward_;
      } else if (!prep) {
        view.group_reward(s) = static_cast<float>(tags) + seen_reward_ * static_cast<float>(seen);
      }
      const bool leaves = team == kHider && tagged_now[s];
      if (leaves || all_tagged) {
        view.step_type(s) = StepType::kLast;
        view.terminated(s) = 1;
      } else if (timeout) {
        view.step_type(s) = StepType::kLast;
        view.terminated(s) = 0;
      } else {
        view.step_type(s) = StepType::kMid;
      }
    }
  }
}

EpisodeMetrics Pursuit::episode_metrics() const {
  const float seen_fraction =
      test_steps_ > 0 ? static_cast<float>(seen_steps_) / static_cast<float>(test_steps_) : 0.f;
  return {{"tag_rate", tagged_ > 0 ? 1.f : 0.f},
          {"seen_fraction", seen_fraction},
          {"tagged", static_cast<float>(tagged_)}};
}

}  // namespace rlt
