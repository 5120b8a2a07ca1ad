// Contacts between the bodies of a BulletWorld, frame by frame, for "per collision" rewards.
//
// touching_pairs(): every pair of collision objects whose persistent manifold (from the world's
// dispatcher, as left by the last step_frame()) holds at least one contact point at distance
// <= epsilon (m; negative distances are penetrations). Bullet keeps manifold points up to its
// contact breaking threshold (about 0.02 m) apart, so epsilon decides what "touching" means.
// Each pair is stored with its two objects in a canonical order (a < b by address), once.
// ContactTracker: call update() once after every physics frame. A pair *starts* touching in a frame
// when it touches now and did not in the previous frame: one collision is counted at contact
// start, and a drone pressed against a wall for many frames collides once. Contact is not
// remembered across BulletWorld::reset(): clear() the tracker when the world is rebuilt.
#ifndef RLT_ENV_DRONE_CONTACTS_H_
#define RLT_ENV_DRONE_CONTACTS_H_

#include <btBulletDynamicsCommon.h>

#include <vector>

#include "env/drone/bullet_world.h"

namespace rlt::drone {

inline constexpr float kDefaultContactEpsilon = 0.01f;  // m

// two objects in contact, a < b by address
struct ContactPair {
  const btCollisionObject* a;
  const btCollisionObject* b;
  bool involves(const btCollisionObject* o) const { return a == o || b == o; }
  // the other object of the pair, or nullptr when `o` is not in it
  const btCollisionObject* other(const btCollisionObject* o) const {
    return a == o ? b : b == o ? a : nullptr;
  }
  bool operator==(const ContactPair& p) const { return a == p.a && b == p.b; }
};

// the pair {x, y} in canonical order
ContactPair make_contact_pair(const btCollisionObject* x, const btCollisionObject* y);

// pairs touching after the last frame, in the dispatcher's manifold order
std::vector<ContactPair> touching_pairs(BulletWorld& world, float epsilon = kDefaultContactEpsilon);

class ContactTracker {
 public:
  explicit ContactTracker(float epsilon = kDefaultContactEpsilon) : epsilon_(epsilon) {}

  // reads the world's contacts after a frame; returns the pairs that started touching in it
  const std::vector<ContactPair>& update(BulletWorld& world);
  // forgets every contact (after a world reset)
  void clear();

  const std::vector<ContactPair>& touching() const { return touching_; }  // now
  const std::vector<ContactPair>& started() const { return started_; }    // since last frame
  bool touching(const btCollisionObject* x, const btCollisionObject* y) const;
  bool started(const btCollisionObject* x, const btCollisionObject* y) const;

 private:
  float epsilon_;
  std::vector<ContactPair> touching_;
  std::vector<ContactPair> started_;
};

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_CONTACTS_H_
