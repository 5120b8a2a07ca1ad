// FlatAdam against LibTorch's own Adam (the reference), gradient clipping against
// torch::nn::utils::clip_grad_norm_, and relinking after a module load.
#include "rl/core/flat_adam.h"

#include <gtest/gtest.h>

#include <sstream>

namespace rlt {
namespace {

// two small layers; parameters of different shapes
struct Net : torch::nn::Module {
  Net() {
    w1 = register_parameter("w1", torch::randn({3, 5}));
    b1 = register_parameter("b1", torch::randn({5}));
    w2 = register_parameter("w2", torch::randn({5, 2}));
  }
  torch::Tensor forward(const torch::Tensor& x) { return torch::tanh(torch::addmm(b1, x, w1)).mm(w2); }
  torch::Tensor w1, b1, w2;
};

// one loss whose gradients differ from step to step
torch::Tensor loss_at(Net& net, int step) {
  torch::manual_seed(100 + step);
  auto x = torch::randn({8, 3});
  return (net.forward(x) - 0.3).pow(2).sum();
}

TEST(FlatAdam, MatchesTorchAdamStepByStep) {
  torch::manual_seed(0);
  Net a;
  Net b;
  {
    torch::NoGradGuard g;
    for (size_t i = 0; i < a.parameters().size(); ++i) b.parameters()[i].copy_(a.parameters()[i]);
  }
  torch::optim::Adam reference(a.parameters(), torch::optim::AdamOptions(0.01).eps(1e-5));
  FlatAdam flat(b.parameters(), 1e-5);
  for (int step = 0; step < 50; ++step) {
    reference.zero_grad();
    loss_at(a, step).backward();
    reference.step();
    flat.zero_grad();
    loss_at(b, step).backward();
    flat.step(0.01);
  }
  for (size_t i = 0; i < a.parameters().size(); ++i)
    EXPECT_TRUE(torch::allclose(a.parameters()[i], b.parameters()[i], 1e-5, 1e-6)) << "parameter " << i;
  // the steps did change the parameters
  torch::manual_seed(0);
  Net initial;
  EXPECT_FALSE(torch::allclose(initial.w1, b.w1, 1e-3, 1e-3));
}

TEST(FlatAdam, ParametersAndGradientsAreViewsOfTheFlatBuffers) {
  torch::manual_seed(1);
  Net net;
  auto before = net.w2.detach().clone();
  FlatAdam flat(net.parameters());
  EXPECT_TRUE(torch::equal(net.w2, before));  // values kept
  EXPECT_EQ(flat.flat_parameters().numel(), 3 * 5 + 5 + 5 * 2);
  flat.zero_grad();
  loss_at(net, 0).backward();
  EXPECT_TRUE(torch::equal(flat.flat_gradients().narrow(0, 20, 10).view({5, 2}), net.w2.grad()));
  EXPECT_GT(flat.flat_gradients().abs().sum().item<float>(), 0.f);
}

TEST(FlatAdam, ClipMatchesTorchClipGradNorm) {
  torch::manual_seed(2);
  Net a;
  Net b;
  {
    torch::NoGradGuard g;
    for (size_t i = 0; i < a.parameters().size(); ++i) b.parameters()[i].copy_(a.parameters()[i]);
  }
  FlatAdam flat(b.parameters());
  loss_at(a, 3).backward();
  flat.zero_grad();
  loss_at(b, 3).backward();
  const float expected = torch::nn::utils::clip_grad_norm_(a.parameters(), 0.5);
  const float norm = flat.clip_grad_norm(0.5);
  EXPECT_NEAR(norm, expected, 1e-4f * expected);
  EXPECT_GT(norm, 0.5f);  // the clip was active
  for (size_t i = 0; i < a.parameters().size(); ++i)
    EXPECT_TRUE(torch::allclose(a.parameters()[i].grad(), b.parameters()[i].grad(), 1e-5, 1e-7));
}

TEST(FlatAdam, RelinkAfterModuleLoadKeepsTrainingTheLoadedValues) {
  torch::manual_seed(3);
  Net source;
  std::stringstream stream;
  {
    torch::serialize::OutputArchive out;
    source.save(out);
    out.save_to(stream);
  }
  torch::manual_seed(4);
  Net target;
  FlatAdam flat(target.parameters());
  torch::serialize::InputArchive in;
  in.load_from(stream);
  target.load(in);  // replaces the parameters' storage
  flat.relink();
  EXPECT_TRUE(torch::equal(target.w1, source.w1));
  EXPECT_TRUE(torch::equal(flat.flat_parameters().narrow(0, 0, 15).view({3, 5}), source.w1));
  // an update through the flat buffer reaches the module's parameters
  flat.zero_grad();
  loss_at(target, 0).backward();
  flat.step(0.1);
  EXPECT_FALSE(torch::equal(target.w1, source.w1));
  EXPECT_TRUE(torch::equal(flat.flat_parameters().narrow(0, 0, 15).view({3, 5}), target.w1));
}

}  // namespace
}  // namespace rlt
