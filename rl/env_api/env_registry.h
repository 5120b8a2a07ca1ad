// Environments registered by name (e.g. "CartPole") and built from a parameter map.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rl/env_api/env.h"

namespace rlt {

using EnvFactory = std::function<std::unique_ptr<Env>(const Parameters&)>;

class EnvRegistry {
 public:
  static EnvRegistry& instance();

  // Registers `factory` under `name`; registering a name twice is an error.
  void add(const std::string& name, EnvFactory factory);
  bool contains(const std::string& name) const;
  std::vector<std::string> names() const;  // sorted

  // Builds env `name`. Throws std::invalid_argument naming the env or the parameter when `name` is
  // unknown or `params` holds a name the env does not declare in its default_parameters.
  std::unique_ptr<Env> make(const std::string& name, const Parameters& params = {}) const;

 private:
  std::vector<std::pair<std::string, EnvFactory>> factories_;
};

}  // namespace rlt
