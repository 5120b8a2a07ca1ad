#include "rl/core/policy_export.h"

#include <torch/script.h>

#include <cctype>
#include <sstream>

#include "rl/core/atomic_file.h"
#include "rl/core/json.h"
#include "rl/core/policy_network.h"
#include "rl/core/running_normalizer.h"

namespace rlt {

std::string behavior_spec_json(const BehaviorSpec& spec) {
  std::ostringstream os;
  os << "{\"name\":" << json_string(spec.name) << ",\"observations\":[";
  for (size_t i = 0; i < spec.observations.size(); ++i) {
    const auto& o = spec.observations[i];
    os << (i ? "," : "") << "{\"name\":" << json_string(o.name) << ",\"shape\":[";
    for (size_t d = 0; d < o.shape.size(); ++d) os << (d ? "," : "") << o.shape[d];
    os << "],\"kind\":\"" << (o.kind == ObservationKind::kGrid ? "grid" : "vector") << "\"}";
  }
  os << "],\"action\":{\"continuous_size\":" << spec.action.continuous_size
     << ",\"discrete_branches\":[";
  for (size_t i = 0; i < spec.action.discrete_branches.size(); ++i)
    os << (i ? "," : "") << spec.action.discrete_branches[i];
  os << "]},\"agent_slots\":" << spec.agent_slots << "}";
  return os.str();
}

namespace {
// TorchScript expression of the activation of `h`
std::string activation_code(Activation a) {
  switch (a) {
    case Activation::kTanh:
      return "torch.tanh(h)";
    case Activation::kRelu:
      return "torch.relu(h)";
    case Activation::kSwish:
      break;
  }
  return "h * torch.sigmoid(h)";
}
}  // namespace

void export_policy(const PolicyNetworkImpl& net, const RunningNormalizer* normalizer,
                   const BehaviorSpec& spec, const std::string& path) {
  torch::NoGradGuard no_grad;
  const auto& shape = net.shape();
  // the module's class name must be an identifier: behavior names may hold any character
  std::string class_name = "rlt_policy_" + spec.name;
  for (char& c : class_name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  torch::jit::Module m(class_name);
  auto add = [&](const std::string& name, const torch::Tensor& t) {
    m.register_buffer(name, t.detach().clone());
  };
  std::ostringstream src;
  src << "def forward(self, observations: List[Tensor], action_mask: Optional[Tensor] = None)"
         " -> Tuple[Tensor, Tensor]:\n";
  src << "    flat = [o.flatten(1) for o in observations]\n";
  src << "    x = torch.cat(flat, 1)\n";
  src << "    batch = x.size(0)\n";
  if (normalizer) {
    add("obs_mean", torch::tensor(normalizer->mean_float()));
    add("obs_inv_std", torch::tensor(normalizer->inverse_std()));
    src << "    x = torch.clamp((x - self.obs_mean) * self.obs_inv_std, -5.0, 5.0)\n";
  }
  for (size_t l = 0; l < net.actor_body.size(); ++l) {
    add("w" + std::to_string(l), net.actor_body[l].weight);
    add("b" + std::to_string(l), net.actor_body[l].bias);
    src << "    h = torch.addmm(self.b" << l << ", x, self.w" << l << ")\n";
    src << "    x = " << activation_code(shape.activation) << "\n";
  }
  if (spec.action.continuous_size > 0) {
    add("mean_w", net.mean_head.weight);
    add("mean_b", net.mean_head.bias);
    src << "    continuous = torch.clamp(torch.addmm(self.mean_b, x, self.mean_w), -3.0, 3.0) / 3.0\n";
  } else {
    src << "    continuous = torch.zeros([batch, 0])\n";
  }
  if (spec.action.num_branches() > 0) {
    add("logits_w", net.logits_head.weight);
    add("logits_b", net.logits_head.bias);
    src << "    logits = torch.addmm(self.logits_b, x, self.logits_w)\n";
    src << "    if action_mask is not None:\n";
    src << "        logits = logits + (action_mask.float() - 1.0) * 100000000.0\n";
    src << "    choices = []\n";
    int offset = 0;
    for (int n : spec.action.discrete_branches) {
      src << "    choices.append(torch.argmax(logits.narrow(1, " << offset << ", " << n << "), 1))\n";
      offset += n;
    }
    src << "    discrete = torch.stack(choices, 1)\n";
  } else {
    src << "    discrete = torch.zeros([batch, 0]).long()\n";
  }
  src << "    return continuous, discrete\n";
  m.register_attribute("spec_json", c10::StringType::get(), behavior_spec_json(spec));
  m.register_attribute("format_version", c10::IntType::get(), int64_t(1));
  m.define(src.str());
  // serialized in memory first: LibTorch's file writer reports a failed write from a destructor
  std::ostringstream bytes;
  m.save(bytes);
  write_file_atomically(path, bytes.str());
}

}  // namespace rlt
