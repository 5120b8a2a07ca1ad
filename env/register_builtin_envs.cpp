#include "env/register_builtin_envs.h"

#include <memory>
#include <mutex>

#include "env/classic/cartpole.h"
#include "env/classic/pendulum.h"
#include "env/drone/hide_and_seek.h"
#include "env/drone/eye.h"
#include "env/drone/hummingbird.h"
#include "env/drone/target_drone.h"
#include "env/toy/duel.h"
#include "env/toy/escape.h"
#include "env/toy/hybrid_reach.h"
#include "env/toy/masked_choice.h"
#include "env/toy/pursuit.h"
#include "rl/env_api/env_registry.h"

namespace rlt {

namespace {
template <typename E>
void add_env(const char* name) {
  auto& registry = EnvRegistry::instance();
  if (registry.contains(name)) return;
  registry.add(name,
               [](const Parameters&) -> std::unique_ptr<Env> { return std::make_unique<E>(); });
}
}  // namespace

void register_builtin_envs() {
  static std::once_flag once;
  std::call_once(once, [] {
    // classic control
    add_env<CartPole>("CartPole");
    add_env<Pendulum>("Pendulum");
    // toy envs for tests
    add_env<HybridReach>("HybridReach");
    add_env<MaskedChoice>("MaskedChoice");
    // toy multi-agent envs: group credit, hide-and-seek in 2D, symmetric self-play
    add_env<Escape>("Escape");
    add_env<Pursuit>("Pursuit");
    add_env<Duel>("Duel");
    // the Bullet drone world
    add_env<HideAndSeek>("HideAndSeek");
    // drone tasks (SPEC section 7): the paper's pre-experiments on the Bullet drone world
    add_env<Hummingbird>("Hummingbird");
    add_env<TargetDrone>("TargetDrone");
    add_env<Eye>("Eye");
  });
}

}  // namespace rlt
