// SurfacePoints: a point cloud sampled on the surfaces of the colliders of a Bullet world, the
// input of the grid sensors (grid_sensor.h; SPEC.md section 6, "spatial grid" and "frontal grid").
// It follows the detection scheme of MBaske's Unity Grid Sensors: objects are not found by per-cell
// raycasts but by points scanned on their colliders at a fixed resolution.
//
// Sampling (metres, world frame, y up):
//   btBoxShape:    each of the six faces (2a x 2b) is cut into ceil(2a / res) x ceil(2b / res)
//                  equal cells and gets one point at each cell centre (so even a face smaller than
//                  res gets one point, and no point sits on an edge);
//   btSphereShape: n = max(4, ceil(4 pi r^2 / res^2)) points on a Fibonacci spiral (equal area
//                  per point, spacing about res).
//   Other shapes are not detectable (counted in num_unsupported()), nor are bodies whose tag_of()
//   is not a Tag (a body added to the btDynamicsWorld directly), so every point's tag is in
//   [0, kNumTags).
// Static bodies (isStaticObject() at build time: the arena's walls) use static_resolution and are
// sampled once, in world coordinates; a static point is dropped when it lies inside or on another
// static box (faces buried in a neighbouring wall, a chunk's sides against the wall it plugs, wall
// ends on the floor) or outside the static_keep box (the outer faces of the boundary walls, which
// are always behind the inner faces). Dropping them changes no grid observation from inside the
// arena (the nearer wall points win the wall channel) and saves time.
// Floor and ceiling: a static box whose vertical extent times slab_aspect is smaller than both
// horizontal extents is a slab and is not detectable unless detect_slabs is set: a floor 1 m below
// the drone would fill the whole lower hemisphere of a grid, and the vector observation already
// carries the height. Slabs still bury the points of other static boxes that touch them.
// Dynamic bodies (drones, props, obstacles) use dynamic_resolution; their points are cached in the
// body's local frame and re-transformed by its current world transform on every update().
// Layout: structure of arrays x, y, z, tag of size() points; static bodies first, then dynamic
// ones, each body owning the contiguous index range body(i) so that an observer can skip its own.
// Rebuild: update() resamples everything when the BulletWorld epoch (its resets) or the number of
// collision objects changed since the last build; call rebuild() after adding and removing the same
// number of bodies, or after moving a static body.
#ifndef RLT_ENV_DRONE_SURFACE_POINTS_H_
#define RLT_ENV_DRONE_SURFACE_POINTS_H_

#include <btBulletDynamicsCommon.h>

#include <cstdint>
#include <vector>

#include "env/drone/bullet_world.h"

namespace rlt::drone {

struct SurfacePointsParams {
  float static_resolution = 1.0f;   // point spacing on static bodies (walls) (m)
  float dynamic_resolution = 0.3f;  // point spacing on dynamic bodies (drones, props, obstacles) (m)
  bool detect_slabs = false;        // sample floor and ceiling slabs too
  float slab_aspect = 4.0f;         // a static box is a slab when height * aspect < width and depth
  // static points outside this world box are dropped (default: keep everything); e.g. the arena's
  // inner volume, so that the outer faces of the boundary walls cost nothing
  btVector3 static_keep_min = btVector3(-1e30f, -1e30f, -1e30f);
  btVector3 static_keep_max = btVector3(1e30f, 1e30f, 1e30f);
  float bury_tolerance = 1e-3f;  // a point within this of another static box is buried (m)
};

// the points of one detectable body: indices [begin, end) of the arrays
struct SurfaceBody {
  const btCollisionObject* object = nullptr;
  int begin = 0;
  int end = 0;
  bool dynamic = false;
};

class SurfacePoints {
 public:
  explicit SurfacePoints(const SurfacePointsParams& params = {});

  // resamples every body of `world` (static and dynamic) at the current poses
  void rebuild(const btCollisionWorld& world);
  // rebuilds if the world was reset or its number of objects changed, otherwise re-transforms the
  // dynamic bodies' points to their current poses
  void update(const BulletWorld& world);

  int size() const { return static_cast<int>(x_.size()); }
  const float* x() const { return x_.data(); }           // [size()] world x (m)
  const float* y() const { return y_.data(); }           // [size()] world y (m)
  const float* z() const { return z_.data(); }           // [size()] world z (m)
  const std::int32_t* tag() const { return tag_.data(); }  // [size()] Tag of the point's body

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  const SurfaceBody& body(int i) const { return bodies_[i]; }
  // index of the body holding `object`'s points, or -1 when it has none (slab, unsupported shape,
  // not in the world at the last build)
  int body_index(const btCollisionObject& object) const;

  int num_static_points() const { return num_static_points_; }
  int num_dynamic_points() const { return size() - num_static_points_; }
  int num_unsupported() const { return num_unsupported_; }  // bodies of other shapes, skipped
  const SurfacePointsParams& params() const { return params_; }

 private:
  SurfacePointsParams params_;
  long epoch_ = -1;       // BulletWorld epoch of the last build
  int num_objects_ = -1;  // collision objects in the world at the last build
  int num_static_points_ = 0;
  int num_unsupported_ = 0;
  std::vector<float> x_, y_, z_;   // [size()] world coordinates
  std::vector<std::int32_t> tag_;  // [size()]
  std::vector<SurfaceBody> bodies_;
  // local coordinates of the dynamic points, [num_dynamic_points()] each, in the order of x_
  // starting at num_static_points_
  std::vector<float> local_x_, local_y_, local_z_;
};

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_SURFACE_POINTS_H_
