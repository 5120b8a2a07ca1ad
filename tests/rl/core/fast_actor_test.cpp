// Equivalence of the Eigen FastActor with the LibTorch PolicyNetwork it copies: deterministic
// actions are the torch mean and masked argmax, values agree, and the log-probability reported for
// a sampled action is evaluate_actions' log-probability of that action; for every activation,
// shared and separate critics, with and without normalization. Sampling respects masks, follows
// the distribution, and is a function of the rng seed alone.
#include "rl/core/fast_actor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "rl/core/action_distribution.h"
#include "rl/core/policy_network.h"

namespace rlt {
namespace {

constexpr int kObs = 6;

ActionSpec make_spec(int continuous, std::vector<int> branches) {
  ActionSpec spec;
  spec.continuous_size = continuous;
  spec.discrete_branches = std::move(branches);
  return spec;
}

// a network whose weights are far from their initialization (small heads, zero biases, log_std 0)
PolicyNetwork make_network(const ActionSpec& spec, Activation act, bool shared, uint64_t seed) {
  torch::manual_seed(seed);
  NetworkShape shape;
  shape.obs_size = kObs;
  shape.action = spec;
  shape.hidden_units = 16;
  shape.num_layers = 2;
  shape.activation = act;
  shape.shared_critic = shared;
  PolicyNetwork net(shape);
  torch::NoGradGuard no_grad;
  for (auto& p : net->parameters()) p.add_(0.4f * torch::randn_like(p));
  return net;
}

RunningNormalizer make_normalizer(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> dist(0.f, 1.f);
  std::vector<float> data(200 * kObs);
  for (int r = 0; r < 200; ++r)
    for (int i = 0; i < kObs; ++i) data[r * kObs + i] = 2.f * i - 3.f + (0.5f + i) * dist(rng);
  RunningNormalizer norm(kObs);
  norm.update(data.data(), 200);
  return norm;
}

RowMatrix random_obs(int rows, std::mt19937_64& rng) {
  // wide enough that some normalized values hit the +-5 clamp
  std::normal_distribution<float> dist(0.f, 6.f);
  RowMatrix obs(rows, kObs);
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < kObs; ++i) obs(r, i) = dist(rng);
  return obs;
}

// random mask [rows, M] with at least one allowed option per branch
std::vector<uint8_t> random_mask(const ActionSpec& spec, int rows, std::mt19937_64& rng) {
  const int m = spec.mask_size();
  std::vector<uint8_t> mask(rows * m, 1);
  for (int r = 0; r < rows; ++r) {
    int offset = 0;
    for (int n : spec.discrete_branches) {
      const int keep = int(rng() % n);
      for (int o = 0; o < n; ++o)
        if (o != keep && rng() % 2) mask[r * m + offset + o] = 0;
      offset += n;
    }
  }
  return mask;
}

// what the trainer feeds the torch network: normalized (or raw) observations
torch::Tensor torch_obs(const RowMatrix& obs, const RunningNormalizer* norm) {
  std::vector<float> x(obs.data(), obs.data() + obs.size());
  if (norm) norm->normalize(x.data(), obs.rows());
  return torch::from_blob(x.data(), {obs.rows(), kObs}).clone();
}

torch::Tensor mask_tensor(const std::vector<uint8_t>& mask, int rows, int m) {
  std::vector<float> f(mask.begin(), mask.end());
  return torch::from_blob(f.data(), {rows, m}).clone();
}

struct Case {
  ActionSpec spec;
  Activation activation;
  bool shared, normalized;
  std::string name() const {
    return std::string(activation == Activation::kTanh   ? "tanh"
                       : activation == Activation::kRelu ? "relu"
                                                         : "swish") +
           (shared ? " shared" : " separate") + (normalized ? " normalized" : " raw") +
           " C=" + std::to_string(spec.continuous_size) +
           " K=" + std::to_string(spec.num_branches());
  }
};

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (Activation a : {Activation::kTanh, Activation::kSwish, Activation::kRelu})
    for (bool shared : {false, true})
      for (bool normalized : {false, true})
        cases.push_back({make_spec(2, {3, 2}), a, shared, normalized});
  // continuous-only and discrete-only specs
  cases.push_back({make_spec(3, {}), Activation::kSwish, false, true});
  cases.push_back({make_spec(0, {4}), Activation::kTanh, true, false});
  return cases;
}

