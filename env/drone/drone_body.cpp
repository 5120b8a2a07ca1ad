#include "env/drone/drone_body.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace rlt::drone {

namespace {
float clip(float x) { return std::clamp(x, -1.0f, 1.0f); }
}  // namespace

DroneBody::DroneBody(BulletWorld& world, const btVector3& position, float yaw, Tag tag,
                     const DroneParams& params)
    : params_(params), dt_(world.dt()) {
  DynamicBodyDesc desc;
  desc.position = position;
  desc.rotation = btQuaternion(btVector3(0, 1, 0), yaw);
  desc.mass = params_.mass;
  desc.tag = tag;
  body_ = world.add_dynamic_body(std::make_unique<btSphereShape>(params_.radius), desc);

  // no gravity: opt out of the world's before and after being added
  body_->setFlags(body_->getFlags() | BT_DISABLE_WORLD_GRAVITY);
  body_->setGravity(btVector3(0, 0, 0));
  body_->setDamping(params_.linear_damping, params_.angular_damping);
  // upright: rotation about y only
  body_->setAngularFactor(btVector3(0, 1, 0));
  body_->setActivationState(DISABLE_DEACTIVATION);
  body_->setFriction(0.0f);
  body_->setRestitution(0.0f);
  if (params_.ccd) {
    // sweep whenever a frame moves the centre by more than half a radius
    body_->setCcdMotionThreshold(0.5f * params_.radius);
    body_->setCcdSweptSphereRadius(0.9f * params_.radius);
  }
}

void DroneBody::apply_action(float forward, float strafe, float vertical, float yaw_rate) {
  const btVector3 force =
      params_.max_force * (clip(forward) * this->forward() + clip(strafe) * right() +
                           clip(vertical) * btVector3(0, 1, 0));
  body_->clearForces();
  body_->setAngularVelocity(btVector3(0, clip(yaw_rate) * params_.max_yaw_rate, 0));
  cap_speed();
  // trim the thrust so that the frame ends no faster than max_speed (damping only slows it)
  const btVector3 v = body_->getLinearVelocity();
  btVector3 next = v + force * (dt_ / params_.mass);
  const btScalar speed = next.length();
  if (speed > params_.max_speed) next *= params_.max_speed / speed;
  body_->applyCentralForce((next - v) * (params_.mass / dt_));
}

void DroneBody::cap_speed() {
  const btVector3 v = body_->getLinearVelocity();
  const btScalar speed = v.length();
  if (speed > params_.max_speed) body_->setLinearVelocity(v * (params_.max_speed / speed));
}

btVector3 DroneBody::position() const { return body_->getWorldTransform().getOrigin(); }

btVector3 DroneBody::forward() const {
  btVector3 f = body_->getWorldTransform().getBasis() * btVector3(0, 0, 1);
  f.setY(0);
  return f.normalized();
}

btVector3 DroneBody::right() const { return forward().cross(btVector3(0, 1, 0)); }

float DroneBody::yaw() const {
  const btVector3 f = forward();
  return std::atan2(f.x(), f.z());
}

}  // namespace rlt::drone
