// Props and obstacles of the drone world (SPEC.md section 6, "Props", "Obstacles", "Drones").
//
// Props are box panels (tag kProp, half extents 0.75 x 1.0 x 0.1 m, 2 kg by default) owned by the
// BulletWorld, with continuous collision detection, linear and angular damping and no gravity by
// default (a prop stays where it is left; PropParams::gravity turns it on).
// A PropSet keeps the props of one world and who holds or locked them. Rules, for one drone:
//   reach:  the gap between the drone's sphere and the prop's box (surface to surface) is at most
//           reach (1.5 m);
//   front:  the direction from the drone's centre to the closest point of the box is within
//           cone_degrees (60) of the drone's forward (a box the drone touches counts as in front);
//   grab:   attaches the nearest prop in reach and in front that is neither locked nor held by
//           another drone, with a btFixedConstraint that keeps the prop's pose in the drone's
//           frame (collisions between the two are off): it is dragged at a fixed distance and
//           turns with the drone, so a drone can carry a panel square to an opening; a drone
//           already holding a prop keeps it. With square_hold the held pose is turned about the
//           panel's centre to the nearer of the two face-on poses (its broad side across the
//           drone's forward) and kept clear of the drone, so the constraint swings the panel
//           square within a few frames: facing an opening then holds the panel parallel to it.
//           Fails (-1) when no prop qualifies: a locked prop is never grabbed and a failed grab
//           releases nothing;
//   release: removes the drone's constraint; the prop keeps its velocity and is then damped;
//   lock:   freezes the nearest unlocked prop in reach and in front: any grab on it is released,
//           its velocities are zeroed and it gets zero inverse mass and zero linear and angular
//           factors, so nothing can move it; it remembers the locking team;
//   unlock: the nearest locked prop in reach and in front is unfrozen (mass, inertia and factors
//           restored) only when `team` is the team that locked it; otherwise it fails (-1).
// Each rule also takes the props the drone may act on (`allowed`, bit i for prop i; all by
// default, kAllProps, which alone also lets through props from the 33rd on): the others are
// passed over as if they were out of reach.
// Obstacles (add_obstacle) are light boxes (tag kObstacle, 0.5 kg) with weak per-body gravity
// (0.981 m/s^2 down, 1/10 g, set on the body since the world gravity is 0), low friction (0.05)
// and little damping (0.1), so that they glide and drift once pushed and settle slowly.
// Lifetime: the props and constraints belong to the world; a PropSet is valid for one world epoch
// (until BulletWorld::reset()); after a reset build a new one. Its destructor releases its grabs
// only when the world was not reset in between. A drone or prop removed with
// BulletWorld::remove_body() takes its grab constraint with it; release() the drone afterwards to
// clear the set's record.
#ifndef RLT_ENV_DRONE_PROP_H_
#define RLT_ENV_DRONE_PROP_H_

#include <btBulletDynamicsCommon.h>

#include <vector>

#include "env/drone/bullet_world.h"
#include "env/drone/drone_body.h"

namespace rlt::drone {

struct PropParams {
  btVector3 half = btVector3(0.75f, 1.0f, 0.1f);  // half extents of a panel (m)
  float mass = 2.0f;                              // kg
  float friction = 0.5f;
  float linear_damping = 0.5f;  // Bullet damping (fraction of velocity lost per second)
  float angular_damping = 0.9f;
  btVector3 gravity = btVector3(0, 0, 0);  // per-body gravity (m/s^2)
  float reach = 1.5f;                      // largest surface-to-surface gap for grab and lock (m)
  float cone_degrees = 60.0f;              // half angle of the front cone
  bool ccd = true;  // continuous collision detection (off only to show it matters)
  bool square_hold = false;  // grab swings the panel face-on to the drone (see grab above)
};

struct ObstacleParams {
  btVector3 half = btVector3(0.4f, 0.4f, 0.4f);  // half extents (m)
  float mass = 0.5f;                             // kg
  float friction = 0.05f;
  float linear_damping = 0.1f;
  float angular_damping = 0.5f;
  btVector3 gravity = btVector3(0, -0.981f, 0);  // weak gravity, 1/10 g
};

inline constexpr int kNoTeam = -1;
// PropSet's `allowed` masks: bit i lets a drone act on prop i
inline constexpr unsigned kAllProps = ~0u;

// one prop: its body (owned by the world) and its state
struct Prop {
  btRigidBody* body = nullptr;
  btVector3 half;
  int locked_by = kNoTeam;               // team id while locked
  const btRigidBody* held_by = nullptr;  // the holding drone's body
  btTypedConstraint* grab = nullptr;     // owned by the world
  bool locked() const { return locked_by != kNoTeam; }
  btVector3 position() const { return body->getWorldTransform().getOrigin(); }
  // the panel's face normal (its local z) in the world
  btVector3 normal() const { return body->getWorldTransform().getBasis().getColumn(2); }
};

class PropSet {
 public:
  explicit PropSet(BulletWorld& world, const PropParams& params = {});
  ~PropSet();
  PropSet(const PropSet&) = delete;
  PropSet& operator=(const PropSet&) = delete;

  // adds a panel centred at `centre` turned by `yaw` about +y; returns its index
  int add(const btVector3& centre, float yaw = 0.0f);
  int add(const btVector3& centre, float yaw, const btVector3& half);

  // the rules in the header comment; each returns the prop's index or -1 on failure
  int grab(const DroneBody& drone, unsigned allowed = kAllProps);
  int release(const DroneBody& drone);
  int lock(const DroneBody& drone, int team, unsigned allowed = kAllProps);
  int unlock(const DroneBody& drone, int team, unsigned allowed = kAllProps);

  int held_by(const DroneBody& drone) const;  // index of the prop the drone holds or -1
  // what grab, lock and unlock would act on now, without acting: the prop's index or -1
  int grabbable(const DroneBody& drone, unsigned allowed = kAllProps) const;
  int lockable(const DroneBody& drone, unsigned allowed = kAllProps) const;
  int unlockable(const DroneBody& drone, int team, unsigned allowed = kAllProps) const;
  // surface gap between the drone and prop i, and whether prop i is in the drone's front cone
  float gap(const DroneBody& drone, int i) const;
  bool in_front(const DroneBody& drone, int i) const;

  int size() const { return static_cast<int>(props_.size()); }
  const Prop& operator[](int i) const { return props_[i]; }
  const PropParams& params() const { return params_; }

 private:
  btVector3 closest_point(const DroneBody& drone, int i) const;
  // nearest allowed prop in reach and in front that passes `ok`, or -1
  template <typename Ok>
  int nearest(const DroneBody& drone, unsigned allowed, Ok ok) const;
  void drop(Prop& prop);  // removes the prop's grab constraint if any

  BulletWorld& world_;
  PropParams params_;
  long epoch_;
  std::vector<Prop> props_;
};

// adds a gliding obstacle box centred at `centre` turned by `yaw` about +y
btRigidBody* add_obstacle(BulletWorld& world, const btVector3& centre, float yaw = 0.0f,
                          const ObstacleParams& params = {});

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_PROP_H_