TEST(FastActorTest, MatchesPolicyNetwork) {
  const int rows = 40;
  uint64_t seed = 100;
  for (const Case& c : all_cases()) {
    SCOPED_TRACE(c.name());
    ++seed;
    PolicyNetwork net = make_network(c.spec, c.activation, c.shared, seed);
    RunningNormalizer norm = make_normalizer(seed);
    const RunningNormalizer* normp = c.normalized ? &norm : nullptr;
    FastActor actor;
    actor.copy_from(*net, normp);
    std::mt19937_64 rng(seed);
    RowMatrix obs = random_obs(rows, rng);
    const int m = c.spec.mask_size(), k = c.spec.num_branches(), cs = c.spec.continuous_size;
    std::vector<uint8_t> mask = random_mask(c.spec, rows, rng);
    const uint8_t* maskp = k > 0 ? mask.data() : nullptr;
    torch::Tensor maskt = k > 0 ? mask_tensor(mask, rows, m) : torch::Tensor();

    torch::NoGradGuard no_grad;
    auto x = torch_obs(obs, normp);
    auto out = net->actor(x);
    auto value = net->value(x, out.hidden);
    // torch logits with forbidden options pushed down, for the argmax
    torch::Tensor masked_logits;
    if (k > 0) masked_logits = out.logits + (maskt - 1.f) * 1e8f;

    // deterministic: mean and masked argmax
    ActBatch det;
    actor.act(obs, maskp, true, rng, det);
    ASSERT_EQ(det.continuous.rows(), rows);
    ASSERT_EQ(det.continuous.cols(), cs);
    ASSERT_EQ(det.discrete.cols(), k);
    for (int r = 0; r < rows; ++r) {
      for (int j = 0; j < cs; ++j)
        EXPECT_NEAR(det.continuous(r, j), out.mean[r][j].item<float>(), 1e-5) << "row " << r;
      int offset = 0;
      for (int br = 0; br < k; ++br) {
        const int n = c.spec.discrete_branches[br];
        auto branch = masked_logits[r].narrow(0, offset, n);
        const int choice = det.discrete(r, br);
        ASSERT_GE(choice, 0);
        ASSERT_LT(choice, n);
        EXPECT_TRUE(mask[r * m + offset + choice]) << "row " << r << " branch " << br;
        // the torch argmax, up to float noise between near-equal logits
        const int64_t best = branch.argmax().item<int64_t>();
        if (choice != best) {
          EXPECT_NEAR(branch[choice].item<float>(), branch[best].item<float>(), 1e-5)
              << "row " << r << " branch " << br;
        }
        offset += n;
      }
      EXPECT_NEAR(det.value[r], value[r].item<float>(), 1e-5) << "row " << r;
    }
    Eigen::VectorXf critic = actor.value(obs);
    for (int r = 0; r < rows; ++r) EXPECT_NEAR(critic[r], value[r].item<float>(), 1e-5);

    // sampled: reported log_prob equals evaluate_actions of the same action
    ActBatch sampled;
    actor.act(obs, maskp, false, rng, sampled);
    torch::Tensor cont, disc;
    if (cs > 0) cont = torch::from_blob(sampled.continuous.data(), {rows, cs}).clone();
    if (k > 0) {
      disc = torch::empty({rows, k}, torch::kLong);
      for (int r = 0; r < rows; ++r)
        for (int br = 0; br < k; ++br) disc[r][br] = int64_t(sampled.discrete(r, br));
    }
    auto lp = evaluate_actions(c.spec, out.mean, net->log_std, out.logits, maskt, cont, disc);
    for (int r = 0; r < rows; ++r) {
      const float ref = lp.log_prob[r].item<float>();
      EXPECT_NEAR(sampled.log_prob[r], ref, 1e-4 * (1 + std::abs(ref))) << "row " << r;
      EXPECT_NEAR(sampled.value[r], value[r].item<float>(), 1e-5) << "row " << r;
    }
  }
}

