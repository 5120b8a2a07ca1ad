#include "env/drone/sphere_cast.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rlt::drone {

namespace {

// directions shorter than this along an axis count as parallel to it
constexpr float kParallel = 1e-12f;

// entry of o + t d into the box |x_k| <= grown_k for all k: returns false when the line misses it;
// otherwise t_enter (may be negative: o inside on every axis), t_exit and the axis of entry
// (-1 when o is inside on every axis that d crosses)
inline bool slab_entry(const float o[3], const float d[3], const float grown[3], float& t_enter,
                       float& t_exit, int& enter_axis) {
  t_enter = -std::numeric_limits<float>::infinity();
  t_exit = std::numeric_limits<float>::infinity();
  enter_axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::fabs(d[k]) < kParallel) {
      if (std::fabs(o[k]) > grown[k]) return false;
      continue;
    }
    const float inv = 1.0f / d[k];
    float t0 = (-grown[k] - o[k]) * inv;
    float t1 = (grown[k] - o[k]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_enter) {
      t_enter = t0;
      enter_axis = k;
    }
    t_exit = std::min(t_exit, t1);
  }
  return t_enter <= t_exit;
}

// first t in [0, best) at which o + t d enters a sphere of radius r about c (o outside it),
// or best
inline float sphere_entry(const float o[3], const float d[3], float a, const float c[3], float r,
                          float best) {
  const float w[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
  const float b = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
  if (b >= 0) return best;  // moving away
  const float cc = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - r * r;
  const float disc = b * b - a * cc;
  if (disc < 0) return best;
  const float t = std::max((-b - std::sqrt(disc)) / a, 0.0f);
  return t < best ? t : best;
}

// the start-in-contact rule of the header for a box: hit at 0 when the motion points into it
inline float overlap_box(const float o[3], const float d[3], const float h[3]) {
  float e[3];
  float e2 = 0;
  for (int k = 0; k < 3; ++k) {
    e[k] = o[k] - std::clamp(o[k], -h[k], h[k]);
    e2 += e[k] * e[k];
  }
  if (e2 > 0) return e[0] * d[0] + e[1] * d[1] + e[2] * d[2] < 0 ? 0.0f : kNoHit;
  // centre inside the core: the nearest face's outward normal
  int k = 0;
  for (int i = 1; i < 3; ++i) {
    if (h[i] - std::fabs(o[i]) < h[k] - std::fabs(o[k])) k = i;
  }
  const float outward = o[k] < 0 ? -1.0f : 1.0f;
  return d[k] * outward < 0 ? 0.0f : kNoHit;
}

// first entry of o + t d, t in [0, t_max), into the box of half extents h grown by r, for o
// outside the grown box's rounded shape: the minimum over its pieces (face slabs, edge cylinders,
// corner spheres), or kNoHit
float rounded_box_pieces(const float o[3], const float d[3], const float h[3], float r,
                         float t_max) {
  float best = t_max;
  // face slabs: the box grown by r along one axis
  for (int k = 0; k < 3; ++k) {
    float grown[3] = {h[0], h[1], h[2]};
    grown[k] += r;
    float t_enter, t_exit;
    int axis;
    if (slab_entry(o, d, grown, t_enter, t_exit, axis) && t_enter >= 0 && t_enter < best) {
      best = t_enter;
    }
  }
  // edge cylinders of radius r, entered through their side within the edge's length (an entry
  // through an end cap is an entry into the corner sphere there, found below)
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const float a = d[i] * d[i] + d[j] * d[j];
    if (a < kParallel) continue;  // moving along the edge: only caps and faces can be entered
    for (int si = -1; si <= 1; si += 2) {
      for (int sj = -1; sj <= 1; sj += 2) {
        const float wi = o[i] - si * h[i], wj = o[j] - sj * h[j];
        const float b = wi * d[i] + wj * d[j];
        const float c = wi * wi + wj * wj - r * r;
        if (b >= 0 || c < 0) continue;  // moving away from the edge, or beyond its end
        const float disc = b * b - a * c;
        if (disc < 0) continue;
        const float t = std::max((-b - std::sqrt(disc)) / a, 0.0f);
        if (t < best && std::fabs(o[k] + t * d[k]) <= h[k]) best = t;
      }
    }
  }
  // corner spheres of radius r
  const float a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  for (int corner = 0; corner < 8; ++corner) {
    const float c[3] = {corner & 1 ? h[0] : -h[0], corner & 2 ? h[1] : -h[1],
                        corner & 4 ? h[2] : -h[2]};
    best = sphere_entry(o, d, a, c, r, best);
  }
  return best < t_max ? best : kNoHit;
}

}  // namespace

