// ShapeSnapshot: a per-frame copy of a btCollisionWorld's collision objects as analytic primitives,
// in structure-of-arrays form, for casts that do not go through Bullet (sphere_cast.h, RaySensor).
//
// Primitives (metres, world frame, y up):
//   boxes:   a btBoxShape: centre, rotation as three unit axes (the columns of the world basis),
//            half extents with Bullet's margin (btBoxShape::getHalfExtentsWithMargin(), i.e. the
//            half extents the box was built with) and the margin itself as `rounding`. Bullet's
//            GJK sees a box as a core box of half extents half - rounding swept by a sphere of
//            radius rounding: faces where the half extents say, edges and corners rounded with the
//            margin (0.04 m by default; Bullet caps it at a tenth of the smallest half extent, so
//            0.01 m for the 0.2 m thick walls). Casts use that shape, so that they agree with
//            btCollisionWorld::convexSweepTest.
//   spheres: a btSphereShape: centre and radius (its margin is its radius, nothing is added).
// Each primitive keeps its Tag (tag_of) and the btCollisionObject it came from, and a bounding
// radius about its centre (|half| for a box) for cheap culling.
// capture() refills the arrays from the world's collision object array in its order; it reuses the
// capacity, so once the arrays have grown to the world's size it does not allocate. Any other shape
// type throws std::invalid_argument naming the shape. A snapshot is only valid until the world
// moves or changes: the object pointers are for identification (e.g. to ignore the caster), not for
// reading state later. Capturing the level-4 arena with its drones, props and obstacles (33
// objects) takes about 0.4 us, so static bodies are not cached across frames.
#ifndef RLT_ENV_DRONE_SHAPE_SNAPSHOT_H_
#define RLT_ENV_DRONE_SHAPE_SNAPSHOT_H_

#include <btBulletDynamicsCommon.h>

#include <vector>

#include "env/drone/bullet_world.h"

namespace rlt::drone {

// oriented boxes, one entry per box in every array
struct BoxArrays {
  std::vector<float> centre_x, centre_y, centre_z;  // [n] centre (m)
  // [n] each: unit axes of the box in world coordinates, axis k = (axis_k_x, axis_k_y, axis_k_z);
  // a world vector v has local coordinates (axis_0 . v, axis_1 . v, axis_2 . v)
  std::vector<float> axis0_x, axis0_y, axis0_z;
  std::vector<float> axis1_x, axis1_y, axis1_z;
  std::vector<float> axis2_x, axis2_y, axis2_z;
  std::vector<float> half_x, half_y, half_z;     // [n] half extents with margin (m)
  std::vector<float> rounding;                   // [n] Bullet margin: edge and corner radius (m)
  std::vector<float> bound;                      // [n] bounding sphere radius about the centre (m)
  std::vector<int> tag;                          // [n] Tag
  std::vector<const btCollisionObject*> object;  // [n] source object

  int size() const { return static_cast<int>(tag.size()); }
  void clear();
};

// spheres, one entry per sphere in every array
struct SphereArrays {
  std::vector<float> centre_x, centre_y, centre_z;  // [n] centre (m)
  std::vector<float> radius;                        // [n] radius (m)
  std::vector<int> tag;                             // [n] Tag
  std::vector<const btCollisionObject*> object;     // [n] source object

  int size() const { return static_cast<int>(tag.size()); }
  void clear();
};

class ShapeSnapshot {
 public:
  // refills the snapshot with every collision object of `world` (throws std::invalid_argument on a
  // shape that is neither a btBoxShape nor a btSphereShape)
  void capture(const btCollisionWorld& world);
  // appends one object (what capture() does for each object of the world)
  void add(const btCollisionObject& object);
  void clear();

  const BoxArrays& boxes() const { return boxes_; }
  const SphereArrays& spheres() const { return spheres_; }
  int size() const { return boxes_.size() + spheres_.size(); }

 private:
  BoxArrays boxes_;
  SphereArrays spheres_;
};

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_SHAPE_SNAPSHOT_H_
