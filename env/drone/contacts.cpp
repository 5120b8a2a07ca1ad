#include "env/drone/contacts.h"

#include <algorithm>
#include <functional>

namespace rlt::drone {
namespace {

bool contains(const std::vector<ContactPair>& pairs, const ContactPair& p) {
  return std::find(pairs.begin(), pairs.end(), p) != pairs.end();
}

}  // namespace

ContactPair make_contact_pair(const btCollisionObject* x, const btCollisionObject* y) {
  return std::less<const btCollisionObject*>()(x, y) ? ContactPair{x, y} : ContactPair{y, x};
}

std::vector<ContactPair> touching_pairs(BulletWorld& world, float epsilon) {
  std::vector<ContactPair> pairs;
  btDispatcher* dispatcher = world.world().getDispatcher();
  const int n = dispatcher->getNumManifolds();
  for (int i = 0; i < n; ++i) {
    const btPersistentManifold* m = dispatcher->getManifoldByIndexInternal(i);
    bool touch = false;
    for (int k = 0; k < m->getNumContacts() && !touch; ++k)
      touch = m->getContactPoint(k).getDistance() <= epsilon;
    if (!touch) continue;
    const ContactPair p = make_contact_pair(m->getBody0(), m->getBody1());
    if (!contains(pairs, p)) pairs.push_back(p);  // compound shapes may give several manifolds
  }
  return pairs;
}

const std::vector<ContactPair>& ContactTracker::update(BulletWorld& world) {
  std::vector<ContactPair> now = touching_pairs(world, epsilon_);
  started_.clear();
  for (const ContactPair& p : now)
    if (!contains(touching_, p)) started_.push_back(p);
  touching_ = std::move(now);
  return started_;
}

void ContactTracker::clear() {
  touching_.clear();
  started_.clear();
}

bool ContactTracker::touching(const btCollisionObject* x, const btCollisionObject* y) const {
  return contains(touching_, make_contact_pair(x, y));
}

bool ContactTracker::started(const btCollisionObject* x, const btCollisionObject* y) const {
  return contains(started_, make_contact_pair(x, y));
}

}  // namespace rlt::drone