float sweep_sphere_aligned_box(const float origin[3], const float delta[3], const float half[3],
                               float radius, float t_max) {
  const float grown[3] = {half[0] + radius, half[1] + radius, half[2] + radius};
  float t_enter, t_exit;
  int axis;
  if (!slab_entry(origin, delta, grown, t_enter, t_exit, axis)) return kNoHit;
  if (t_exit < 0 || t_enter >= t_max) return kNoHit;
  if (t_enter >= 0) {
    // entering the grown box through a face: a hit if the entry point is on that face's slab
    // (not beyond an edge of the core box), which always holds for a thin ray
    bool on_face_slab = true;
    for (int k = 0; k < 3; ++k) {
      if (k != axis && std::fabs(origin[k] + t_enter * delta[k]) > half[k]) on_face_slab = false;
    }
    if (on_face_slab || radius <= 0) return t_enter;
  } else {
    // starting inside the grown box: in contact when within radius of the core
    float e2 = 0;
    for (int k = 0; k < 3; ++k) {
      const float e = std::fabs(origin[k]) - half[k];
      if (e > 0) e2 += e * e;
    }
    if (e2 <= radius * radius) return overlap_box(origin, delta, half);
  }
  return rounded_box_pieces(origin, delta, half, radius, t_max);
}

float sweep_sphere_box(const btVector3& from, const btVector3& to, float radius,
                       const OrientedBox& box) {
  const btVector3 w = from - box.centre;
  const btVector3 delta = to - from;
  if (delta.length2() == 0) return kNoHit;
  float o[3], d[3], core[3];
  for (int k = 0; k < 3; ++k) {
    const btVector3 axis = box.basis.getColumn(k);
    o[k] = axis.dot(w);
    d[k] = axis.dot(delta);
    core[k] = std::max(box.half[k] - box.rounding, 0.0f);
  }
  const float t = sweep_sphere_aligned_box(o, d, core, radius + box.rounding, 1.0f);
  return t <= 1.0f ? t : kNoHit;
}

float sweep_sphere_sphere(const btVector3& from, const btVector3& to, float radius,
                          const btVector3& centre, float sphere_radius) {
  const btVector3 delta = to - from;
  const float a = delta.length2();
  if (a == 0) return kNoHit;
  const btVector3 w = from - centre;
  const float b = w.dot(delta);
  const float r = radius + sphere_radius;
  const float c = w.length2() - r * r;
  // in contact at the start: a hit at 0 when moving towards the centre, else nothing
  if (c <= 0) return b < 0 ? 0.0f : kNoHit;
  if (b >= 0) return kNoHit;
  const float disc = b * b - a * c;
  if (disc < 0) return kNoHit;
  const float t = (-b - std::sqrt(disc)) / a;
  return t <= 1.0f ? std::max(t, 0.0f) : kNoHit;
}

