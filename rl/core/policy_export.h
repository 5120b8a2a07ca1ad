// Export of a behavior's actor as a TorchScript module, built with torch::jit (no Python needed).
//
// The module's forward takes the list of observation tensors ([B, ...] each, in the order of the
// behavior spec) and an optional action mask [B, M] (1 = allowed), and returns the deterministic
// action as (continuous [B, C] in [-1, 1], discrete [B, K] int64). Observation normalization is
// inside the module. The attribute `spec_json` carries the observation and action specs.
#pragma once

#include <string>

#include "rl/env_api/spec.h"

namespace rlt {

class PolicyNetworkImpl;
class RunningNormalizer;

// Writes the module to `path` atomically (temporary file, then rename).
void export_policy(const PolicyNetworkImpl& net, const RunningNormalizer* normalizer,
                   const BehaviorSpec& spec, const std::string& path);

// JSON description of a behavior spec, as stored in the module's `spec_json`
std::string behavior_spec_json(const BehaviorSpec& spec);

}  // namespace rlt
