// BulletWorld: an RAII owner of one Bullet discrete dynamics world for the drone envs (SPEC.md
// section 6): the collision configuration, dispatcher, broadphase, solver and world, and every body
// added to it. Units are metres and seconds, y is up.
//
// Time: a fixed 50 Hz step; step_frame() advances exactly one 1/50 s substep with no interpolation
// of motion states. Gravity is per world (default 0); a body may opt out of it (drones do).
// Bodies: static boxes (walls, floor, ceiling) and dynamic rigid bodies, each tagged with a Tag
// stored in the collision object's user index (tag_of). The world owns the bodies; the pointers it
// hands out stay valid until reset() or destruction.
// Constraints (e.g. a grab) are owned by the world too and are removed before the bodies they join,
// both in remove_body() and in reset().
// reset() destroys everything and recreates an empty world with the same parameters, so that the
// same bodies added in the same order with the same actions give bit-identical trajectories (no
// solver seed, broadphase pair cache or contact manifold survives a reset).
#ifndef RLT_ENV_DRONE_BULLET_WORLD_H_
#define RLT_ENV_DRONE_BULLET_WORLD_H_

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <vector>

namespace rlt::drone {

// what a body is, as sensors see it (also the one-hot order of the ray sensor)
enum Tag : int { kWall = 0, kProp = 1, kObstacle = 2, kHider = 3, kSeeker = 4 };
inline constexpr int kNumTags = 5;

// the tag of a collision object created by a BulletWorld
inline Tag tag_of(const btCollisionObject& object) {
  return static_cast<Tag>(object.getUserIndex());
}

struct WorldParams {
  float frame_rate = 50.0f;                // physics frames per second (Hz)
  btVector3 gravity = btVector3(0, 0, 0);  // world gravity (m/s^2), bodies may opt out
};

// a dynamic rigid body and what it needs to live: its shape and motion state
struct DynamicBodyDesc {
  btVector3 position = btVector3(0, 0, 0);  // centre of mass (m)
  btQuaternion rotation = btQuaternion::getIdentity();
  float mass = 1.0f;  // kg, > 0
  Tag tag = kObstacle;
};

class BulletWorld {
 public:
  explicit BulletWorld(const WorldParams& params = {});
  ~BulletWorld();
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  // one fixed physics frame of 1 / frame_rate seconds
  void step_frame();
  // destroy every body and recreate an empty world with the same parameters
  void reset();

  // a static axis-aligned box of half extents `half` centred at `centre`
  btRigidBody* add_static_box(const btVector3& centre, const btVector3& half, Tag tag = kWall);
  // a dynamic body of the given shape (the world takes ownership of the shape)
  btRigidBody* add_dynamic_body(std::unique_ptr<btCollisionShape> shape,
                                const DynamicBodyDesc& desc);
  // removes and destroys one body added to this world (and any constraint joining it)
  void remove_body(btRigidBody* body);
  // adds a constraint between bodies of this world and takes ownership of it
  btTypedConstraint* add_constraint(std::unique_ptr<btTypedConstraint> constraint,
                                    bool disable_collisions_between_bodies = true);
  // removes and destroys one constraint added to this world
  void remove_constraint(btTypedConstraint* constraint);
  bool has_constraint(const btTypedConstraint* constraint) const;

  btDiscreteDynamicsWorld& world() { return *world_; }
  const btDiscreteDynamicsWorld& world() const { return *world_; }
  float dt() const { return 1.0f / params_.frame_rate; }
  long frame() const { return frame_; }  // frames since the last reset
  long epoch() const { return epoch_; }  // number of resets: pointers from an older epoch dangle
  int num_constraints() const { return static_cast<int>(constraints_.size()); }
  int num_bodies() const { return static_cast<int>(bodies_.size()); }

 private:
  // one body with its shape and motion state; destroyed after removal from the world
  struct OwnedBody {
    std::unique_ptr<btCollisionShape> shape;
    std::unique_ptr<btDefaultMotionState> motion;
    std::unique_ptr<btRigidBody> body;
  };

  void create();
  void destroy();
  btRigidBody* add(std::unique_ptr<btCollisionShape> shape, const btTransform& pose, float mass,
                   Tag tag);

  WorldParams params_;
  long frame_ = 0;
  long epoch_ = 0;
  // declaration order is construction order; destroy() tears down in reverse
  std::unique_ptr<btDefaultCollisionConfiguration> configuration_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<std::unique_ptr<OwnedBody>> bodies_;               // in insertion order
  std::vector<std::unique_ptr<btTypedConstraint>> constraints_;  // in insertion order
};

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_BULLET_WORLD_H_
