// Equivalence of ppo_loss with a naive scalar loop in double (both sides of the ratio clip,
// positive and negative advantages, value clipping, the approximate KL and the clip fraction),
// the discrete branches' own entropy bonus, and zero policy gradient in the clipped region.
#include "rl/ppo/ppo_loss.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace rlt {
namespace {

struct Minibatch {
  std::vector<float> log_prob, old_log_prob, advantages, values, old_values, returns, entropy;
  std::vector<float> discrete_entropy;  // the branches' part of entropy (empty: no branches)
};

torch::Tensor tensor(const std::vector<float>& v) { return torch::tensor(v); }

struct NaiveLoss {
  double policy = 0, value = 0, entropy = 0, total = 0, approx_kl = 0, clip_fraction = 0;
};

// discrete_beta weighs the branches' part of the entropy (beta when not given)
NaiveLoss naive_loss(const Minibatch& m, double eps, double beta,
                     std::optional<double> discrete_beta = std::nullopt) {
  double discrete_entropy = 0;
  for (float h : m.discrete_entropy) discrete_entropy += h;
  NaiveLoss out;
  const size_t n = m.log_prob.size();
  for (size_t i = 0; i < n; ++i) {
    const double r = std::exp(double(m.log_prob[i]) - double(m.old_log_prob[i]));
    const double a = m.advantages[i];
    const double clipped = std::min(std::max(r, 1 - eps), 1 + eps);
    out.policy -= std::min(r * a, clipped * a);
    const double v = m.values[i], v_old = m.old_values[i], ret = m.returns[i];
    const double v_clip = v_old + std::min(std::max(v - v_old, -eps), eps);
    out.value += std::max((ret - v) * (ret - v), (ret - v_clip) * (ret - v_clip));
    out.entropy += m.entropy[i];
    out.approx_kl += r - 1 - std::log(r);
    out.clip_fraction += std::abs(r - 1) > eps ? 1 : 0;
  }
  out.approx_kl /= n;
  out.clip_fraction /= n;
  out.policy /= n;
  out.value /= n;
  out.entropy /= n;
  discrete_entropy /= n;
  out.total = out.policy + 0.5 * out.value - beta * (out.entropy - discrete_entropy) -
              discrete_beta.value_or(beta) * discrete_entropy;
  return out;
}

PpoLoss run(const Minibatch& m, float eps, float beta, torch::Tensor* log_prob = nullptr,
            torch::Tensor* values = nullptr, std::optional<float> discrete_beta = std::nullopt) {
  auto lp = tensor(m.log_prob).requires_grad_(true);
  auto v = tensor(m.values).requires_grad_(true);
  if (log_prob) *log_prob = lp;
  if (values) *values = v;
  return ppo_loss(lp, tensor(m.old_log_prob), tensor(m.advantages), v, tensor(m.old_values),
                  tensor(m.returns), tensor(m.entropy),
                  m.discrete_entropy.empty() ? torch::Tensor() : tensor(m.discrete_entropy), eps,
                  beta, discrete_beta.value_or(beta));
}

void expect_matches_naive(const Minibatch& m, float eps, float beta,
                          std::optional<float> discrete_beta = std::nullopt) {
  PpoLoss got = run(m, eps, beta, nullptr, nullptr, discrete_beta);
  NaiveLoss ref = naive_loss(m, eps, beta, discrete_beta);
  EXPECT_NEAR(got.policy.item<float>(), ref.policy, 1e-5 * (1 + std::abs(ref.policy)));
  EXPECT_NEAR(got.value.item<float>(), ref.value, 1e-5 * (1 + std::abs(ref.value)));
  EXPECT_NEAR(got.entropy.item<float>(), ref.entropy, 1e-5 * (1 + std::abs(ref.entropy)));
  EXPECT_NEAR(got.total.item<float>(), ref.total, 1e-5 * (1 + std::abs(ref.total)));
  EXPECT_NEAR(got.approx_kl.item<float>(), ref.approx_kl, 1e-5 * (1 + ref.approx_kl));
  EXPECT_FLOAT_EQ(got.clip_fraction.item<float>(), float(ref.clip_fraction));
  EXPECT_FALSE(got.approx_kl.requires_grad());
}

// one element in each case: ratio above / inside / below the clip range, advantage + / -,
// value moved beyond / within the clip range towards / away from the return
Minibatch case_batch() {
  Minibatch m;
  const float up = std::log(1.5f), down = std::log(0.6f), in = std::log(1.05f);
  m.log_prob = {up, up, down, down, in, in, 0.f, 0.f};
  m.old_log_prob = std::vector<float>(8, 0.f);
  m.advantages = {2.f, -2.f, 1.5f, -1.5f, 0.7f, -0.7f, 1.f, -1.f};
  m.old_values = {0.f, 0.f, 1.f, 1.f, -1.f, -1.f, 2.f, 2.f};
  m.values = {0.5f, -0.5f, 1.1f, 0.9f, -0.3f, -1.8f, 2.f, 2.05f};
  m.returns = {1.f, 1.f, 0.f, 3.f, 0.f, -0.5f, 2.5f, -1.f};
  m.entropy = {1.f, 0.5f, 0.2f, 1.3f, 0.9f, 0.4f, 0.7f, 1.1f};
  return m;
}

TEST(PpoLossTest, EveryClipCaseMatchesNaive) {
  expect_matches_naive(case_batch(), 0.2f, 0.01f);
  // two rows above the range (1.5) and two below (0.6) of eight; the KL term of each row is
  // r - 1 - log r: 0.5 - log 1.5, -0.4 - log 0.6, 0.05 - log 1.05, twice each, and 0 twice
  PpoLoss l = run(case_batch(), 0.2f, 0.01f);
  EXPECT_FLOAT_EQ(l.clip_fraction.item<float>(), 0.5f);
  const double kl = 2 * ((0.5 - std::log(1.5)) + (-0.4 - std::log(0.6)) + (0.05 - std::log(1.05))) / 8;
  EXPECT_NEAR(l.approx_kl.item<float>(), kl, 1e-6);
  // the same policy measures no change
  Minibatch same = case_batch();
  same.log_prob = same.old_log_prob;
  PpoLoss none = run(same, 0.2f, 0.01f);
  EXPECT_EQ(none.approx_kl.item<float>(), 0.f);
  EXPECT_EQ(none.clip_fraction.item<float>(), 0.f);
  expect_matches_naive(case_batch(), 0.1f, 0.f);
}

TEST(PpoLossTest, RandomMinibatchesMatchNaive) {
  torch::manual_seed(11);
  for (int trial = 0; trial < 5; ++trial) {
    const int n = 32 + 17 * trial;
    auto vec = [&](float scale) {
      auto t = (scale * torch::randn({n})).contiguous();
      return std::vector<float>(t.data_ptr<float>(), t.data_ptr<float>() + n);
    };
    Minibatch m;
    m.old_log_prob = vec(1.f);
    m.log_prob = m.old_log_prob;
    auto shift = vec(0.3f);
    for (int i = 0; i < n; ++i) m.log_prob[i] += shift[i];
    m.advantages = vec(1.f);
    m.old_values = vec(1.f);
    m.values = m.old_values;
    auto dv = vec(0.4f);
    for (int i = 0; i < n; ++i) m.values[i] += dv[i];
    m.returns = vec(2.f);
    m.entropy = vec(1.f);
    expect_matches_naive(m, 0.2f, 0.005f);
  }
}

TEST(PpoLossTest, DiscreteBetaWeighsTheBranchesEntropy) {
  Minibatch m = case_batch();
  m.discrete_entropy = {0.6f, 0.1f, 0.2f, 0.7f, 0.0f, 0.4f, 0.3f, 0.5f};  // at most entropy
  expect_matches_naive(m, 0.2f, 0.01f, 0.05f);
  expect_matches_naive(m, 0.2f, 0.01f, 0.f);
  expect_matches_naive(m, 0.2f, 0.01f);  // discrete_beta = beta: one bonus over all of it
  // the totals differ by exactly the extra bonus on the branches: (0.05 - 0.01) mean(H_discrete)
  const float same = run(m, 0.2f, 0.01f).total.item<float>();
  const float more = run(m, 0.2f, 0.01f, nullptr, nullptr, 0.05f).total.item<float>();
  EXPECT_NEAR(same - more, 0.04 * 2.8 / 8, 1e-6);
}

TEST(PpoLossTest, ClippedRegionHasZeroPolicyGradient) {
  Minibatch m = case_batch();
  const float eps = 0.2f;
  torch::Tensor lp;
  PpoLoss got = run(m, eps, 0.f, &lp);
  got.policy.backward();
  auto grad = lp.grad().contiguous();
  const int n = static_cast<int>(m.log_prob.size());
  for (int i = 0; i < n; ++i) {
    const double r = std::exp(double(m.log_prob[i]) - m.old_log_prob[i]);
    const double a = m.advantages[i];
    const bool clipped = (r > 1 + eps && a > 0) || (r < 1 - eps && a < 0);
    // d(-r A / n) / d log_prob = -r A / n outside the clipped region
    const double expected = clipped ? 0.0 : -r * a / n;
    EXPECT_NEAR(grad[i].item<float>(), expected, 1e-6) << "element " << i;
    if (clipped) {
      EXPECT_EQ(grad[i].item<float>(), 0.f) << "element " << i;
    }
  }
  // the case batch has both clipped sides and unclipped elements
  EXPECT_EQ(grad[0].item<float>(), 0.f);
  EXPECT_EQ(grad[3].item<float>(), 0.f);
  EXPECT_NE(grad[1].item<float>(), 0.f);
  EXPECT_NE(grad[2].item<float>(), 0.f);
}

TEST(PpoLossTest, ValueGradientFollowsTheLargerTerm) {
  Minibatch m = case_batch();
  const float eps = 0.2f;
  torch::Tensor v;
  PpoLoss got = run(m, eps, 0.f, nullptr, &v);
  got.value.backward();
  auto grad = v.grad().contiguous();
  const int n = static_cast<int>(m.values.size());
  for (int i = 0; i < n; ++i) {
    const double val = m.values[i], old = m.old_values[i], ret = m.returns[i];
    const double diff = val - old;
    const double v_clip = old + std::min(std::max(diff, double(-eps)), double(eps));
    const double plain = (ret - val) * (ret - val), clip = (ret - v_clip) * (ret - v_clip);
    // when the clipped term wins and the value moved out of range, the value gets no gradient
    double expected = 0;
    if (plain >= clip) {
      expected = -2 * (ret - val) / n;
    } else if (std::abs(diff) < eps) {
      expected = -2 * (ret - v_clip) / n;
    }
    EXPECT_NEAR(grad[i].item<float>(), expected, 1e-5) << "element " << i;
  }
}

}  // namespace
}  // namespace rlt
