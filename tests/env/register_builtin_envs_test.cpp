// The built-in envs are registered once, under their own names.
#include "env/register_builtin_envs.h"

#include <gtest/gtest.h>

#include "rl/env_api/env_registry.h"

namespace rlt {
namespace {

TEST(RegisterBuiltinEnvsTest, RegistersEveryEnvOnceUnderItsSpecName) {
  register_builtin_envs();
  register_builtin_envs();  // idempotent
  auto& registry = EnvRegistry::instance();
  for (const char* name : {"CartPole", "Pendulum", "HybridReach", "MaskedChoice", "Escape",
                           "Pursuit", "Duel", "Hummingbird", "TargetDrone", "Eye"}) {
    ASSERT_TRUE(registry.contains(name)) << name;
    EXPECT_EQ(registry.make(name)->spec().name, name);
  }
}

}  // namespace
}  // namespace rlt
