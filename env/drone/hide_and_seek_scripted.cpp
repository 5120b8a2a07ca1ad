#include "env/drone/hide_and_seek_scripted.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "env/drone/drone_steering.h"
#include "env/drone/vision.h"

namespace rlt::drone {

namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kDoorFlightHeight = 0.9f;  // m, well inside a 1.9 m doorway

using Team = HideAndSeek::Team;

float wrap(float a) {
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}
// an angle difference modulo pi (a panel's normal and its negative are the same orientation)
float wrap_half(float a) {
  a = wrap(a);
  if (a > 0.5f * kPi) a -= kPi;
  if (a <= -0.5f * kPi) a += kPi;
  return a;
}

btVector3 horizontal(btVector3 v) {
  v.setY(0);
  return v;
}

// the openings open at the level, doorways first, then by index
std::vector<int> open_openings(const HideAndSeek& env) {
  std::vector<int> out;
  const auto& openings = env.arena().openings();
  for (int kind = 0; kind < 2; ++kind)
    for (int o = 0; o < kNumOpenings; ++o)
      if (openings[o].open && openings[o].kind == kind) out.push_back(o);
  return out;
}

// the opening the hider of `rank` (among those present) works on: its own, the rank-th of
// `open_ones`, until it is closed, then the first one still open that is no other hider's own;
// -1 when none is left
int opening_for(const HideAndSeek& env, const std::vector<int>& open_ones, int rank, int hiders) {
  const int n = static_cast<int>(open_ones.size());
  if (rank < n && !env.opening_closed(open_ones[rank])) return open_ones[rank];
  for (int i = 0; i < n; ++i) {
    const bool someones = i < hiders && i != rank;
    if (!someones && !env.opening_closed(open_ones[i])) return open_ones[i];
  }
  return -1;
}

// true when the straight path from a to b crosses the room (inflated by `margin`)
bool crosses_room(const ArenaParams& arena, const btVector3& a, const btVector3& b, float margin) {
  const float r = arena.room_half + 0.5f * arena.wall_thickness + margin;
  // slab test in x and z
  float t0 = 0, t1 = 1;
  const float p[2] = {float(a.x()), float(a.z())};
  const float d[2] = {float(b.x() - a.x()), float(b.z() - a.z())};
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-6f) {
      if (p[k] < -r || p[k] > r) return false;
      continue;
    }
    float ta = (-r - p[k]) / d[k], tb = (r - p[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// the next point on a shortest path from `from` to `to` (both outside the room) that goes around
// the room through points just off its corners (at most two of them)
btVector3 around_room(const ArenaParams& arena, const btVector3& from, const btVector3& to) {
  if (!crosses_room(arena, from, to, 0.6f)) return to;
  const float c = arena.room_half + 0.5f * arena.wall_thickness + 1.2f;
  std::vector<btVector3> corners;
  for (float sx : {-1.0f, 1.0f})
    for (float sz : {-1.0f, 1.0f}) corners.emplace_back(sx * c, from.y(), sz * c);
  auto clear = [&](const btVector3& a, const btVector3& b) {
    return !crosses_room(arena, a, b, 0.3f);
  };
  btVector3 best = to;
  float best_length = std::numeric_limits<float>::infinity();
  for (const btVector3& c1 : corners) {
    if ((c1 - from).length() < 0.6f || !clear(from, c1)) continue;  // reached, or blocked
    const float first = (c1 - from).length();
    if (clear(c1, to) && first + (to - c1).length() < best_length) {
      best_length = first + (to - c1).length();
      best = c1;
    }
    for (const btVector3& c2 : corners) {
      if (&c2 == &c1 || !clear(c1, c2) || !clear(c2, to)) continue;
      const float length = first + (c2 - c1).length() + (to - c2).length();
      if (length < best_length) {
        best_length = length;
        best = c1;
      }
    }
  }
  return best;
}

// where the seeker should fly next to reach `goal` (a hider's position)
btVector3 seeker_waypoint(const HideAndSeek& env, const btVector3& p, const btVector3& goal) {
  const Arena& arena = env.arena();
  const bool me_in = arena.inside_room(p), goal_in = arena.inside_room(goal);
  if (me_in == goal_in) return me_in ? goal : around_room(arena.params(), p, goal);
  // through the nearest open doorway or window that no locked prop closes
  int best = -1;
  float best_distance = std::numeric_limits<float>::infinity();
  for (int o = 0; o < kNumOpenings; ++o) {
    const Opening& opening = arena.openings()[o];
    if (!opening.open || env.opening_closed(o)) continue;
    const float d = (opening.centre - p).length() + (goal - opening.centre).length();
    if (d < best_distance) {
      best_distance = d;
      best = o;
    }
  }
  if (best < 0) return goal;  // no way in: press on
  const Opening& opening = arena.openings()[best];
  const float side = me_in ? -1.0f : 1.0f;  // which side of the wall I am on
  btVector3 near_side = opening.centre + opening.normal * (side * 1.5f);
  btVector3 far_side = opening.centre - opening.normal * (side * 1.5f);
  const float y = opening.kind == Opening::kDoorway ? kDoorFlightHeight : float(opening.centre.y());
  near_side.setY(y);
  far_side.setY(y);
  const btVector3 rel = p - opening.centre;
  const float along = rel.dot(opening.normal) * side;  // > 0 on my side
  const btVector3 across = rel - opening.normal * rel.dot(opening.normal);
  // lined up with the opening near it, or already in its passage: go through
  const bool lined_up = along > -0.5f && along < 2.0f &&
                        std::abs(across.x()) + std::abs(across.z()) < 0.35f &&
                        std::abs(p.y() - y) < 0.3f;
  if (lined_up) return far_side;
  return me_in ? near_side : around_room(arena.params(), p, near_side);
}

void seeker_actions(HideAndSeek& env, BehaviorView& view, int slot) {
  const DroneBody& me = *env.agent(HideAndSeek::kSeeker, slot).drone;
  const btVector3 p = me.position();
  // the nearest hider it sees, else the nearest one in the game
  int seen = -1, any = -1;
  float seen_d = std::numeric_limits<float>::infinity(), any_d = seen_d;
  for (int h = 0; h < HideAndSeek::kMaxHiders; ++h) {
    const auto& hider = env.agent(HideAndSeek::kHider, h);
    if (!hider.present) continue;
    const float d = (hider.drone->position() - p).length();
    if (d < any_d) any_d = d, any = h;
    if (d < seen_d && sees(env.world(), me.body(), hider.drone->body())) seen_d = d, seen = h;
  }
  float* c = view.continuous_action_out(slot);
  int32_t* k = view.discrete_action_out(slot);
  k[0] = k[1] = 0;
  if (any < 0) {
    std::fill(c, c + 4, 0.0f);
    return;
  }
  const btVector3 goal = env.agent(HideAndSeek::kHider, seen >= 0 ? seen : any).drone->position();
  btVector3 target = seen >= 0 ? goal : seeker_waypoint(env, p, goal);
  if (seen < 0 && !env.arena().inside_room(target) && target.y() > 2.5f)
    target.setY(kDoorFlightHeight);
  SteeringGains gains;
  gains.arrive_gain = 100.0f;  // full speed until contact
  const auto a = steer(me, target, seen >= 0 ? goal : target, gains);
  std::copy(a.begin(), a.end(), c);
}

// hider `slot` works on its opening; `claimed` lists props given to hiders before it
void hider_actions(HideAndSeek& env, BehaviorView& view, int slot, std::vector<int>& claimed,
                   const std::vector<int>& open_ones) {
  DroneBody& me = *env.agent(HideAndSeek::kHider, slot).drone;
  PropSet& props = env.props();
  const btVector3 p = me.position();
  float* c = view.continuous_action_out(slot);
  int32_t* k = view.discrete_action_out(slot);
  std::fill(c, c + 4, 0.0f);
  k[HideAndSeek::kGrabBranch] = 0;
  k[HideAndSeek::kLockBranch] = 0;

  int rank = 0, hiders = 0;
  for (int h = 0; h < HideAndSeek::kMaxHiders; ++h) {
    const bool present = env.agent(HideAndSeek::kHider, h).present;
    rank += present && h < slot;
    hiders += present;
  }
  const int target = opening_for(env, open_ones, rank, hiders);
  if (target < 0) return;  // nothing for me: stay
  const Opening& opening = env.arena().openings()[target];

  int prop = props.held_by(me);
  if (prop < 0) {
    // the free prop with the shortest way: to it, then with it to the opening
    float best = std::numeric_limits<float>::infinity();
    for (int i = 0; i < props.size(); ++i) {
      if (props[i].locked() || props[i].held_by != nullptr) continue;
      if (std::find(claimed.begin(), claimed.end(), i) != claimed.end()) continue;
      const btVector3 at = props[i].position();
      const float d = horizontal(at - p).length() + horizontal(opening.centre - at).length();
      if (d < best) best = d, prop = i;
    }
  }
  if (prop < 0) return;
  claimed.push_back(prop);
  const Prop& panel = props[prop];
  const btTransform& pose = panel.body->getWorldTransform();
  const btVector3 centre = pose.getOrigin();
  btVector3 normal = horizontal(pose.getBasis() * btVector3(0, 0, 1));
  if (normal.length2() < 1e-6f) normal = btVector3(0, 0, 1);
  normal.normalize();

  if (props.held_by(me) != prop) {
    // approach the broad face on the room's side (or on my side outside the room)
    const btVector3 towards = env.arena().inside_room(centre) ? -horizontal(centre) : p - centre;
    const float side = normal.dot(towards) >= 0 ? 1.0f : -1.0f;
    btVector3 approach = centre + normal * (side * HideAndSeek::kGrabStandoff);
    approach.setY(centre.y());
    const auto a = steer(me, approach, centre);
    std::copy(a.begin(), a.end(), c);
    const bool arrived = (approach - p).length() < 0.3f;
    if (arrived && std::abs(heading_error(me, centre)) < 0.2f) k[HideAndSeek::kGrabBranch] = 1;
    return;
  }

  // carrying: bring the panel flat against the wall's inner face over the opening
  k[HideAndSeek::kGrabBranch] = 1;
  const ArenaParams& ap = env.arena().params();
  btVector3 goal = opening.centre - opening.normal * (0.5f * ap.wall_thickness + panel.half.z() + 0.03f);
  if (opening.kind == Opening::kDoorway) goal.setY(panel.half.y() + 0.02f);
  const btVector3 error = goal - centre;
  const float along = error.dot(opening.normal);  // > 0: not there yet
  const btVector3 lateral = error - opening.normal * along;
  const float outward = std::atan2(opening.normal.x(), opening.normal.z());
  const float turn = wrap_half(outward - std::atan2(normal.x(), normal.z()));
  // the drone turns until the panel is square to the opening and lies between the drone and the
  // wall: a drone on the opening's side of its panel would go through the opening first and pin
  // the panel against the wall from outside. Of the two yaws that square the panel, the one that
  // puts the panel (bearing `bearing` from the drone's forward) on the wall's side.
  const btVector3 forward = me.forward();
  const btVector3 to_panel = horizontal(centre - p);
  const float yaw = std::atan2(forward.x(), forward.z());
  float want = yaw + turn;
  const float bearing = std::atan2(to_panel.x(), to_panel.z()) - yaw;
  if (std::cos(want + bearing - outward) < 0) want += kPi;
  const float heading = wrap(want - yaw);
  btVector3 prop_target = goal;
  if (lateral.length() > 0.2f || std::abs(heading) > 0.15f)
    prop_target = goal - opening.normal * 1.2f;  // line up inside the room first
  // the drone moves with the panel: fly the drone by the panel's error
  const auto a = steer(me, p + (prop_target - centre), p);
  std::copy(a.begin(), a.end(), c);
  c[3] = std::clamp(2.5f * heading, -1.0f, 1.0f);
  if (error.length() < 0.15f && std::abs(turn) < 0.1f) k[HideAndSeek::kLockBranch] = 1;
}

}  // namespace

bool write_scripted_hide_and_seek_actions(HideAndSeek& env, HideAndSeek::Team team,
                                          BehaviorView& view) {
  std::vector<int> claimed;
  const std::vector<int> open_ones =
      team == HideAndSeek::kHider ? open_openings(env) : std::vector<int>();
  for (int slot = 0; slot < view.slots(); ++slot) {
    if (!needs_action(view.step_type(slot))) continue;
    if (!env.agent(team, slot).present) continue;
    if (team == HideAndSeek::kSeeker)
      seeker_actions(env, view, slot);
    else
      hider_actions(env, view, slot, claimed, open_ones);
  }
  return true;
}

}  // namespace rlt::drone