void first_hits(const ShapeSnapshot& scene, const btVector3& from, const btVector3* directions,
                int num_rays, float length, float radius, const btCollisionObject* ignore,
                CastHit* hits) {
  if (num_rays > kMaxFanRays) throw std::invalid_argument("first_hits: too many rays");
  const float ox = from.x(), oy = from.y(), oz = from.z();
  // per ray: unit direction, and the distance of the closest hit so far (m); `length` while none
  // (a touch at exactly the end of the segment is not a hit)
  float ux[kMaxFanRays], uy[kMaxFanRays], uz[kMaxFanRays], best[kMaxFanRays];
  for (int r = 0; r < num_rays; ++r) {
    ux[r] = directions[r].x();
    uy[r] = directions[r].y();
    uz[r] = directions[r].z();
    best[r] = length;
    hits[r] = CastHit{};
  }
  if (!(length > 0)) return;

  // spheres: exact, as cheap as any bound
  const SphereArrays& s = scene.spheres();
  for (int n = 0, size = s.size(); n < size; ++n) {
    if (s.object[n] == ignore) continue;
    const float wx = s.centre_x[n] - ox, wy = s.centre_y[n] - oy, wz = s.centre_z[n] - oz;
    const float w2 = wx * wx + wy * wy + wz * wz;
    const float grown = s.radius[n] + radius;
    for (int r = 0; r < num_rays; ++r) {
      const float along = wx * ux[r] + wy * uy[r] + wz * uz[r];  // centre along the ray (m)
      const float miss2 = w2 - along * along;  // squared distance of the centre from the line
      if (along <= 0 || miss2 > grown * grown || along - grown >= best[r]) continue;
      // in contact at the start and moving towards the centre (along > 0): a hit at 0
      const float t = w2 <= grown * grown ? 0.0f : along - std::sqrt(grown * grown - miss2);
      if (t < best[r]) {
        best[r] = t;
        hits[r].kind = CastHit::kSphere;
        hits[r].index = n;
      }
    }
  }

  // boxes: cull by bounding sphere against each ray's best hit so far, then the exact cast in the
  // box's frame (the start's local coordinates are shared by all rays)
  const BoxArrays& b = scene.boxes();
  for (int n = 0, size = b.size(); n < size; ++n) {
    if (b.object[n] == ignore) continue;
    const float wx = b.centre_x[n] - ox, wy = b.centre_y[n] - oy, wz = b.centre_z[n] - oz;
    const float w2 = wx * wx + wy * wy + wz * wz;
    // slack for rounding in miss2 (the bound only has to be conservative)
    const float bound = b.bound[n] + radius + 1e-3f;
    const float a0x = b.axis0_x[n], a0y = b.axis0_y[n], a0z = b.axis0_z[n];
    const float a1x = b.axis1_x[n], a1y = b.axis1_y[n], a1z = b.axis1_z[n];
    const float a2x = b.axis2_x[n], a2y = b.axis2_y[n], a2z = b.axis2_z[n];
    const float o[3] = {-(a0x * wx + a0y * wy + a0z * wz), -(a1x * wx + a1y * wy + a1z * wz),
                        -(a2x * wx + a2y * wy + a2z * wz)};
    const float rounding = b.rounding[n];
    const float core[3] = {std::max(b.half_x[n] - rounding, 0.0f),
                           std::max(b.half_y[n] - rounding, 0.0f),
                           std::max(b.half_z[n] - rounding, 0.0f)};
    for (int r = 0; r < num_rays; ++r) {
      const float along = wx * ux[r] + wy * uy[r] + wz * uz[r];
      const float miss2 = w2 - along * along;
      if (miss2 > bound * bound) continue;
      const float half_chord = std::sqrt(bound * bound - miss2);
      if (along + half_chord < 0 || along - half_chord >= best[r]) continue;
      const float d[3] = {a0x * ux[r] + a0y * uy[r] + a0z * uz[r],
                          a1x * ux[r] + a1y * uy[r] + a1z * uz[r],
                          a2x * ux[r] + a2y * uy[r] + a2z * uz[r]};
      const float t = sweep_sphere_aligned_box(o, d, core, radius + rounding, best[r]);
      if (t < best[r]) {
        best[r] = t;
        hits[r].kind = CastHit::kBox;
        hits[r].index = n;
      }
    }
  }

  const float inv_length = 1.0f / length;
  for (int r = 0; r < num_rays; ++r) {
    CastHit& hit = hits[r];
    if (hit.kind == CastHit::kBox) {
      hit.tag = b.tag[hit.index];
      hit.object = b.object[hit.index];
    } else if (hit.kind == CastHit::kSphere) {
      hit.tag = s.tag[hit.index];
      hit.object = s.object[hit.index];
    }
    if (hit.hit()) hit.fraction = std::min(best[r] * inv_length, 1.0f);
  }
}

CastHit first_hit(const ShapeSnapshot& scene, const btVector3& from, const btVector3& to,
                  float radius, const btCollisionObject* ignore) {
  CastHit hit;
  const btVector3 delta = to - from;
  const float length = delta.length();
  if (!(length > 0)) return hit;
  const btVector3 direction = delta / length;
  first_hits(scene, from, &direction, 1, length, radius, ignore, &hit);
  return hit;
}

}  // namespace rlt::drone
