#include "env/drone/bullet_world.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <utility>

namespace rlt::drone {

BulletWorld::BulletWorld(const WorldParams& params) : params_(params) {
  if (!(params_.frame_rate > 0)) throw std::invalid_argument("BulletWorld: frame_rate must be > 0");
  create();
}

BulletWorld::~BulletWorld() { destroy(); }

void BulletWorld::create() {
  configuration_ = std::make_unique<btDefaultCollisionConfiguration>();
  dispatcher_ = std::make_unique<btCollisionDispatcher>(configuration_.get());
  broadphase_ = std::make_unique<btDbvtBroadphase>();
  solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
  world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(),
                                                     solver_.get(), configuration_.get());
  world_->setGravity(params_.gravity);
  frame_ = 0;
}

void BulletWorld::destroy() {
  // constraints go first: they reference the bodies
  for (auto it = constraints_.rbegin(); it != constraints_.rend(); ++it) {
    if (world_) world_->removeConstraint(it->get());
  }
  constraints_.clear();
  // bodies leave the world before anything they reference is freed, newest first
  for (auto it = bodies_.rbegin(); it != bodies_.rend(); ++it) {
    if (world_) world_->removeRigidBody((*it)->body.get());
  }
  bodies_.clear();
  world_.reset();
  solver_.reset();
  broadphase_.reset();
  dispatcher_.reset();
  configuration_.reset();
}

void BulletWorld::reset() {
  destroy();
  create();
  ++epoch_;
}

void BulletWorld::step_frame() {
  // maxSubSteps = 0: exactly one step of dt, motion states get the simulated pose
  world_->stepSimulation(dt(), 0);
  ++frame_;
}

btRigidBody* BulletWorld::add(std::unique_ptr<btCollisionShape> shape, const btTransform& pose,
                              float mass, Tag tag) {
  auto owned = std::make_unique<OwnedBody>();
  btVector3 inertia(0, 0, 0);
  if (mass > 0) shape->calculateLocalInertia(mass, inertia);
  owned->motion = std::make_unique<btDefaultMotionState>(pose);
  btRigidBody::btRigidBodyConstructionInfo info(mass, owned->motion.get(), shape.get(), inertia);
  owned->shape = std::move(shape);
  owned->body = std::make_unique<btRigidBody>(info);
  owned->body->setUserIndex(tag);
  btRigidBody* body = owned->body.get();
  world_->addRigidBody(body);
  bodies_.push_back(std::move(owned));
  return body;
}

btRigidBody* BulletWorld::add_static_box(const btVector3& centre, const btVector3& half, Tag tag) {
  btTransform pose;
  pose.setIdentity();
  pose.setOrigin(centre);
  return add(std::make_unique<btBoxShape>(half), pose, 0.0f, tag);
}

btRigidBody* BulletWorld::add_dynamic_body(std::unique_ptr<btCollisionShape> shape,
                                           const DynamicBodyDesc& desc) {
  if (!(desc.mass > 0)) throw std::invalid_argument("BulletWorld: a dynamic body needs mass > 0");
  return add(std::move(shape), btTransform(desc.rotation, desc.position), desc.mass, desc.tag);
}

void BulletWorld::remove_body(btRigidBody* body) {
  auto it = std::find_if(bodies_.begin(), bodies_.end(),
                         [body](const auto& owned) { return owned->body.get() == body; });
  if (it == bodies_.end()) throw std::invalid_argument("BulletWorld: body not in this world");
  for (std::size_t i = constraints_.size(); i-- > 0;) {
    btTypedConstraint* c = constraints_[i].get();
    if (&c->getRigidBodyA() == body || &c->getRigidBodyB() == body) remove_constraint(c);
  }
  world_->removeRigidBody(body);
  bodies_.erase(it);
}

btTypedConstraint* BulletWorld::add_constraint(std::unique_ptr<btTypedConstraint> constraint,
                                               bool disable_collisions_between_bodies) {
  btTypedConstraint* c = constraint.get();
  world_->addConstraint(c, disable_collisions_between_bodies);
  constraints_.push_back(std::move(constraint));
  return c;
}

void BulletWorld::remove_constraint(btTypedConstraint* constraint) {
  auto it = std::find_if(constraints_.begin(), constraints_.end(),
                         [constraint](const auto& owned) { return owned.get() == constraint; });
  if (it == constraints_.end()) {
    throw std::invalid_argument("BulletWorld: constraint not in this world");
  }
  world_->removeConstraint(constraint);
  constraints_.erase(it);
}

bool BulletWorld::has_constraint(const btTypedConstraint* constraint) const {
  return std::any_of(constraints_.begin(), constraints_.end(),
                     [constraint](const auto& owned) { return owned.get() == constraint; });
}

}  // namespace rlt::drone
