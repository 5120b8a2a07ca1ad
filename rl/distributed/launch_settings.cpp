#include "rl/distributed/launch_settings.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace rlt {

namespace {

// the integer value of variable `name` in [low, high], or `fallback` when unset
int integer_variable(const char* name, int fallback, int low, int high) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*end != '\0' || value < low || value > high)
    throw std::invalid_argument(std::string(name) + "=" + text + ": expected an integer in [" +
                                std::to_string(low) + ", " + std::to_string(high) + "]");
  return int(value);
}

}  // namespace

LaunchSettings launch_settings_from_environment() {
  LaunchSettings s;
  const bool has_world = std::getenv("WORLD_SIZE") && *std::getenv("WORLD_SIZE");
  s.world_size = integer_variable("WORLD_SIZE", 1, 1, 65536);
  s.rank = integer_variable("RANK", 0, 0, 65535);
  s.local_rank = integer_variable("LOCAL_RANK", s.rank, 0, 65535);
  s.master_port = integer_variable("MASTER_PORT", 29500, 1, 65535);
  if (const char* addr = std::getenv("MASTER_ADDR"); addr && *addr) s.master_addr = addr;
  if (!has_world && std::getenv("RANK") && *std::getenv("RANK"))
    throw std::invalid_argument("RANK is set but WORLD_SIZE is not: set both (torchrun does)");
  if (s.rank >= s.world_size)
    throw std::invalid_argument("RANK=" + std::to_string(s.rank) +
                                " is not below WORLD_SIZE=" + std::to_string(s.world_size));
  return s;
}

}  // namespace rlt
