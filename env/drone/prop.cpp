#include "env/drone/prop.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace rlt::drone {

namespace {

constexpr float kPi = 3.14159265358979f;

btQuaternion yaw_rotation(float yaw) { return btQuaternion(btVector3(0, 1, 0), yaw); }

// the held pose of a square hold (PropParams::square_hold)
btTransform squared(const btTransform& prop_in_drone, const btVector3& half, float drone_radius) {
  // the panel's normal is its local z, the drone's forward its local z: turn the panel about the
  // vertical by the multiple of pi nearest its yaw in the drone's frame (0 or pi: face-on)
  const btVector3 normal = prop_in_drone.getBasis().getColumn(2);
  const float yaw = std::atan2(normal.x(), normal.z());
  const float face_on = kPi * std::round(yaw / kPi);
  btTransform out(yaw_rotation(face_on), prop_in_drone.getOrigin());
  // its near face at least a hand's breadth in front of the drone's sphere
  const float clear = drone_radius + half.z() + 0.05f;
  if (out.getOrigin().z() < clear) out.getOrigin().setZ(clear);
  return out;
}

// continuous collision detection for a box: sweep when a frame moves it by half its thinnest side
void enable_ccd(btRigidBody* body, const btVector3& half) {
  const float thin = std::min({half.x(), half.y(), half.z()});
  body->setCcdMotionThreshold(0.5f * thin);
  body->setCcdSweptSphereRadius(0.9f * thin);
}

// per-body gravity that ignores the world's, set after the body was added
void set_own_gravity(btRigidBody* body, const btVector3& gravity) {
  body->setFlags(body->getFlags() | BT_DISABLE_WORLD_GRAVITY);
  body->setGravity(gravity);
}

}  // namespace

PropSet::PropSet(BulletWorld& world, const PropParams& params)
    : world_(world), params_(params), epoch_(world.epoch()) {}

PropSet::~PropSet() {
  if (world_.epoch() != epoch_) return;  // the world already destroyed our constraints
  for (Prop& prop : props_) drop(prop);
}

int PropSet::add(const btVector3& centre, float yaw) { return add(centre, yaw, params_.half); }

int PropSet::add(const btVector3& centre, float yaw, const btVector3& half) {
  DynamicBodyDesc desc;
  desc.position = centre;
  desc.rotation = yaw_rotation(yaw);
  desc.mass = params_.mass;
  desc.tag = kProp;
  Prop prop;
  prop.half = half;
  prop.body = world_.add_dynamic_body(std::make_unique<btBoxShape>(half), desc);
  set_own_gravity(prop.body, params_.gravity);
  prop.body->setFriction(params_.friction);
  prop.body->setRestitution(0.0f);
  prop.body->setDamping(params_.linear_damping, params_.angular_damping);
  if (params_.ccd) enable_ccd(prop.body, half);
  props_.push_back(prop);
  return size() - 1;
}

btVector3 PropSet::closest_point(const DroneBody& drone, int i) const {
  const Prop& prop = props_[i];
  const btTransform& pose = prop.body->getWorldTransform();
  btVector3 local = pose.invXform(drone.position());
  for (int k = 0; k < 3; ++k) local[k] = std::clamp(local[k], -prop.half[k], prop.half[k]);
  return pose * local;
}

float PropSet::gap(const DroneBody& drone, int i) const {
  const float d = (closest_point(drone, i) - drone.position()).length();
  return std::max(0.0f, d - drone.params().radius);
}

bool PropSet::in_front(const DroneBody& drone, int i) const {
  const btVector3 to = closest_point(drone, i) - drone.position();
  const float length = to.length();
  if (length < 1e-4f) return true;  // the centre is inside the box
  const float cos_angle = to.dot(drone.forward()) / length;
  return cos_angle >= std::cos(params_.cone_degrees * kPi / 180.0f);
}

template <typename Ok>
int PropSet::nearest(const DroneBody& drone, unsigned allowed, Ok ok) const {
  int best = -1;
  float best_gap = std::numeric_limits<float>::infinity();
  for (int i = 0; i < size(); ++i) {
    // a mask names the first 32 props; the ones past it only kAllProps lets through
    const bool may = i < 32 ? ((allowed >> i) & 1u) != 0 : allowed == kAllProps;
    if (!may || !ok(props_[i])) continue;
    const float g = gap(drone, i);
    if (g > params_.reach || g >= best_gap || !in_front(drone, i)) continue;
    best = i;
    best_gap = g;
  }
  return best;
}

