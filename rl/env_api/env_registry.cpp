#include "rl/env_api/env_registry.h"

#include <algorithm>
#include <stdexcept>

namespace rlt {

EnvRegistry& EnvRegistry::instance() {
  static EnvRegistry registry;
  return registry;
}

void EnvRegistry::add(const std::string& name, EnvFactory factory) {
  if (contains(name)) throw std::invalid_argument("environment '" + name + "' registered twice");
  factories_.emplace_back(name, std::move(factory));
}

bool EnvRegistry::contains(const std::string& name) const {
  return std::any_of(factories_.begin(), factories_.end(),
                     [&](const auto& f) { return f.first == name; });
}

std::vector<std::string> EnvRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& f : factories_) out.push_back(f.first);
  std::sort(out.begin(), out.end());
  return out;
}

std::unique_ptr<Env> EnvRegistry::make(const std::string& name, const Parameters& params) const {
  for (const auto& [n, factory] : factories_) {
    if (n != name) continue;
    auto env = factory(params);
    const auto& known = env->spec().default_parameters;
    for (const auto& [k, v] : params) {
      if (!known.count(k)) {
        std::string list;
        for (const auto& [kk, vv] : known) list += (list.empty() ? "" : ", ") + kk;
        throw std::invalid_argument("environment '" + name + "' has no parameter '" + k +
                                    "' (known: " + (list.empty() ? "none" : list) + ")");
      }
    }
    env->set_parameters(params);
    return env;
  }
  std::string list;
  for (const auto& n2 : names()) list += (list.empty() ? "" : ", ") + n2;
  throw std::invalid_argument("unknown environment '" + name + "' (known: " + list + ")");
}

}  // namespace rlt
