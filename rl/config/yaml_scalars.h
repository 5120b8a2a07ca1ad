// How the configuration reads YAML scalars it does not convert itself: which are strings the
// author quoted, and which spell true or false. One rule for the parser and the layering.
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>

namespace rlt {

// A scalar the author wrote as a string: quoted, or tagged !!str.
bool is_quoted(const YAML::Node& node);

// true or false for an unquoted scalar spelled as YAML 1.1 does (true, True, TRUE, yes, on, ...
// and their false counterparts); nothing for any other node ("y", "1", "true" in quotes).
std::optional<bool> plain_bool(const YAML::Node& node);

}  // namespace rlt
