// Layering a run configuration over its base: a key-by-key merge of two yaml-cpp trees that
// builds new mappings only where both trees have one and reuses every other node as it is.
#include "rl/config/config_layers.h"

#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "rl/config/config_parser.h"
#include "rl/config/yaml_scalars.h"

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

bool is_removal(const YAML::Node& value) { return value.Tag() == kRemoveTag; }

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

// What a mapping laid over a named list does with one of its names.
struct NamedChange {
  std::string name;
  YAML::Node key;      // the name's key node in the over file, for its line
  YAML::Node keys;     // the keys to lay over the entry (or the new entry's keys)
  std::string before;  // a new entry: the base entry it goes before ("" when after)
  std::string after;   // a new entry: the base entry it goes after ("" when before)
  bool remove = false;
};

// The change `value` (a mapping) makes to entry `name`, checked against the base's names.
NamedChange read_change(const YAML::Node& key, const YAML::Node& value, const std::string& name,
                        const std::set<std::string>& names, const std::string& listed,
                        const std::string& path, const std::string& over_file) {
  const std::string at = child_path(path, name);
  if (!value.IsMap()) {
    throw ConfigError(over_file, at, line_of(key),
                      "a change to entry '" + name + "' of the base's list must be a mapping");
  }
  if (name.empty()) {
    throw ConfigError(over_file, path, line_of(key), "an entry's name must not be empty");
  }
  NamedChange change;
  change.name = name;
  change.key = key;
  // the keys to lay over or to make the entry of, less those that say what to do with it; the
  // nodes are over's own, so each keeps its line (YAML::Clone would lose them)
  change.keys = YAML::Node(YAML::NodeType::Map);
  std::set<std::string> fields;
  YAML::Node remove_key;
  for (auto it = value.begin(); it != value.end(); ++it) {
    const std::string field = it->first.IsScalar() ? it->first.Scalar() : "";
    if (!fields.insert(field).second) {
      throw ConfigError(over_file, at, line_of(it->first), "key '" + field + "' appears twice");
    }
    if (field == "name") {
      throw ConfigError(over_file, child_path(at, field), line_of(it->first),
                        "an entry's name is its key here ('" + name +
                            "'); it cannot be given or changed");
    }
    if (field == "insert_before" || field == "insert_after") {
      if (!it->second.IsScalar() || !names.count(it->second.Scalar())) {
        throw ConfigError(over_file, child_path(at, field), line_of(it->first),
                          field + " must name an entry of the base's list (its names: " + listed +
                              ")");
      }
      if (!change.before.empty() || !change.after.empty()) {
        throw ConfigError(over_file, child_path(at, field), line_of(it->first),
                          "a new entry goes before one entry or after one: give insert_before "
                          "or insert_after, not both");
      }
      (field == "insert_before" ? change.before : change.after) = it->second.Scalar();
    } else if (field == "remove") {
      if (plain_bool(it->second) != std::optional<bool>(true)) {
        throw ConfigError(over_file, child_path(at, field), line_of(it->first),
                          "remove must be true (leave it out to keep the entry)");
      }
      change.remove = true;
      remove_key = it->first;
    } else {
      change.keys.force_insert(it->first, it->second);
    }
  }
  const bool is_new = !change.before.empty() || !change.after.empty();
  if (names.count(name) && is_new) {
    throw ConfigError(over_file, at, line_of(key),
                      "the base's list has an entry named '" + name +
                          "' already; insert_before and insert_after add an entry of a new name");
  }
  if (!names.count(name) && !is_new) {
    throw ConfigError(over_file, path, line_of(key),
                      "the base's list has no entry named '" + name + "' to change (its names: " +
                          listed + "); to add one, give it insert_before or insert_after");
  }
  if (change.remove && (is_new || change.keys.size() > 0)) {
    throw ConfigError(over_file, child_path(at, "remove"), line_of(remove_key),
                      "an entry removed takes no other keys");
  }
  return change;
}

// A new entry of the list: its name (the key's node, with its line), then its keys.
YAML::Node new_entry(const NamedChange& change) {
  YAML::Node entry(YAML::NodeType::Map);
  entry.force_insert(YAML::Node("name"), change.key);
  for (auto it = change.keys.begin(); it != change.keys.end(); ++it) {
    entry.force_insert(it->first, it->second);
  }
  return entry;
}