TEST(FastActorTest, SamplesRespectMasks) {
  const ActionSpec spec = make_spec(2, {3, 2});
  PolicyNetwork net = make_network(spec, Activation::kSwish, false, 7);
  FastActor actor;
  actor.copy_from(*net, nullptr);
  std::mt19937_64 rng(8);
  const int rows = 500, m = spec.mask_size();
  RowMatrix obs = random_obs(rows, rng);
  std::vector<uint8_t> mask = random_mask(spec, rows, rng);
  int forbidden = 0, masked_rows = 0;
  for (int draw = 0; draw < 10; ++draw) {
    ActBatch out;
    actor.act(obs, mask.data(), false, rng, out);
    for (int r = 0; r < rows; ++r) {
      EXPECT_TRUE(mask[r * m + out.discrete(r, 0)]) << "row " << r;
      EXPECT_TRUE(mask[r * m + 3 + out.discrete(r, 1)]) << "row " << r;
      EXPECT_TRUE(std::isfinite(out.log_prob[r])) << "row " << r;
    }
  }
  for (uint8_t v : mask) forbidden += v == 0;
  for (int r = 0; r < rows; ++r) masked_rows += mask[r * m] == 0 || mask[r * m + 1] == 0;
  // the masks actually forbid something
  EXPECT_GT(forbidden, rows / 2);
  EXPECT_GT(masked_rows, rows / 4);
}

TEST(FastActorTest, SamplesFollowTheDistribution) {
  const ActionSpec spec = make_spec(2, {3, 2});
  PolicyNetwork net = make_network(spec, Activation::kTanh, false, 9);
  {
    torch::NoGradGuard no_grad;
    net->log_std.copy_(torch::tensor({-0.5f, 0.3f}));
  }
  FastActor actor;
  actor.copy_from(*net, nullptr);
  std::mt19937_64 rng(10);
  const int rows = 20000;
  RowMatrix one = random_obs(1, rng);
  RowMatrix obs = one.replicate(rows, 1);
  std::vector<uint8_t> mask(rows * 5, 1);
  for (int r = 0; r < rows; ++r) mask[r * 5 + 1] = 0;  // forbid option 1 of branch 0
  ActBatch out;
  actor.act(obs, mask.data(), false, rng, out);

  torch::NoGradGuard no_grad;
  auto x = torch::from_blob(one.data(), {1, kObs}).clone();
  auto ref = net->actor(x);
  auto p = torch::exp(masked_log_softmax(spec, ref.logits, mask_tensor(mask, 1, 5)))[0];
  std::vector<double> freq(5, 0.0);
  for (int r = 0; r < rows; ++r) {
    freq[out.discrete(r, 0)] += 1.0 / rows;
    freq[3 + out.discrete(r, 1)] += 1.0 / rows;
  }
  for (int o = 0; o < 5; ++o) EXPECT_NEAR(freq[o], p[o].item<float>(), 0.015) << "option " << o;
  EXPECT_EQ(freq[1], 0.0);
  for (int j = 0; j < 2; ++j) {
    const double mu = ref.mean[0][j].item<float>(), sigma = std::exp(net->log_std[j].item<float>());
    double s = 0, s2 = 0;
    for (int r = 0; r < rows; ++r) {
      s += out.continuous(r, j);
      s2 += double(out.continuous(r, j)) * out.continuous(r, j);
    }
    const double mean = s / rows, sd = std::sqrt(s2 / rows - mean * mean);
    EXPECT_NEAR(mean, mu, 4 * sigma / std::sqrt(double(rows))) << "dim " << j;
    EXPECT_NEAR(sd, sigma, 0.03 * sigma) << "dim " << j;
  }
}

TEST(FastActorTest, SameSeedSameSamples) {
  const ActionSpec spec = make_spec(2, {3, 2});
  PolicyNetwork net = make_network(spec, Activation::kRelu, true, 11);
  RunningNormalizer norm = make_normalizer(12);
  FastActor actor;
  actor.copy_from(*net, &norm);
  std::mt19937_64 data_rng(13);
  RowMatrix obs = random_obs(30, data_rng);
  std::vector<uint8_t> mask = random_mask(spec, 30, data_rng);
  auto draw = [&](uint64_t seed) {
    std::mt19937_64 rng(seed);
    ActBatch a, b;
    actor.act(obs, mask.data(), false, rng, a);
    actor.act(obs, mask.data(), false, rng, b);  // a second draw from the same stream
    return std::make_pair(a, b);
  };
  auto first = draw(77), second = draw(77), other = draw(78);
  EXPECT_EQ(first.first.continuous, second.first.continuous);
  EXPECT_EQ(first.first.discrete, second.first.discrete);
  EXPECT_EQ(first.first.log_prob, second.first.log_prob);
  EXPECT_EQ(first.second.continuous, second.second.continuous);
  EXPECT_EQ(first.second.discrete, second.second.discrete);
  // the stream moves on, and another seed gives other samples
  EXPECT_NE(first.first.continuous, first.second.continuous);
  EXPECT_NE(first.first.continuous, other.first.continuous);
}

}  // namespace
}  // namespace rlt
