// Layering one run configuration over another: a file that names a `base_config` holds only what
// it changes, and its keys are laid over the base's. Mappings merge key by key at every depth;
// a mapping laid over a list of named mappings (a curriculum's lessons) changes the entries it
// names (lesson name -> the lesson's keys to lay over), keeping the list's order and the rest,
// and adds (`insert_before: NAME` or `insert_after: NAME`) or drops (`remove: true`) entries;
// a key whose value is the tag `!remove` alone drops the base's key; anything else (a scalar, a
// list, null) replaces the base's value whole. Our extension: ML-Agents has no base files.
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>

namespace rlt {

// Which file each part of a layered tree came from, for messages: key path -> file for the
// subtrees not taken from the top file. A path that is not listed takes the file of its nearest
// listed ancestor, and the top file when none is listed.
class KeyOrigins {
 public:
  explicit KeyOrigins(std::string top_file) : top_file_(std::move(top_file)) {}

  // The file the value at `key_path` came from; key paths read as the parser writes them,
  // "behaviors.Hider.hyperparameters" or "environment_parameters.level.curriculum[3].name".
  const std::string& file_of(const std::string& key_path) const;
  const std::string& top_file() const { return top_file_; }

  // The subtree at `key_path` is `from`'s subtree there, with the files `from` gives its parts.
  void take_subtree(const std::string& key_path, const KeyOrigins& from);

  // The origins of the subtree at `from_path` alone, moved to `to_path` (a list entry that
  // changed its index): what take_subtree(to_path, ...) needs, and nothing outside it.
  KeyOrigins moved(const std::string& from_path, const std::string& to_path) const;

 private:
  std::string top_file_;
  std::map<std::string, std::string> files_;
};

// `over` laid on `under`, both whole configurations (mappings), as a new tree. Neither input
// changes and the result's nodes are theirs, so every value keeps its line. `under_origins`
// tells where under's parts came from; the returned origins have over's file (`over_file`) on top.
// A key given twice in a mapping of `over` that meets a mapping of `under` throws ConfigError
// naming over_file (elsewhere the parser finds it as in any file).
YAML::Node lay_over(const YAML::Node& under, const KeyOrigins& under_origins,
                    const YAML::Node& over, const std::string& over_file, KeyOrigins* origins);

// The tag of a value that drops its key from the base: `key: !remove`.
inline constexpr const char* kRemoveTag = "!remove";

// Throws ConfigError naming the file, key and line of the first value in `tree` still tagged
// !remove: one in a file without a base, under a key the base does not have as a mapping, in a
// list, or in a lesson the file adds. lay_over has dropped every key it could.
void refuse_removals(const YAML::Node& tree, const KeyOrigins& origins);

}  // namespace rlt
