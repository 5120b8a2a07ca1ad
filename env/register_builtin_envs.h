// Registers every environment of env/ with the EnvRegistry (idempotent).
#pragma once

namespace rlt {
void register_builtin_envs();
}  // namespace rlt
