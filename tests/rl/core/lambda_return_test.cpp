// compute_lambda_returns against the lambda-return written as a weighted sum of n-step returns.
#include "rl/core/lambda_return.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace rlt {
namespace {

// G^lambda_t = (1 - l) sum_{n=1}^{T-t-1} l^(n-1) G^(n)_t + l^(T-t-1) G^(T-t)_t, where the n-step
// return G^(n)_t = sum_{k<n} g^k r_{t+k} + g^n V_{t+n} and V_T is the bootstrap value
std::vector<double> naive(const std::vector<float>& r, const std::vector<float>& v, float boot,
                          double g, double l) {
  const int T = int(r.size());
  auto value_at = [&](int i) { return i == T ? double(boot) : double(v[i]); };
  auto n_step = [&](int t, int n) {
    double sum = 0;
    for (int k = 0; k < n; ++k) sum += std::pow(g, k) * r[t + k];
    return sum + std::pow(g, n) * value_at(t + n);
  };
  std::vector<double> out(T);
  for (int t = 0; t < T; ++t) {
    double sum = 0;
    for (int n = 1; n < T - t; ++n) sum += (1 - l) * std::pow(l, n - 1) * n_step(t, n);
    out[t] = sum + std::pow(l, T - t - 1) * n_step(t, T - t);
  }
  return out;
}

TEST(LambdaReturn, EqualsWeightedSumOfNStepReturns) {
  std::mt19937 rng(3);
  std::normal_distribution<float> normal;
  for (int T : {1, 2, 7, 40}) {
    for (float lambda : {0.f, 0.6f, 0.95f, 1.f}) {
      std::vector<float> r(T), v(T), out(T);
      for (int i = 0; i < T; ++i) {
        r[i] = normal(rng);
        v[i] = normal(rng);
      }
      const float boot = normal(rng);
      compute_lambda_returns(r.data(), v.data(), T, boot, 0.97f, lambda, out.data());
      auto expected = naive(r, v, boot, 0.97, lambda);
      for (int t = 0; t < T; ++t) EXPECT_NEAR(out[t], expected[t], 1e-4) << "T " << T << " lambda " << lambda << " t " << t;
    }
  }
}

TEST(LambdaReturn, LambdaZeroIsOneStepTargetAndOneIsMonteCarlo) {
  std::vector<float> r = {1, 2, 3}, v = {10, 20, 30}, out(3);
  compute_lambda_returns(r.data(), v.data(), 3, 5.f, 0.5f, 0.f, out.data());
  EXPECT_FLOAT_EQ(out[0], 1 + 0.5f * 20);
  EXPECT_FLOAT_EQ(out[1], 2 + 0.5f * 30);
  EXPECT_FLOAT_EQ(out[2], 3 + 0.5f * 5);
  compute_lambda_returns(r.data(), v.data(), 3, 5.f, 0.5f, 1.f, out.data());
  EXPECT_FLOAT_EQ(out[0], 1 + 0.5f * 2 + 0.25f * 3 + 0.125f * 5);
}

}  // namespace
}  // namespace rlt
