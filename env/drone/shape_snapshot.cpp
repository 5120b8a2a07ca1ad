#include "env/drone/shape_snapshot.h"

#include <stdexcept>
#include <string>

namespace rlt::drone {

void BoxArrays::clear() {
  for (std::vector<float>* v :
       {&centre_x, &centre_y, &centre_z, &axis0_x, &axis0_y, &axis0_z, &axis1_x, &axis1_y, &axis1_z,
        &axis2_x, &axis2_y, &axis2_z, &half_x, &half_y, &half_z, &rounding, &bound}) {
    v->clear();
  }
  tag.clear();
  object.clear();
}

void SphereArrays::clear() {
  centre_x.clear();
  centre_y.clear();
  centre_z.clear();
  radius.clear();
  tag.clear();
  object.clear();
}

void ShapeSnapshot::clear() {
  boxes_.clear();
  spheres_.clear();
}

void ShapeSnapshot::capture(const btCollisionWorld& world) {
  clear();
  const btCollisionObjectArray& objects = world.getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) add(*objects[i]);
}

void ShapeSnapshot::add(const btCollisionObject& object) {
  const btCollisionShape* shape = object.getCollisionShape();
  const btTransform& pose = object.getWorldTransform();
  const btVector3& centre = pose.getOrigin();
  switch (shape->getShapeType()) {
    case BOX_SHAPE_PROXYTYPE: {
      const auto* box = static_cast<const btBoxShape*>(shape);
      const btVector3 half = box->getHalfExtentsWithMargin();
      const btMatrix3x3& basis = pose.getBasis();
      BoxArrays& b = boxes_;
      b.centre_x.push_back(centre.x());
      b.centre_y.push_back(centre.y());
      b.centre_z.push_back(centre.z());
      // the box's local axis k in world coordinates is column k of the basis
      b.axis0_x.push_back(basis[0][0]);
      b.axis0_y.push_back(basis[1][0]);
      b.axis0_z.push_back(basis[2][0]);
      b.axis1_x.push_back(basis[0][1]);
      b.axis1_y.push_back(basis[1][1]);
      b.axis1_z.push_back(basis[2][1]);
      b.axis2_x.push_back(basis[0][2]);
      b.axis2_y.push_back(basis[1][2]);
      b.axis2_z.push_back(basis[2][2]);
      b.half_x.push_back(half.x());
      b.half_y.push_back(half.y());
      b.half_z.push_back(half.z());
      b.rounding.push_back(box->getMargin());
      b.bound.push_back(half.length());
      b.tag.push_back(tag_of(object));
      b.object.push_back(&object);
      return;
    }
    case SPHERE_SHAPE_PROXYTYPE: {
      const auto* sphere = static_cast<const btSphereShape*>(shape);
      SphereArrays& s = spheres_;
      s.centre_x.push_back(centre.x());
      s.centre_y.push_back(centre.y());
      s.centre_z.push_back(centre.z());
      s.radius.push_back(sphere->getRadius());
      s.tag.push_back(tag_of(object));
      s.object.push_back(&object);
      return;
    }
    default:
      throw std::invalid_argument(std::string("ShapeSnapshot: unsupported collision shape ") +
                                  shape->getName() + " (type " +
                                  std::to_string(shape->getShapeType()) + ")");
  }
}

}  // namespace rlt::drone
