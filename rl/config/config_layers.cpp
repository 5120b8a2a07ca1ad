// Layering a run configuration over its base: a key-by-key merge of two yaml-cpp trees that
// builds new mappings only where both trees have one and reuses every other node as it is.
#include "rl/config/config_layers.h"

#include <set>
#include <utility>

#include "rl/config/config_parser.h"

namespace rlt {

namespace {

// Whether `path` is `ancestor` or lies below it ("a.b" is below "a", "a[1]" too, "ab" is not).
bool is_within(const std::string& path, const std::string& ancestor) {
  if (ancestor.empty()) return true;
  if (path.compare(0, ancestor.size(), ancestor) != 0) return false;
  return path.size() == ancestor.size() || path[ancestor.size()] == '.' ||
         path[ancestor.size()] == '[';
}

std::string child_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

int line_of(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

// The entry of scalar key `key` in mapping `map` (the key node, for its line, and the value).
std::pair<YAML::Node, YAML::Node> find_entry(const YAML::Node& map, const std::string& key) {
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) return {it->first, it->second};
  }
  return {YAML::Node(YAML::NodeType::Undefined), YAML::Node(YAML::NodeType::Undefined)};
}

void lay_over_at(const YAML::Node& under, const KeyOrigins& under_origins, const YAML::Node& over,
                 const std::string& path, const std::string& over_file, KeyOrigins* origins,
                 YAML::Node* out);

// The value of entry `entry`'s scalar key `name`, or "" when it has none (or is no mapping).
std::string name_of(const YAML::Node& entry) {
  if (!entry.IsMap()) return "";
  const YAML::Node name = find_entry(entry, "name").second;
  return name.IsDefined() && name.IsScalar() ? name.Scalar() : "";
}

// Whether `list` is a list of named mappings (a curriculum's lessons), which a mapping can patch.
bool is_named_list(const YAML::Node& list) {
  if (!list.IsSequence() || list.size() == 0) return false;
  for (const YAML::Node& entry : list) {
    if (name_of(entry).empty()) return false;
  }
  return true;
}

// `patches` (name -> mapping) laid over the entries of `list` that have those names; the other
// entries are kept as they are, and the list keeps its order and length.
YAML::Node patch_by_name(const YAML::Node& list, const KeyOrigins& under_origins,
                         const YAML::Node& patches, const std::string& path,
                         const std::string& over_file, KeyOrigins* origins) {
  std::set<std::string> names;
  std::string listed;
  for (const YAML::Node& entry : list) {
    names.insert(name_of(entry));
    listed += (listed.empty() ? "'" : ", '") + name_of(entry) + "'";
  }
  std::set<std::string> patched;
  for (auto it = patches.begin(); it != patches.end(); ++it) {
    const std::string name = it->first.IsScalar() ? it->first.Scalar() : "";
    if (!patched.insert(name).second) {
      throw ConfigError(over_file, path, line_of(it->first), "entry '" + name + "' appears twice");
    }
    if (!names.count(name)) {
      throw ConfigError(over_file, path, line_of(it->first),
                        "the base's list has no entry named '" + name +
                            "' to change (its names: " + listed + ")");
    }
    if (!it->second.IsMap()) {
      throw ConfigError(over_file, child_path(path, name), line_of(it->first),
                        "a change to entry '" + name + "' of the base's list must be a mapping");
    }
  }
  YAML::Node result(YAML::NodeType::Sequence);
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string at = path + "[" + std::to_string(i) + "]";
    const YAML::Node patch = find_entry(patches, name_of(list[i])).second;
    if (!patch.IsDefined()) {
      result.push_back(list[i]);
      origins->take_subtree(at, under_origins);
      continue;
    }
    YAML::Node merged(YAML::NodeType::Map);
    lay_over_at(list[i], under_origins, patch, at, over_file, origins, &merged);
    result.push_back(merged);
  }
  return result;
}

void lay_over_at(const YAML::Node& under, const KeyOrigins& under_origins, const YAML::Node& over,
                 const std::string& path, const std::string& over_file, KeyOrigins* origins,
                 YAML::Node* out) {
  std::set<std::string> over_keys;
  for (auto it = over.begin(); it != over.end(); ++it) {
    if (!it->first.IsScalar()) continue;  // the parser reports a key that is not a name
    if (!over_keys.insert(it->first.Scalar()).second) {
      throw ConfigError(over_file, path, line_of(it->first),
                        "key '" + it->first.Scalar() + "' appears twice");
    }
  }
  // The base's keys first, in the base's order, then the keys only `over` has, in its order.
  std::set<std::string> under_keys;
  for (auto it = under.begin(); it != under.end(); ++it) {
    const std::string key = it->first.IsScalar() ? it->first.Scalar() : "";
    under_keys.insert(key);
    const std::string at = child_path(path, key);
    if (!over_keys.count(key)) {
      out->force_insert(it->first, it->second);
      origins->take_subtree(at, under_origins);
      continue;
    }
    // over's key node, so that messages about the key give the line in over's file
    const auto [over_key, replacement] = find_entry(over, key);
    if (it->second.IsMap() && replacement.IsMap()) {
      YAML::Node merged(YAML::NodeType::Map);
      lay_over_at(it->second, under_origins, replacement, at, over_file, origins, &merged);
      out->force_insert(over_key, merged);
    } else if (is_named_list(it->second) && replacement.IsMap()) {
      out->force_insert(over_key, patch_by_name(it->second, under_origins, replacement, at,
                                                over_file, origins));
    } else {
      out->force_insert(over_key, replacement);
    }
  }
  for (auto it = over.begin(); it != over.end(); ++it) {
    if (!it->first.IsScalar() || !under_keys.count(it->first.Scalar())) {
      out->force_insert(it->first, it->second);
    }
  }
}

}  // namespace

const std::string& KeyOrigins::file_of(const std::string& key_path) const {
  // The nearest listed ancestor: the longest listed path that key_path lies within.
  const std::string* best = &top_file_;
  size_t best_length = 0;
  bool found = false;
  for (auto it = files_.begin(); it != files_.end(); ++it) {
    if (is_within(key_path, it->first) && (!found || it->first.size() >= best_length)) {
      best = &it->second;
      best_length = it->first.size();
      found = true;
    }
  }
  return *best;
}

void KeyOrigins::take_subtree(const std::string& key_path, const KeyOrigins& from) {
  files_[key_path] = from.file_of(key_path);
  for (const auto& [path, file] : from.files_) {
    if (path != key_path && is_within(path, key_path)) files_[path] = file;
  }
}

YAML::Node lay_over(const YAML::Node& under, const KeyOrigins& under_origins,
                    const YAML::Node& over, const std::string& over_file, KeyOrigins* origins) {
  *origins = KeyOrigins(over_file);
  YAML::Node merged(YAML::NodeType::Map);
  lay_over_at(under, under_origins, over, "", over_file, origins, &merged);
  return merged;
}

}  // namespace rlt
