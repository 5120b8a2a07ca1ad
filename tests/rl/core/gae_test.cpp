// Equivalence of compute_gae with a naive reference: the explicit sum
// A_t = sum_k (gamma lambda)^k delta_{t+k}, computed in double, on random trajectories; and the
// two limits lambda = 1 (discounted return minus value) and lambda = 0 (one-step TD error).
#include "rl/core/gae.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace rlt {
namespace {

struct Trajectory {
  std::vector<float> rewards;  // [T]
  std::vector<float> values;   // [T]
};

Trajectory random_trajectory(int length, std::mt19937_64& rng) {
  std::normal_distribution<float> reward(0.f, 1.f), value(0.5f, 2.f);
  Trajectory tr;
  for (int t = 0; t < length; ++t) {
    tr.rewards.push_back(reward(rng));
    tr.values.push_back(value(rng));
  }
  return tr;
}

// naive: delta_t for every t, then the explicit discounted sum for every t
std::vector<double> naive_advantages(const Trajectory& tr, double bootstrap, double gamma,
                                     double lambda) {
  const int n = static_cast<int>(tr.rewards.size());
  std::vector<double> delta(n);
  for (int t = 0; t < n; ++t) {
    const double next_value = t + 1 < n ? double(tr.values[t + 1]) : bootstrap;
    delta[t] = double(tr.rewards[t]) + gamma * next_value - double(tr.values[t]);
  }
  std::vector<double> adv(n, 0.0);
  for (int t = 0; t < n; ++t)
    for (int k = 0; t + k < n; ++k) adv[t] += std::pow(gamma * lambda, k) * delta[t + k];
  return adv;
}

struct GaeOut {
  std::vector<float> advantages, returns;  // [T]
};

GaeOut run_gae(const Trajectory& tr, float bootstrap, float gamma, float lambda) {
  const int64_t n = static_cast<int64_t>(tr.rewards.size());
  GaeOut out{std::vector<float>(n, NAN), std::vector<float>(n, NAN)};
  compute_gae(tr.rewards.data(), tr.values.data(), n, bootstrap, gamma, lambda,
              out.advantages.data(), out.returns.data());
  return out;
}

TEST(GaeTest, MatchesExplicitSumOnRandomTrajectories) {
  std::mt19937_64 rng(12345);
  const float gamma = 0.99f, lambda = 0.95f;
  for (int length : {1, 2, 3, 7, 64, 257}) {
    for (bool terminated : {false, true}) {
      SCOPED_TRACE(testing::Message() << "length " << length << " terminated " << terminated);
      Trajectory tr = random_trajectory(length, rng);
      // a terminated episode bootstraps with 0, a truncated one with V(s_T)
      const float bootstrap = terminated ? 0.f : 1.7f;
      GaeOut out = run_gae(tr, bootstrap, gamma, lambda);
      auto ref = naive_advantages(tr, bootstrap, gamma, lambda);
      for (int t = 0; t < length; ++t) {
        const double tol = 1e-5 * (1.0 + std::abs(ref[t]));
        EXPECT_NEAR(out.advantages[t], ref[t], tol) << "t " << t;
        EXPECT_NEAR(out.returns[t], ref[t] + tr.values[t], tol) << "t " << t;
      }
    }
  }
}

TEST(GaeTest, BootstrapValueOnlyEntersThroughTheLastStep) {
  std::mt19937_64 rng(7);
  const float gamma = 0.9f, lambda = 0.8f;
  Trajectory tr = random_trajectory(10, rng);
  GaeOut terminated = run_gae(tr, 0.f, gamma, lambda);
  GaeOut truncated = run_gae(tr, 3.f, gamma, lambda);
  // A_t grows by (gamma lambda)^(T-1-t) gamma * bootstrap
  for (int t = 0; t < 10; ++t) {
    const double expected = std::pow(double(gamma) * lambda, 9 - t) * gamma * 3.0;
    EXPECT_NEAR(truncated.advantages[t] - terminated.advantages[t], expected, 1e-5) << "t " << t;
  }
}

TEST(GaeTest, LambdaOneIsDiscountedReturnMinusValue) {
  std::mt19937_64 rng(99);
  const double gamma = 0.97;
  for (float bootstrap : {0.f, -2.5f}) {
    Trajectory tr = random_trajectory(50, rng);
    GaeOut out = run_gae(tr, bootstrap, float(gamma), 1.f);
    for (int t = 0; t < 50; ++t) {
      // Monte-Carlo return: sum_k gamma^k r_{t+k} + gamma^(T-t) bootstrap
      double ret = 0;
      for (int k = 0; t + k < 50; ++k) ret += std::pow(gamma, k) * tr.rewards[t + k];
      ret += std::pow(gamma, 50 - t) * bootstrap;
      EXPECT_NEAR(out.advantages[t], ret - tr.values[t], 1e-4) << "t " << t;
      EXPECT_NEAR(out.returns[t], ret, 1e-4) << "t " << t;
    }
  }
}

TEST(GaeTest, LambdaZeroIsOneStepTdError) {
  std::mt19937_64 rng(5);
  const float gamma = 0.95f, bootstrap = 0.75f;
  Trajectory tr = random_trajectory(20, rng);
  GaeOut out = run_gae(tr, bootstrap, gamma, 0.f);
  for (int t = 0; t < 20; ++t) {
    const double next_value = t + 1 < 20 ? tr.values[t + 1] : bootstrap;
    const double td = tr.rewards[t] + double(gamma) * next_value - tr.values[t];
    EXPECT_NEAR(out.advantages[t], td, 1e-5) << "t " << t;
    EXPECT_NEAR(out.returns[t], tr.rewards[t] + double(gamma) * next_value, 1e-5) << "t " << t;
  }
}

TEST(GaeTest, ZeroLengthWritesNothing) {
  float r = 1.f, v = 2.f, adv = 42.f, ret = 43.f;
  compute_gae(&r, &v, 0, 5.f, 0.99f, 0.95f, &adv, &ret);
  EXPECT_EQ(adv, 42.f);
  EXPECT_EQ(ret, 43.f);
}

}  // namespace
}  // namespace rlt
