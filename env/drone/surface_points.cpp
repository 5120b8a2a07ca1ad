#include "env/drone/surface_points.h"

#include <algorithm>
#include <cmath>

namespace rlt::drone {
namespace {

constexpr float kPi = 3.14159265358979f;

// whether a body carries one of the sensors' tags (BulletWorld tags every body it creates)
bool has_tag(const btCollisionObject& object) {
  return object.getUserIndex() >= 0 && object.getUserIndex() < kNumTags;
}

// cell centres of the face of a box of half extents `half` whose normal is +-axis `normal_axis`
void sample_box_face(const btVector3& half, int normal_axis, float sign, float resolution,
                     std::vector<btVector3>& out) {
  const int u_axis = (normal_axis + 1) % 3;
  const int v_axis = (normal_axis + 2) % 3;
  const float a = half[u_axis], b = half[v_axis];
  const int nu = std::max(1, static_cast<int>(std::ceil(2.0f * a / resolution - 1e-4f)));
  const int nv = std::max(1, static_cast<int>(std::ceil(2.0f * b / resolution - 1e-4f)));
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      btVector3 p(0, 0, 0);
      p[normal_axis] = sign * half[normal_axis];
      p[u_axis] = -a + (i + 0.5f) * 2.0f * a / nu;
      p[v_axis] = -b + (j + 0.5f) * 2.0f * b / nv;
      out.push_back(p);
    }
  }
}

void sample_box(const btVector3& half, float resolution, std::vector<btVector3>& out) {
  for (int axis = 0; axis < 3; ++axis) {
    sample_box_face(half, axis, 1.0f, resolution, out);
    sample_box_face(half, axis, -1.0f, resolution, out);
  }
}

// Fibonacci spiral: equal-area bands in y, golden-angle steps in azimuth
void sample_sphere(float radius, float resolution, std::vector<btVector3>& out) {
  const float area = 4.0f * kPi * radius * radius;
  const int n = std::max(4, static_cast<int>(std::ceil(area / (resolution * resolution))));
  const float golden_angle = kPi * (3.0f - std::sqrt(5.0f));
  for (int k = 0; k < n; ++k) {
    const float y = 1.0f - 2.0f * (k + 0.5f) / n;
    const float ring = std::sqrt(std::max(0.0f, 1.0f - y * y));
    const float phi = golden_angle * k;
    out.emplace_back(radius * ring * std::cos(phi), radius * y, radius * ring * std::sin(phi));
  }
}

// samples a supported shape in its local frame; false for other shapes
bool sample_shape(const btCollisionShape& shape, float resolution, std::vector<btVector3>& out) {
  switch (shape.getShapeType()) {
    case BOX_SHAPE_PROXYTYPE:
      sample_box(static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin(), resolution, out);
      return true;
    case SPHERE_SHAPE_PROXYTYPE:
      sample_sphere(static_cast<const btSphereShape&>(shape).getRadius(), resolution, out);
      return true;
    default:
      return false;
  }
}

bool is_box(const btCollisionObject& object) {
  return object.getCollisionShape()->getShapeType() == BOX_SHAPE_PROXYTYPE;
}

// a wide thin horizontal box: floor or ceiling
bool is_slab(const btCollisionObject& object, float aspect) {
  if (!is_box(object)) return false;
  btVector3 lo, hi;
  object.getCollisionShape()->getAabb(object.getWorldTransform(), lo, hi);
  const btVector3 extent = hi - lo;
  return extent.y() * aspect < extent.x() && extent.y() * aspect < extent.z();
}

// inside or within `tolerance` of the box of a static object
bool inside_box(const btCollisionObject& box, const btVector3& world_point, float tolerance) {
  const btVector3 half =
      static_cast<const btBoxShape*>(box.getCollisionShape())->getHalfExtentsWithMargin();
  const btVector3 local = box.getWorldTransform().invXform(world_point);
  return std::fabs(local.x()) <= half.x() + tolerance &&
         std::fabs(local.y()) <= half.y() + tolerance &&
         std::fabs(local.z()) <= half.z() + tolerance;
}

bool inside_keep(const btVector3& p, const btVector3& lo, const btVector3& hi) {
  return p.x() >= lo.x() && p.y() >= lo.y() && p.z() >= lo.z() && p.x() <= hi.x() &&
         p.y() <= hi.y() && p.z() <= hi.z();
}