// `patches` (name -> mapping) laid over the entries of `list` that have those names; the other
// entries are kept as they are and in their order. A mapping with `insert_before: NAME` or
// `insert_after: NAME` adds an entry of a new name next to the base's entry NAME (several next to
// one entry keep the over file's order); `remove: true` drops the entry.
YAML::Node patch_by_name(const YAML::Node& list, const KeyOrigins& under_origins,
                         const YAML::Node& patches, const std::string& path,
                         const std::string& over_file, KeyOrigins* origins) {
  std::set<std::string> names;
  std::string listed;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string at = path + "[" + std::to_string(i) + "]";
    if (!names.insert(name_of(list[i])).second) {
      throw ConfigError(under_origins.file_of(at), child_path(at, "name"), line_of(list[i]),
                        "a second entry named '" + name_of(list[i]) +
                            "': a list changed by name needs names that differ");
    }
    listed += (listed.empty() ? "'" : ", '") + name_of(list[i]) + "'";
  }
  std::vector<NamedChange> changes;
  std::set<std::string> seen;
  for (auto it = patches.begin(); it != patches.end(); ++it) {
    const std::string name = it->first.IsScalar() ? it->first.Scalar() : "";
    if (!seen.insert(name).second) {
      throw ConfigError(over_file, path, line_of(it->first), "entry '" + name + "' appears twice");
    }
    changes.push_back(read_change(it->first, it->second, name, names, listed, path, over_file));
  }
  YAML::Node result(YAML::NodeType::Sequence);
  // Entries the over file adds next to base entry `name`: before it or after it.
  const auto insert_next_to = [&](const std::string& name, bool before) {
    for (const NamedChange& change : changes) {
      if ((before ? change.before : change.after) == name) result.push_back(new_entry(change));
    }
  };
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string name = name_of(list[i]);
    insert_next_to(name, true);
    const NamedChange* change = nullptr;
    for (const NamedChange& c : changes) {
      if (c.name == name) change = &c;
    }
    if (change == nullptr || !change->remove) {
      // The base's entry i is entry `at` of the result: its origins move with it.
      const std::string at = path + "[" + std::to_string(result.size()) + "]";
      const KeyOrigins entry_origins =
          under_origins.moved(path + "[" + std::to_string(i) + "]", at);
      if (change == nullptr) {
        result.push_back(list[i]);
        origins->take_subtree(at, entry_origins);
      } else {
        YAML::Node merged(YAML::NodeType::Map);
        lay_over_at(list[i], entry_origins, change->keys, at, over_file, origins, &merged);
        result.push_back(merged);
      }
    }
    insert_next_to(name, false);
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
    if (is_removal(it->second)) {
      const std::string at = child_path(path, it->first.Scalar());
      // yaml-cpp reads a tag alone as an empty scalar
      if (!it->second.IsNull() && !(it->second.IsScalar() && it->second.Scalar().empty())) {
        throw ConfigError(over_file, at, line_of(it->first),
                          std::string(kRemoveTag) + " takes no value (it drops the base's key)");
      }
      if (!find_entry(under, it->first.Scalar()).second.IsDefined()) {
        throw ConfigError(over_file, at, line_of(it->first),
                          "the base has no key '" + it->first.Scalar() + "' here to remove");
      }
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
    if (is_removal(replacement)) continue;
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

// The first value tagged !remove at or below `node` (at `path`) throws: only a key the base
// has can be removed, and lay_over_at has dropped every one of those.
void refuse_removals_at(const YAML::Node& node, const std::string& path, const KeyOrigins& origins) {
  if (is_removal(node)) {
    throw ConfigError(origins.file_of(path), path, line_of(node),
                      std::string(kRemoveTag) +
                          " drops a key of the base configuration (base_config); here there is "
                          "no base's key for it to drop");
  }
  if (node.IsMap()) {
    for (auto it = node.begin(); it != node.end(); ++it) {
      const std::string key = it->first.IsScalar() ? it->first.Scalar() : "";
      refuse_removals_at(it->second, child_path(path, key), origins);
    }
  } else if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) {
      refuse_removals_at(node[i], path + "[" + std::to_string(i) + "]", origins);
    }
  }
}

}  // namespace

void refuse_removals(const YAML::Node& tree, const KeyOrigins& origins) {
  refuse_removals_at(tree, "", origins);
}

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

KeyOrigins KeyOrigins::moved(const std::string& from_path, const std::string& to_path) const {
  KeyOrigins out(top_file_);
  out.files_[to_path] = file_of(from_path);
  for (const auto& [path, file] : files_) {
    if (is_within(path, from_path)) out.files_[to_path + path.substr(from_path.size())] = file;
  }
  return out;
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
