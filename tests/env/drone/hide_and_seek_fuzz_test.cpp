// HideAndSeek fuzz: over 1M physics frames of random actions (masks obeyed, and on purpose also
// forbidden options and out-of-range thrust) at all four levels with random team sizes, every
// observation stays finite and inside its declared bounds, every reward is finite, and every body
// stays inside the arena (issue 4).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "env/drone/hide_and_seek.h"
#include "tests/env/single_env_harness.h"

namespace rlt {
namespace {

TEST(HideAndSeekFuzzTest, MillionRandomFramesStayFiniteInRangeAndInside) {
  constexpr long kFrames = 1000000;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<float> thrust(-1.5f, 1.5f);  // beyond [-1, 1]: the env clips
  long frames = 0, episodes = 0, checked_bodies = 0;
  int failures = 0;
  while (frames < kFrames && failures < 10) {
    HideAndSeek env;
    const int level = 1 + int(episodes % 4);
    env.set_parameters({{"level", float(level)},
                        {"num_hiders", float(1 + rng() % 2)},
                        {"num_seekers", float(1 + rng() % 4)},
                        {"episode_frames", float(600 + rng() % 1200)},
                        {"end_on_tag", float(rng() % 2)},
                        {"reward_preset", float(rng() % 2)}});
    env.seed(rng());
    SingleEnvHarness h(env);
    h.reset();
    const long start = env.physics_frames();
    for (bool done = false; !done;) {
      done = true;
      for (int b = 0; b < 2; ++b) {
        BehaviorBuffers& buf = h.buffers(b);
        const auto& spec = buf.spec;
        for (int r = 0; r < buf.rows; ++r) {
          if (buf.step_type[r] == StepType::kAbsent) continue;
          for (size_t k = 0; k < spec.observations.size(); ++k) {
            const auto& o = spec.observations[k];
            const float* x = buf.observations[k].data() + size_t(r) * o.size();
            for (int i = 0; i < o.size(); ++i) {
              if (!(std::isfinite(x[i]) && x[i] >= o.low && x[i] <= o.high) && failures++ < 10)
                ADD_FAILURE() << spec.name << " slot " << r << " " << o.name << "[" << i
                              << "] = " << x[i] << " at level " << level << " frame "
                              << env.frame();
            }
          }
          if (!std::isfinite(buf.reward[r]) || !std::isfinite(buf.group_reward[r])) {
            if (failures++ < 10) ADD_FAILURE() << "reward not finite";
          }
          if (!needs_action(buf.step_type[r])) continue;
          done = false;
          for (int k = 0; k < 4; ++k) buf.continuous_actions[r * 4 + k] = thrust(rng);
          // random options, forbidden ones included one time in ten (the env must ignore them)
          const uint8_t* mask = buf.action_mask.data() + r * 5;
          for (int branch = 0, offset = 0; branch < 2; offset += spec.action.discrete_branches[branch++]) {
            const int n = spec.action.discrete_branches[branch];
            int pick = int(rng() % n);
            if (rng() % 10 != 0)
              while (!mask[offset + pick]) pick = int(rng() % n);
            buf.discrete_actions[r * 2 + branch] = pick;
          }
        }
      }
      if (done) break;
      h.step();
      const auto& objects = env.world().world().getCollisionObjectArray();
      for (int i = 0; i < objects.size(); ++i) {
        if (objects[i]->isStaticObject()) continue;
        const btVector3 p = objects[i]->getWorldTransform().getOrigin();
        ++checked_bodies;
        if (!env.arena().inside_arena(p) && failures++ < 10)
          ADD_FAILURE() << "a body of tag " << objects[i]->getUserIndex() << " left the arena at ("
                        << p.x() << ", " << p.y() << ", " << p.z() << "), level " << level;
      }
    }
    frames += long(env.physics_frames() - start);
    ++episodes;
  }
  EXPECT_GE(frames, kFrames);
  EXPECT_GT(checked_bodies, kFrames);  // bodies were checked after every step
  std::printf("%ld frames in %ld episodes, %ld body positions checked\n", frames, episodes,
              checked_bodies);
}

}  // namespace
}  // namespace rlt
