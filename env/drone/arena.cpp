#include "env/drone/arena.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rlt::drone {
namespace {

// outward normal of room side 0: -z, 1: +z, 2: +x, 3: -x
btVector3 side_normal(int side) {
  switch (side) {
    case 0:
      return btVector3(0, 0, -1);
    case 1:
      return btVector3(0, 0, 1);
    case 2:
      return btVector3(1, 0, 0);
    default:
      return btVector3(-1, 0, 0);
  }
}

}  // namespace

int open_openings_at_level(int level) {
  if (level < kMinLevel || level > kMaxLevel) {
    throw std::invalid_argument("arena level must be in [1, 4], got " + std::to_string(level));
  }
  return level;  // 1 doorway; 2 doorways; 2 doorways + 1 window; 2 doorways + 2 windows
}

CoverShares cover_shares(const Opening& opening, const btCollisionObject& body, float fade_depth,
                         float depth, int samples) {
  const float reach = std::max(depth, fade_depth);  // how far inside the rays go
  const btVector3 up(0, 1, 0);
  const btVector3 across = up.cross(opening.normal);  // horizontal, along the wall
  btTransform from = btTransform::getIdentity(), to = btTransform::getIdentity();
  int covered = 0;
  float graded = 0.0f;
  for (int i = 0; i < samples; ++i) {
    for (int j = 0; j < samples; ++j) {
      const float u = ((i + 0.5f) / samples - 0.5f) * opening.width;
      const float v = ((j + 0.5f) / samples - 0.5f) * opening.height;
      const btVector3 p = opening.centre + across * u + up * v;
      from.setOrigin(p + opening.normal * depth);
      to.setOrigin(p - opening.normal * reach);
      btCollisionWorld::ClosestRayResultCallback ray(from.getOrigin(), to.getOrigin());
      btCollisionWorld::rayTestSingle(from, to, const_cast<btCollisionObject*>(&body),
                                      body.getCollisionShape(), body.getWorldTransform(), ray);
      if (!ray.hasHit()) continue;
      // how far inside the wall's centre plane the body's face is where the ray meets it
      const float inside = ray.m_closestHitFraction * (depth + reach) - depth;
      if (inside <= depth) {
        ++covered;
        graded += 1.0f;
      } else {
        graded += (reach - inside) / (reach - depth);
      }
    }
  }
  const float n = static_cast<float>(samples * samples);
  return {covered / n, graded / n};
}

float covered_fraction(const Opening& opening, const btCollisionObject& body, float depth,
                       int samples) {
  return cover_shares(opening, body, depth, depth, samples).covered;
}

Arena::Arena(BulletWorld& world, const ArenaParams& params) : world_(world), params_(params) {
  const int n_open = params_.room ? open_openings_at_level(params_.level) : 0;
  const float t = params_.wall_thickness;
  const float h = params_.half_size;
  const float ht = 0.5f * t;
  const float top = params_.height;

  // floor and ceiling slabs, and the four boundary walls (their inner faces at +-half_size)
  const float outer = h + t;
  world_.add_static_box(btVector3(0, -ht, 0), btVector3(outer, ht, outer), kWall);
  world_.add_static_box(btVector3(0, top + ht, 0), btVector3(outer, ht, outer), kWall);
  const float wall_y = 0.5f * top;
  const btVector3 wall_half_x(ht, 0.5f * top + t, outer);
  const btVector3 wall_half_z(outer, 0.5f * top + t, ht);
  world_.add_static_box(btVector3(h + ht, wall_y, 0), wall_half_x, kWall);
  world_.add_static_box(btVector3(-h - ht, wall_y, 0), wall_half_x, kWall);
  world_.add_static_box(btVector3(0, wall_y, h + ht), wall_half_z, kWall);
  world_.add_static_box(btVector3(0, wall_y, -h - ht), wall_half_z, kWall);
  num_boxes_ = 6;

  if (!params_.room) return;

  // the room: each side a full-height segment from each corner to its opening, then the pieces
  // around the opening, then a chunk if the level leaves it closed
  const float r = params_.room_half;
  const float end = r + ht;  // segments reach over the corners so the L pieces are sealed
  for (int index = 0; index < kNumOpenings; ++index) {
    // the wall opening `index` is in
    const int side = params_.doorways_swapped && index < 2 ? 1 - index : index;
    const bool doorway = index < 2;
    const float w = doorway ? params_.door_width : params_.window_width;
    const float y0 = doorway ? 0.0f : params_.window_sill;
    const float y1 = doorway ? params_.door_height : params_.window_sill + params_.window_height;
    add_side_box(side, -end, -0.5f * w, 0.0f, top);
    add_side_box(side, 0.5f * w, end, 0.0f, top);
    if (y0 > 0.0f) add_side_box(side, -0.5f * w, 0.5f * w, 0.0f, y0);
    if (y1 < top) add_side_box(side, -0.5f * w, 0.5f * w, y1, top);
    const bool open = index < n_open;
    if (!open) add_side_box(side, -0.5f * w, 0.5f * w, y0, y1);
    const btVector3 n = side_normal(side);
    Opening opening;
    opening.kind = doorway ? Opening::kDoorway : Opening::kWindow;
    opening.centre = n * r + btVector3(0, 0.5f * (y0 + y1), 0);
    opening.width = w;
    opening.height = y1 - y0;
    opening.normal = n;
    opening.open = open;
    openings_.push_back(opening);
  }
}

void Arena::add_side_box(int side, float a, float b, float y0, float y1) {
  const float ht = 0.5f * params_.wall_thickness;
  const float r = params_.room_half;
  const float mid = 0.5f * (a + b), half_len = 0.5f * (b - a);
  const float y = 0.5f * (y0 + y1), half_y = 0.5f * (y1 - y0);
  btVector3 centre, half;
  if (side < 2) {  // a wall along x at z = -+r
    centre = btVector3(mid, y, side == 0 ? -r : r);
    half = btVector3(half_len, half_y, ht);
  } else {  // a wall along z at x = +-r
    centre = btVector3(side == 2 ? r : -r, y, mid);
    half = btVector3(ht, half_y, half_len);
  }
  world_.add_static_box(centre, half, kWall);
  ++num_boxes_;
}

int Arena::num_open() const {
  int n = 0;
  for (const Opening& o : openings_) n += o.open;
  return n;
}

bool Arena::inside_room(const btVector3& p) const {
  if (!params_.room) return false;
  const float inner = params_.room_half - 0.5f * params_.wall_thickness;
  return std::abs(p.x()) < inner && std::abs(p.z()) < inner && p.y() > 0.0f &&
         p.y() < params_.height;
}

bool Arena::inside_arena(const btVector3& p) const {
  const float h = params_.half_size;
  return std::abs(p.x()) < h && std::abs(p.z()) < h && p.y() > 0.0f && p.y() < params_.height;
}

}  // namespace rlt::drone
