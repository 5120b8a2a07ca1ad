// Sphere casts without Bullet: the exact first contact of a sphere of radius r moving in a straight
// line from `from` to `to` with an oriented box, a sphere, or a whole ShapeSnapshot. r = 0 is a
// thin ray. Units are metres; results are fractions of the segment from -> to, in [0, 1].
//
// Geometry: the moving sphere touches a shape exactly when its centre is inside the shape grown by
// r (the Minkowski sum). For a sphere of radius R that is a sphere of radius R + r. For a box of
// half extents h it is a rounded box: six face slabs (the box grown by r along one axis), twelve
// edge capsules (cylinders of radius r around the edges, ending in) eight corner spheres of radius
// r. The cast finds the entry of the segment into the grown shape: a slab test against the box
// grown by r on every axis gives the answer whenever the entry point lies on a face slab (the usual
// case); otherwise the first entry over the edge cylinders and corner spheres (and, for safety,
// the face slabs) is taken. A box may itself be rounded (`rounding`, Bullet's margin, see
// shape_snapshot.h): its core shrinks by the rounding and the sphere grows by it.
//
// Starting in contact: when the sphere already touches or overlaps a shape at `from` (its centre
// is inside the grown shape) the cast follows Bullet's btContinuousConvexCollision, which is what
// btCollisionWorld::convexSweepTest uses: it reports a hit at fraction 0 if the motion points into
// the shape (against the outward separating normal: from the closest point of the core shape to the
// centre, or, with the centre inside the core, the normal of the nearest face) and nothing at all
// otherwise (a sphere leaving an overlap does not see that shape). A segment of zero length hits
// nothing.
// Ties between shapes at the same fraction go to the first in snapshot order (spheres before
// boxes); Bullet's order there depends on its broadphase.
#ifndef RLT_ENV_DRONE_SPHERE_CAST_H_
#define RLT_ENV_DRONE_SPHERE_CAST_H_

#include <btBulletDynamicsCommon.h>

#include <limits>

#include "env/drone/shape_snapshot.h"

namespace rlt::drone {

// returned by the casts below when nothing is hit
inline constexpr float kNoHit = std::numeric_limits<float>::infinity();

// an oriented box: centre, rotation (columns are the box's axes in world coordinates), half
// extents, and the radius of its rounded edges (0: a sharp box; must not exceed any half extent)
struct OrientedBox {
  btVector3 centre;
  btMatrix3x3 basis;
  btVector3 half;
  float rounding = 0.0f;
};

// the fraction in [0, 1] of from -> to at which a sphere of `radius` first touches `box`, or kNoHit
float sweep_sphere_box(const btVector3& from, const btVector3& to, float radius,
                       const OrientedBox& box);
// the same against a sphere of radius `sphere_radius` centred at `centre`
float sweep_sphere_sphere(const btVector3& from, const btVector3& to, float radius,
                          const btVector3& centre, float sphere_radius);
// the core of sweep_sphere_box, in the box's frame: a box of half extents `half` centred at the
// origin along the axes, a sphere starting at `origin` moving by t * `delta`; returns the smallest
// t in [0, t_max) at which it touches, or kNoHit
float sweep_sphere_aligned_box(const float origin[3], const float delta[3], const float half[3],
                               float radius, float t_max);

// the closest hit of a cast over a snapshot
struct CastHit {
  enum Kind { kNone, kBox, kSphere };
  Kind kind = kNone;
  int index = -1;      // into scene.boxes() or scene.spheres(), by kind
  float fraction = 1;  // in [0, 1]; 1 on a miss
  int tag = -1;        // Tag of the object hit, -1 on a miss
  const btCollisionObject* object = nullptr;
  bool hit() const { return kind != kNone; }
};

// the first primitive of `scene` that a sphere of `radius` moving from -> to touches, skipping the
// primitives that came from `ignore` (may be null)
CastHit first_hit(const ShapeSnapshot& scene, const btVector3& from, const btVector3& to,
                  float radius, const btCollisionObject* ignore);

// first_hit for a fan of num_rays (<= kMaxFanRays) casts from one point: ray r goes from `from`
// to from + length * directions[r] (unit vectors) and its answer is written to hits[r]. The same
// answers as first_hit, cheaper: the per-primitive work is shared by the rays.
inline constexpr int kMaxFanRays = 128;
void first_hits(const ShapeSnapshot& scene, const btVector3& from, const btVector3* directions,
                int num_rays, float length, float radius, const btCollisionObject* ignore,
                CastHit* hits);

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_SPHERE_CAST_H_
