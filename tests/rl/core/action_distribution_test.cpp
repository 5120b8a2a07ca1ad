// Equivalence of evaluate_actions with a naive per-element computation in double (Gaussian density,
// softmax by hand over the allowed options) for a hybrid action spec (2 continuous + branches
// {3, 2}), with and without masks, and autograd gradients against their analytic forms.
#include "rl/core/action_distribution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace rlt {
namespace {

ActionSpec hybrid_spec() {
  ActionSpec spec;
  spec.continuous_size = 2;
  spec.discrete_branches = {3, 2};
  return spec;
}

struct Batch {
  torch::Tensor mean;        // [B, 2]
  torch::Tensor log_std;     // [2]
  torch::Tensor logits;      // [B, 5]
  torch::Tensor mask;        // [B, 5]
  torch::Tensor continuous;  // [B, 2]
  torch::Tensor discrete;    // [B, 2] int64
};

// random batch; every row's chosen options are allowed by `mask`
Batch random_batch(int64_t rows, const torch::Tensor& mask, uint64_t seed) {
  torch::manual_seed(seed);
  Batch b;
  b.mean = torch::randn({rows, 2});
  b.log_std = torch::tensor({-0.3f, 0.4f});
  b.logits = 2.f * torch::randn({rows, 5});
  b.mask = mask;
  b.continuous = b.mean + torch::randn({rows, 2}) * torch::exp(b.log_std);
  b.discrete = torch::zeros({rows, 2}, torch::kLong);
  auto m = mask.accessor<float, 2>();
  auto d = b.discrete.accessor<int64_t, 2>();
  const int offsets[2] = {0, 3}, sizes[2] = {3, 2};
  for (int64_t r = 0; r < rows; ++r)
    for (int k = 0; k < 2; ++k) {
      std::vector<int> allowed;
      for (int o = 0; o < sizes[k]; ++o)
        if (m[r][offsets[k] + o] > 0.5f) allowed.push_back(o);
      d[r][k] = allowed[(r * 7 + k * 3) % allowed.size()];
    }
  return b;
}

struct Naive {
  std::vector<double> log_prob, entropy, discrete_entropy;  // [B]
};

// double-precision reference, one element at a time
Naive naive(const Batch& b) {
  const int64_t rows = b.mean.size(0);
  Naive out{std::vector<double>(rows, 0.0), std::vector<double>(rows, 0.0),
            std::vector<double>(rows, 0.0)};
  auto mean = b.mean.accessor<float, 2>();
  auto log_std = b.log_std.accessor<float, 1>();
  auto logits = b.logits.accessor<float, 2>();
  auto mask = b.mask.accessor<float, 2>();
  auto act = b.continuous.accessor<float, 2>();
  auto choice = b.discrete.accessor<int64_t, 2>();
  for (int64_t r = 0; r < rows; ++r) {
    for (int j = 0; j < 2; ++j) {
      const double sigma = std::exp(double(log_std[j]));
      const double d = double(act[r][j]) - double(mean[r][j]);
      const double density = std::exp(-d * d / (2 * sigma * sigma)) / (sigma * std::sqrt(2 * M_PI));
      out.log_prob[r] += std::log(density);
      out.entropy[r] += 0.5 * std::log(2 * M_PI * M_E * sigma * sigma);
    }
    const int offsets[2] = {0, 3}, sizes[2] = {3, 2};
    for (int k = 0; k < 2; ++k) {
      double z = 0;
      for (int o = 0; o < sizes[k]; ++o)
        if (mask[r][offsets[k] + o] > 0.5f) z += std::exp(double(logits[r][offsets[k] + o]));
      for (int o = 0; o < sizes[k]; ++o) {
        if (mask[r][offsets[k] + o] < 0.5f) continue;
        const double p = std::exp(double(logits[r][offsets[k] + o])) / z;
        out.entropy[r] -= p * std::log(p);
        out.discrete_entropy[r] -= p * std::log(p);
        if (o == choice[r][k]) out.log_prob[r] += std::log(p);
      }
    }
  }
  return out;
}

void expect_matches_naive(const Batch& b) {
  auto got = evaluate_actions(hybrid_spec(), b.mean, b.log_std, b.logits, b.mask, b.continuous,
                              b.discrete);
  Naive ref = naive(b);
  ASSERT_EQ(got.log_prob.sizes(), torch::IntArrayRef({b.mean.size(0)}));
  ASSERT_EQ(got.entropy.sizes(), torch::IntArrayRef({b.mean.size(0)}));
  ASSERT_EQ(got.discrete_entropy.sizes(), torch::IntArrayRef({b.mean.size(0)}));
  auto lp = got.log_prob.accessor<float, 1>();
  auto ent = got.entropy.accessor<float, 1>();
  auto discrete_ent = got.discrete_entropy.accessor<float, 1>();
  for (int64_t r = 0; r < b.mean.size(0); ++r) {
    EXPECT_NEAR(lp[r], ref.log_prob[r], 1e-5 * (1 + std::abs(ref.log_prob[r]))) << "row " << r;
    EXPECT_NEAR(ent[r], ref.entropy[r], 1e-5 * (1 + std::abs(ref.entropy[r]))) << "row " << r;
    EXPECT_NEAR(discrete_ent[r], ref.discrete_entropy[r], 1e-5 * (1 + ref.discrete_entropy[r]))
        << "row " << r;
  }
}

TEST(ActionDistributionTest, UnmaskedMatchesNaive) {
  expect_matches_naive(random_batch(64, torch::ones({64, 5}), 1));
}

TEST(ActionDistributionTest, MaskedMatchesNaive) {
  // a varied mask: each row forbids a different (never complete) set of options
  auto mask = torch::ones({60, 5});
  auto m = mask.accessor<float, 2>();
  for (int r = 0; r < 60; ++r) {
    if (r % 3 == 1) m[r][r % 3] = 0.f;
    if (r % 3 == 2) m[r][(r / 3) % 3] = m[r][(r / 3 + 1) % 3] = 0.f;
    if (r % 4 == 3) m[r][3 + r % 2] = 0.f;
  }
  expect_matches_naive(random_batch(60, mask, 2));
}

TEST(ActionDistributionTest, ForbiddenOptionHasNoProbabilityAndOthersRenormalize) {
  auto spec = hybrid_spec();
  auto logits = torch::tensor({{1.f, 2.f, 0.5f, -1.f, 1.f}});
  auto mask = torch::tensor({{1.f, 0.f, 1.f, 1.f, 1.f}});
  auto p = torch::exp(masked_log_softmax(spec, logits, mask));
  auto pa = p.accessor<float, 2>();
  EXPECT_LT(pa[0][1], 1e-30f);
  const double z = std::exp(1.0) + std::exp(0.5);
  EXPECT_NEAR(pa[0][0], std::exp(1.0) / z, 1e-6);
  EXPECT_NEAR(pa[0][2], std::exp(0.5) / z, 1e-6);
  // the unmasked branch keeps its plain softmax
  const double z2 = std::exp(-1.0) + std::exp(1.0);
  EXPECT_NEAR(pa[0][3], std::exp(-1.0) / z2, 1e-6);
  EXPECT_NEAR(pa[0][4], std::exp(1.0) / z2, 1e-6);
}

TEST(ActionDistributionTest, MaskingChangesEntropyAsTheNaiveFormulaSays) {
  auto spec = hybrid_spec();
  auto mean = torch::zeros({1, 2});
  auto log_std = torch::zeros({2});
  auto logits = torch::tensor({{0.3f, -0.2f, 1.1f, 0.f, 0.f}});
  auto act = torch::zeros({1, 2});
  auto choice = torch::tensor({{0, 0}}, torch::kLong);
  auto open = evaluate_actions(spec, mean, log_std, logits, torch::ones({1, 5}), act, choice);
  // forbid option 2 of branch 0 and option 1 of branch 1 (that branch becomes certain)
  auto mask = torch::tensor({{1.f, 1.f, 0.f, 1.f, 0.f}});
  auto masked = evaluate_actions(spec, mean, log_std, logits, mask, act, choice);
  const double gauss = 2 * 0.5 * std::log(2 * M_PI * M_E);
  auto branch_entropy = [](std::vector<double> l) {
    double z = 0, h = 0;
    for (double x : l) z += std::exp(x);
    for (double x : l) h -= std::exp(x) / z * (x - std::log(z));
    return h;
  };
  const double h_open = gauss + branch_entropy({0.3, -0.2, 1.1}) + std::log(2.0);
  const double h_masked = gauss + branch_entropy({0.3, -0.2});
  EXPECT_NEAR(open.entropy.item<float>(), h_open, 1e-5);
  EXPECT_NEAR(masked.entropy.item<float>(), h_masked, 1e-5);
  // the certain branch contributes log 1 = 0 to the log-probability
  const double lp_masked =
      2 * -0.5 * std::log(2 * M_PI) + (0.3 - std::log(std::exp(0.3) + std::exp(-0.2)));
  EXPECT_NEAR(masked.log_prob.item<float>(), lp_masked, 1e-5);
}

TEST(ActionDistributionTest, GradientsMatchAnalyticForms) {
  Batch b = random_batch(16, torch::ones({16, 5}), 3);
  auto mask = b.mask.clone();
  mask[0][1] = 0.f;  // a forbidden option gets no gradient
  b.discrete[0][0] = 0;
  auto mean = b.mean.clone().requires_grad_(true);
  auto log_std = b.log_std.clone().requires_grad_(true);
  auto logits = b.logits.clone().requires_grad_(true);
  auto got = evaluate_actions(hybrid_spec(), mean, log_std, logits, mask, b.continuous, b.discrete);
  got.log_prob.sum().backward();
  auto sigma = torch::exp(b.log_std);
  // d log_prob / d mean = (a - mu) / sigma^2
  auto expected_mean = (b.continuous - b.mean) / (sigma * sigma);
  EXPECT_TRUE(torch::allclose(mean.grad(), expected_mean, 1e-4, 1e-5))
      << mean.grad() << expected_mean;
  // d log_prob / d log_std = sum over rows of z^2 - 1
  auto z = (b.continuous - b.mean) / sigma;
  auto expected_log_std = (z * z - 1).sum(0);
  EXPECT_TRUE(torch::allclose(log_std.grad(), expected_log_std, 1e-4, 1e-4))
      << log_std.grad() << expected_log_std;
  // d log p(choice) / d logits = onehot - softmax, per branch
  auto p = torch::exp(masked_log_softmax(hybrid_spec(), b.logits, mask));
  auto onehot = torch::zeros({16, 5});
  for (int r = 0; r < 16; ++r) {
    onehot[r][b.discrete[r][0].item<int64_t>()] = 1.f;
    onehot[r][3 + b.discrete[r][1].item<int64_t>()] = 1.f;
  }
  EXPECT_TRUE(torch::allclose(logits.grad(), onehot - p, 1e-4, 1e-5))
      << logits.grad() << onehot - p;
  EXPECT_EQ(logits.grad()[0][1].item<float>(), 0.f);
}

TEST(ActionDistributionTest, ContinuousOnlyAndDiscreteOnly) {
  Batch b = random_batch(8, torch::ones({8, 5}), 4);
  Naive ref = naive(b);
  ActionSpec cont;
  cont.continuous_size = 2;
  auto c = evaluate_actions(cont, b.mean, b.log_std, {}, {}, b.continuous, {});
  ActionSpec disc;
  disc.discrete_branches = {3, 2};
  auto d = evaluate_actions(disc, {}, {}, b.logits, b.mask, {}, b.discrete);
  // the hybrid log-probability and entropy are the sums of the parts
  auto lp = (c.log_prob + d.log_prob).contiguous();
  auto ent = (c.entropy + d.entropy).contiguous();
  for (int r = 0; r < 8; ++r) {
    EXPECT_NEAR(lp[r].item<float>(), ref.log_prob[r], 1e-4) << "row " << r;
    EXPECT_NEAR(ent[r].item<float>(), ref.entropy[r], 1e-4) << "row " << r;
  }
  // without branches there is no discrete part; without a Gaussian it is all of the entropy
  EXPECT_FALSE(c.discrete_entropy.defined());
  EXPECT_TRUE(torch::equal(d.discrete_entropy, d.entropy));
}

}  // namespace
}  // namespace rlt