// world = pose * local for n points (out of line: GCC 12 vectorizes it here, not inlined)
__attribute__((noinline)) void transform_points(const btTransform& pose, int n,
                                                const float* __restrict lx,
                                                const float* __restrict ly,
                                                const float* __restrict lz, float* __restrict wx,
                                                float* __restrict wy, float* __restrict wz) {
  const btMatrix3x3& r = pose.getBasis();
  const float r00 = r[0][0], r01 = r[0][1], r02 = r[0][2];
  const float r10 = r[1][0], r11 = r[1][1], r12 = r[1][2];
  const float r20 = r[2][0], r21 = r[2][1], r22 = r[2][2];
  const float tx = pose.getOrigin().x(), ty = pose.getOrigin().y(), tz = pose.getOrigin().z();
  for (int i = 0; i < n; ++i) {
    wx[i] = r00 * lx[i] + r01 * ly[i] + r02 * lz[i] + tx;
    wy[i] = r10 * lx[i] + r11 * ly[i] + r12 * lz[i] + ty;
    wz[i] = r20 * lx[i] + r21 * ly[i] + r22 * lz[i] + tz;
  }
}

}  // namespace

SurfacePoints::SurfacePoints(const SurfacePointsParams& params) : params_(params) {}

int SurfacePoints::body_index(const btCollisionObject& object) const {
  for (int i = 0; i < num_bodies(); ++i) {
    if (bodies_[i].object == &object) return i;
  }
  return -1;
}

void SurfacePoints::rebuild(const btCollisionWorld& world) {
  x_.clear();
  y_.clear();
  z_.clear();
  tag_.clear();
  local_x_.clear();
  local_y_.clear();
  local_z_.clear();
  bodies_.clear();
  num_unsupported_ = 0;
  const btCollisionObjectArray& objects = world.getCollisionObjectArray();
  num_objects_ = objects.size();

  // static boxes (slabs included) bury the points of their neighbours
  std::vector<const btCollisionObject*> static_boxes;
  for (int i = 0; i < objects.size(); ++i) {
    if (objects[i]->isStaticObject() && is_box(*objects[i])) static_boxes.push_back(objects[i]);
  }

  std::vector<btVector3> local;
  auto push = [&](const btVector3& p, Tag tag) {
    x_.push_back(p.x());
    y_.push_back(p.y());
    z_.push_back(p.z());
    tag_.push_back(tag);
  };

  // static bodies first, in world coordinates, without buried or outside points
  for (int i = 0; i < objects.size(); ++i) {
    const btCollisionObject& object = *objects[i];
    if (!object.isStaticObject() || !has_tag(object)) continue;
    if (!params_.detect_slabs && is_slab(object, params_.slab_aspect)) continue;
    local.clear();
    if (!sample_shape(*object.getCollisionShape(), params_.static_resolution, local)) {
      ++num_unsupported_;
      continue;
    }
    SurfaceBody body{&object, size(), size(), false};
    for (const btVector3& l : local) {
      const btVector3 p = object.getWorldTransform() * l;
      if (!inside_keep(p, params_.static_keep_min, params_.static_keep_max)) continue;
      bool buried = false;
      for (const btCollisionObject* other : static_boxes) {
        if (other != &object && inside_box(*other, p, params_.bury_tolerance)) {
          buried = true;
          break;
        }
      }
      if (!buried) push(p, tag_of(object));
    }
    body.end = size();
    bodies_.push_back(body);
  }
  num_static_points_ = size();

  // dynamic bodies: local points cached, world points filled by the transform below
  for (int i = 0; i < objects.size(); ++i) {
    const btCollisionObject& object = *objects[i];
    if (object.isStaticObject() || !has_tag(object)) continue;
    local.clear();
    if (!sample_shape(*object.getCollisionShape(), params_.dynamic_resolution, local)) {
      ++num_unsupported_;
      continue;
    }
    SurfaceBody body{&object, size(), size(), true};
    for (const btVector3& l : local) {
      local_x_.push_back(l.x());
      local_y_.push_back(l.y());
      local_z_.push_back(l.z());
      push(object.getWorldTransform() * l, tag_of(object));
    }
    body.end = size();
    bodies_.push_back(body);
  }
}

void SurfacePoints::update(const BulletWorld& world) {
  const btCollisionWorld& collision_world = world.world();
  if (world.epoch() != epoch_ || collision_world.getNumCollisionObjects() != num_objects_) {
    rebuild(collision_world);
    epoch_ = world.epoch();
    return;
  }
  // world = R * local + t per dynamic body, over its contiguous range
  for (const SurfaceBody& body : bodies_) {
    if (!body.dynamic) continue;
    const int local_begin = body.begin - num_static_points_;
    transform_points(body.object->getWorldTransform(), body.end - body.begin,
                     local_x_.data() + local_begin, local_y_.data() + local_begin,
                     local_z_.data() + local_begin, x_.data() + body.begin,
                     y_.data() + body.begin, z_.data() + body.begin);
  }
}

}  // namespace rlt::drone
