// The conformance suite passes every registered env and catches deliberately broken ones.
#include "rl/env_api/conformance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>

#include "env/register_builtin_envs.h"
#include "rl/env_api/env_registry.h"

namespace rlt {
namespace {

// What is wrong with a FlawedEnv.
enum class Flaw {
  kNone,              // a correct env: the positive control
  kNanObservation,    // step 2 observes NaN
  kOutOfBounds,       // step 2 observes 1.5 with declared high 1
  kInfiniteReward,    // step 2 rewards infinity
  kRevivesAgent,      // agent 0 acts again two steps after its kLast
  kKFirstMidEpisode,  // a new agent appears in an empty slot mid-episode
  kDuplicateIds,      // both agents have id 0
  kIgnoresSeed,       // seed() is a no-op
  kSharedRandom,      // draws from one engine shared by all instances
  kNeverEnds,         // agent 1 acts past max_episode_steps
  kEmptyMask,         // the mask of step 2 allows nothing
  kRewardOnFirst,     // kFirst carries a reward
  kTerminatedOnMid,   // `terminated` set on a kMid step
  kThrows,            // step 3 throws
  kBadSpec,           // an observation of size 0
  kMetricNamesVary,   // an episode metric that only ended episodes report
};

// Two agents: agent 0 leaves (terminated) after 3 steps, agent 1 is truncated after 6.
class FlawedEnv : public Env {
 public:
  static constexpr int kMaxSteps = 6;

  explicit FlawedEnv(Flaw flaw) : flaw_(flaw) {
    BehaviorSpec b;
    b.name = "Flawed";
    b.observations.push_back(
        {"x", {flaw == Flaw::kBadSpec ? 0 : 2}, ObservationKind::kVector, -1.f, 1.f});
    b.action.discrete_branches = {3};
    b.agent_slots = 3;  // slot 2 stays empty
    spec_.name = "Flawed";
    spec_.behaviors.push_back(b);
    spec_.max_episode_steps = kMaxSteps;
  }

  const EnvSpec& spec() const override { return spec_; }
  EpisodeMetrics episode_metrics() const override {
    EpisodeMetrics metrics = {{"steps", static_cast<float>(t_)}};
    if (flaw_ == Flaw::kMetricNamesVary && t_ > 0) metrics.emplace("ended", 1.f);
    return metrics;
  }
  void seed(uint64_t seed) override {
    if (flaw_ != Flaw::kIgnoresSeed) engine_.seed(seed);
  }

  void reset(StepView& out) override {
    if (flaw_ == Flaw::kIgnoresSeed) engine_.seed(42);
    t_ = 0;
    BehaviorView& v = out[0];
    for (int s = 0; s < 2; ++s) {
      v.step_type(s) = StepType::kFirst;
      v.agent_id(s) = flaw_ == Flaw::kDuplicateIds ? 0 : s;
      v.reward(s) = flaw_ == Flaw::kRewardOnFirst ? 1.f : 0.f;
      write(v, s);
    }
  }

  void step(StepView& io) override {
    BehaviorView& v = io[0];
    ++t_;
    if (flaw_ == Flaw::kThrows && t_ == 3) throw std::runtime_error("flawed env failed");
    for (int s = 0; s < v.slots(); ++s) {
      const bool alive = needs_action(v.step_type(s));
      const bool revive = flaw_ == Flaw::kRevivesAgent && s == 0 && t_ == 5;
      const bool spawn = flaw_ == Flaw::kKFirstMidEpisode && s == 2 && t_ == 2;
      if (spawn) {
        v.step_type(s) = StepType::kFirst;
        v.agent_id(s) = 7;
        write(v, s);
        continue;
      }
      if (!alive && !revive) {
        v.step_type(s) = StepType::kAbsent;
        continue;
      }
      if (revive) v.agent_id(s) = 0;
      const int end = s == 0 ? 3 : (flaw_ == Flaw::kNeverEnds ? kMaxSteps + 3 : kMaxSteps);
      v.reward(s) = v.discrete_action(s)[0] == 1 ? 1.f : 0.f;
      if (t_ >= end && !revive) {
        v.step_type(s) = StepType::kLast;
        v.terminated(s) = s == 0 ? 1 : 0;
      } else {
        v.step_type(s) = StepType::kMid;
        if (flaw_ == Flaw::kTerminatedOnMid && t_ == 1) v.terminated(s) = 1;
      }
      write(v, s);
      if (t_ == 2 && s == 1) {
        if (flaw_ == Flaw::kNanObservation) v.observation(s)[1] = std::nanf("");
        if (flaw_ == Flaw::kOutOfBounds) v.observation(s)[0] = 1.5f;
        if (flaw_ == Flaw::kInfiniteReward) v.reward(s) = INFINITY;
        if (flaw_ == Flaw::kEmptyMask) std::fill(v.action_mask(s), v.action_mask(s) + 3, 0);
      }
    }
  }