void PropSet::drop(Prop& prop) {
  // the world may have dropped it already with a removed body
  if (prop.grab != nullptr && world_.has_constraint(prop.grab)) world_.remove_constraint(prop.grab);
  prop.grab = nullptr;
  prop.held_by = nullptr;
}

int PropSet::held_by(const DroneBody& drone) const {
  for (int i = 0; i < size(); ++i) {
    if (props_[i].held_by == &drone.body()) return i;
  }
  return -1;
}

int PropSet::grab(const DroneBody& drone, unsigned allowed) {
  const int held = held_by(drone);
  if (held >= 0) return held;
  const int i = grabbable(drone, allowed);
  if (i < 0) return -1;
  Prop& prop = props_[i];
  // the drone's body is owned by the world; the constraint needs it non-const
  btRigidBody& a = const_cast<btRigidBody&>(drone.body());
  // the prop's pose in the drone's frame, kept while held: turning the drone turns the prop
  btTransform prop_in_a = a.getWorldTransform().inverse() * prop.body->getWorldTransform();
  if (params_.square_hold) prop_in_a = squared(prop_in_a, prop.half, drone.params().radius);
  prop.grab = world_.add_constraint(
      std::make_unique<btFixedConstraint>(a, *prop.body, prop_in_a, btTransform::getIdentity()),
      true);
  prop.held_by = &drone.body();
  prop.body->activate(true);
  return i;
}

int PropSet::release(const DroneBody& drone) {
  const int i = held_by(drone);
  if (i >= 0) drop(props_[i]);
  return i;
}

int PropSet::grabbable(const DroneBody& drone, unsigned allowed) const {
  return nearest(drone, allowed, [](const Prop& p) { return !p.locked() && p.held_by == nullptr; });
}

int PropSet::lockable(const DroneBody& drone, unsigned allowed) const {
  return nearest(drone, allowed, [](const Prop& p) { return !p.locked(); });
}

int PropSet::unlockable(const DroneBody& drone, int team, unsigned allowed) const {
  const int i = nearest(drone, allowed, [](const Prop& p) { return p.locked(); });
  return i >= 0 && props_[i].locked_by == team ? i : -1;
}

int PropSet::lock(const DroneBody& drone, int team, unsigned allowed) {
  const int i = lockable(drone, allowed);
  if (i < 0 || team == kNoTeam) return -1;
  Prop& prop = props_[i];
  drop(prop);
  btRigidBody* body = prop.body;
  body->setLinearVelocity(btVector3(0, 0, 0));
  body->setAngularVelocity(btVector3(0, 0, 0));
  body->clearForces();
  body->setMassProps(0.0f, btVector3(0, 0, 0));
  body->setLinearFactor(btVector3(0, 0, 0));
  body->setAngularFactor(btVector3(0, 0, 0));
  body->updateInertiaTensor();
  prop.locked_by = team;
  return i;
}

int PropSet::unlock(const DroneBody& drone, int team, unsigned allowed) {
  const int i = unlockable(drone, team, allowed);
  if (i < 0) return -1;
  Prop& prop = props_[i];
  btRigidBody* body = prop.body;
  btVector3 inertia(0, 0, 0);
  body->getCollisionShape()->calculateLocalInertia(params_.mass, inertia);
  body->setMassProps(params_.mass, inertia);
  body->setLinearFactor(btVector3(1, 1, 1));
  body->setAngularFactor(btVector3(1, 1, 1));
  body->updateInertiaTensor();
  set_own_gravity(body, params_.gravity);
  body->activate(true);
  prop.locked_by = kNoTeam;
  return i;
}

btRigidBody* add_obstacle(BulletWorld& world, const btVector3& centre, float yaw,
                          const ObstacleParams& params) {
  DynamicBodyDesc desc;
  desc.position = centre;
  desc.rotation = yaw_rotation(yaw);
  desc.mass = params.mass;
  desc.tag = kObstacle;
  btRigidBody* body = world.add_dynamic_body(std::make_unique<btBoxShape>(params.half), desc);
  set_own_gravity(body, params.gravity);
  body->setFriction(params.friction);
  body->setRestitution(0.0f);
  body->setDamping(params.linear_damping, params.angular_damping);
  enable_ccd(body, params.half);
  return body;
}

}  // namespace rlt::drone