 private:
  // a random observation in [-1, 1] and a mask that forbids one random option
  void write(BehaviorView& v, int s) {
    if (spec_.behaviors[0].observations[0].size() == 0) return;
    uint64_t draws[2];
    if (flaw_ == Flaw::kSharedRandom) {
      static std::mutex mutex;  // no data race, only an order that depends on the threads
      static std::mt19937_64 shared(1);
      std::lock_guard<std::mutex> lock(mutex);
      draws[0] = shared();
      draws[1] = shared();
    } else {
      draws[0] = engine_();
      draws[1] = engine_();
    }
    v.observation(s)[0] = static_cast<float>(double(draws[0] >> 11) * 0x1.0p-52 - 1.0);
    v.observation(s)[1] = static_cast<float>(t_) / kMaxSteps;
    const int forbidden = static_cast<int>(draws[1] % 3);
    for (int k = 0; k < 3; ++k) v.action_mask(s)[k] = k != forbidden;
  }
  Flaw flaw_;
  EnvSpec spec_;
  std::mt19937_64 engine_;
  int t_ = 0;
};

std::string flawed_name(Flaw flaw) { return "Flawed" + std::to_string(static_cast<int>(flaw)); }

void register_flawed_envs() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int f = 0; f <= static_cast<int>(Flaw::kMetricNamesVary); ++f) {
      const Flaw flaw = static_cast<Flaw>(f);
      EnvRegistry::instance().add(flawed_name(flaw), [flaw](const Parameters&) {
        return std::unique_ptr<Env>(new FlawedEnv(flaw));
      });
    }
  });
}

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += s + "\n";
  return out;
}

TEST(ConformanceTest, EveryRegisteredBuiltinEnvConforms) {
  register_builtin_envs();
  for (const auto& name : EnvRegistry::instance().names()) {
    if (name.rfind("Flawed", 0) == 0) continue;
    SCOPED_TRACE(name);
    // two whole episodes, but at most 1200 steps: the drone envs (episodes of up to thousands of
    // decisions) run whole short episodes in their own tests
    ConformanceOptions opts;
    const int max_steps = EnvRegistry::instance().make(name)->spec().max_episode_steps;
    opts.steps = std::min(2 * (max_steps + 1), 1200);
    const auto violations = check_env_conformance(name, {}, opts);
    EXPECT_TRUE(violations.empty()) << joined(violations);
  }
}

TEST(ConformanceTest, ParametersAreChecked) {
  register_builtin_envs();
  EXPECT_TRUE(check_env_conformance("Pendulum", {{"g", 3.f}}).empty());
  const auto violations = check_env_conformance("Pendulum", {{"gravity", 3.f}});
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_NE(violations[0].find("gravity"), std::string::npos) << violations[0];
}

TEST(ConformanceTest, UnknownEnvIsAViolation) {
  const auto violations = check_env_conformance("NoSuchEnv");
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_NE(violations[0].find("unknown environment"), std::string::npos) << violations[0];
}

TEST(ConformanceTest, CorrectMultiAgentEnvConforms) {
  register_flawed_envs();
  const auto violations = check_env_conformance(flawed_name(Flaw::kNone));
  EXPECT_TRUE(violations.empty()) << joined(violations);
}

struct FlawCase {
  Flaw flaw;
  const char* expected;  // a phrase of the violation that must be reported
};

class ConformanceFlawTest : public ::testing::TestWithParam<FlawCase> {};

TEST_P(ConformanceFlawTest, CatchesTheFlaw) {
  register_flawed_envs();
  const auto violations = check_env_conformance(flawed_name(GetParam().flaw));
  ASSERT_FALSE(violations.empty());
  const std::string all = joined(violations);
  EXPECT_NE(all.find(GetParam().expected), std::string::npos) << all;
}

INSTANTIATE_TEST_SUITE_P(
    Flaws, ConformanceFlawTest,
    ::testing::Values(FlawCase{Flaw::kNanObservation, "is not finite"},
                      FlawCase{Flaw::kOutOfBounds, "'x'[0] = 1.5 is outside [-1, 1]"},
                      FlawCase{Flaw::kInfiniteReward, "reward inf"},
                      FlawCase{Flaw::kRevivesAgent, "came back (kMid) after its kLast"},
                      FlawCase{Flaw::kKFirstMidEpisode, "kAbsent followed by kFirst"},
                      FlawCase{Flaw::kDuplicateIds, "used by two present agents"},
                      FlawCase{Flaw::kIgnoresSeed, "the env ignores its seed"},
                      FlawCase{Flaw::kSharedRandom, "trajectories differ"},
                      FlawCase{Flaw::kNeverEnds, "more than max_episode_steps"},
                      FlawCase{Flaw::kEmptyMask, "allows no option of branch 0"},
                      FlawCase{Flaw::kRewardOnFirst, "kFirst carries a nonzero reward"},
                      FlawCase{Flaw::kTerminatedOnMid, "terminated is set on a kMid step"},
                      FlawCase{Flaw::kThrows, "flawed env failed"},
                      FlawCase{Flaw::kBadSpec, "shape dimension 0 is not positive"},
                      FlawCase{Flaw::kMetricNamesVary,
                               "episode metrics [ended, steps] differ from the names "
                               "episode_metrics() gave after reset: [steps]"}));

TEST(ConformanceSpecTest, FindsBrokenSpecs) {
  EnvSpec spec;
  spec.name = "Bad";
  spec.max_episode_steps = 0;
  BehaviorSpec b;
  b.name = "A";
  b.agent_slots = 0;
  b.observations.push_back({"grid", {4, 4}, ObservationKind::kGrid, 1.f, 0.f});
  b.action.discrete_branches = {2, 0};
  spec.behaviors = {b, b};
  const std::string all = joined(check_env_spec(spec));
  for (const char* phrase : {"max_episode_steps = 0", "name used twice", "agent_slots = 0",
                             "expected 3 (height, width, channels)", "are not an interval",
                             "a discrete branch has 0 options"})
    EXPECT_NE(all.find(phrase), std::string::npos) << phrase << "\n" << all;

  EnvSpec empty;
  EXPECT_NE(joined(check_env_spec(empty)).find("no behavior"), std::string::npos);
}

}  // namespace
}  // namespace rlt
