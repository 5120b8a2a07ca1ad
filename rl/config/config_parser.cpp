// Reading and writing run configurations: a walk over the yaml-cpp node tree that checks every key
// against a table of the keys its section accepts, converts values with our own strict scalar
// rules, and reports the first problem with the file, key path and line.
#include "rl/config/config_parser.h"

#include "rl/config/config_layers.h"
#include "rl/config/yaml_scalars.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

namespace rlt {

namespace {

std::string format_message(const std::string& file, const std::string& key_path, int line,
                           const std::string& problem) {
  std::string text = file;
  if (line > 0) text += ":" + std::to_string(line);
  text += ": ";
  if (!key_path.empty()) text += key_path + ": ";
  return text + problem;
}

}  // namespace

ConfigError::ConfigError(std::string file, std::string key_path, int line, std::string problem)
    : std::runtime_error(format_message(file, key_path, line, problem)),
      file_(std::move(file)),
      key_path_(std::move(key_path)),
      line_(line),
      problem_(std::move(problem)) {}

const char* schedule_name(Schedule schedule) {
  return schedule == Schedule::kLinear ? "linear" : "constant";
}

const char* activation_name(Activation activation) {
  switch (activation) {
    case Activation::kSwish:
      return "swish";
    case Activation::kTanh:
      return "tanh";
    case Activation::kRelu:
      return "relu";
  }
  return "swish";
}

namespace {

constexpr int64_t kIntMax = std::numeric_limits<int>::max();
constexpr int64_t kInt64Max = std::numeric_limits<int64_t>::max();

// ---------------------------------------------------------------------------------------------
// Text helpers.

std::string to_lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// Levenshtein distance (insertions, deletions and substitutions all cost 1).
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];  // row[i-1][j-1]
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];  // row[i-1][j]
      row[j] = std::min({above + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The candidate that `word` is most likely a misspelling of, or "" when none is close.
std::string closest_name(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::numeric_limits<size_t>::max();
  const std::string lowered = to_lower(word);
  for (const std::string& candidate : candidates) {
    const size_t distance = edit_distance(lowered, to_lower(candidate));
    // Short names tolerate one edit, longer ones two or three.
    const size_t limit = candidate.size() <= 3 ? 1 : candidate.size() <= 6 ? 2 : 3;
    if (distance <= limit && distance < best_distance) {
      best = candidate;
      best_distance = distance;
    }
  }
  return best;
}

// " (did you mean 'x'?)" or "".
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string best = closest_name(word, candidates);
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

std::string join_names(const std::vector<std::string>& names) {
  std::string text;
  for (size_t i = 0; i < names.size(); ++i) text += (i == 0 ? "" : ", ") + names[i];
  return text;
}

std::string join_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

// Parses a whole decimal integer such as "42", "-1" or "+7".
bool parse_int_text(const std::string& text, int64_t* value) {
  const char* begin = text.data();
  const char* end = begin + text.size();
  if (begin != end && *begin == '+') ++begin;
  if (begin == end) return false;
  const auto [stop, error] = std::from_chars(begin, end, *value);
  return error == std::errc() && stop == end;
}

// Parses a whole finite decimal number such as "3.0e-4", "3e-4", "0.95", ".5" or "-1".
template <typename T>
bool parse_number_text(const std::string& text, T* value) {
  const char* begin = text.data();
  const char* end = begin + text.size();
  if (begin != end && *begin == '+') ++begin;
  if (begin == end) return false;
  const auto [stop, error] = std::from_chars(begin, end, *value, std::chars_format::general);
  return error == std::errc() && stop == end && std::isfinite(*value);
}

// Shortest text that reads back to exactly `value`, always with a '.' or exponent so that it
// reads as a number with a fractional part: "1.0", "0.0003", "1e-07", "1e+30". Plain decimals
// for the usual magnitudes of settings, exponents for the rest.
std::string format_float(double value, bool single_precision) {
  const double magnitude = std::fabs(value);
  const std::chars_format format = magnitude == 0 || (magnitude >= 1e-5 && magnitude < 1e9)
                                       ? std::chars_format::fixed
                                       : std::chars_format::scientific;
  char buffer[128];
  const auto result =
      single_precision
          ? std::to_chars(buffer, buffer + sizeof(buffer), static_cast<float>(value), format)
          : std::to_chars(buffer, buffer + sizeof(buffer), value, format);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

// ---------------------------------------------------------------------------------------------
// YAML node helpers.

// 1-based line of a node, 0 when yaml-cpp has no position for it.
int line_of(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

// How a value reads in a message: 'abc', the string "64", a list, a mapping, null.
std::string describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "null";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  if (is_quoted(node)) return "the string \"" + node.Scalar() + "\"";
  return "'" + node.Scalar() + "'";
}

// A value together with where it is: its dotted key path and its line (the line of its key).
struct Val {
  Val() = default;
  Val(YAML::Node value, std::string key_path, int key_line)
      : node(std::move(value)), path(std::move(key_path)), line(key_line) {}
  Val(const Val&) = default;
  // Rebinds `node`: yaml-cpp's Node::operator= would instead make the node this Val held share
  // the other's value, changing the tree being read (a base_config's tree is read twice).
  Val& operator=(const Val& other) {
    node.reset(other.node);
    path = other.path;
    line = other.line;
    return *this;
  }

  YAML::Node node;
  std::string path;
  int line = 0;
};

// A key a section accepts and what to do with its value.
struct KeyHandler {
  std::string name;
  std::function<void(const Val&)> handle;
};

// The settings of one behavior while default_settings and the behavior's own keys are layered.
struct BehaviorDraft {
  BehaviorConfig config;           // beta/epsilon schedules stay empty unless given explicitly
  bool even_checkpoints = false;   // checkpoint_interval = max_steps / keep_checkpoints when set
  bool team_change_given = false;  // self_play.team_change set by a layer (else 5 * save_steps)
};

// Inclusive bounds of an integer setting.
struct IntRange {
  int64_t min;
  int64_t max;
};

// Bounds of a real-valued setting; a missing bound is unbounded.
struct RealRange {
  std::optional<double> low;
  bool low_open = false;  // true: value > low; false: value >= low
  std::optional<double> high;
  bool high_open = false;  // true: value < high; false: value <= high
};

constexpr IntRange kPositiveInt{1, kIntMax};
constexpr IntRange kPositiveInt64{1, kInt64Max};
const RealRange kAnyReal{};
const RealRange kPositiveReal{0.0, true, std::nullopt, false};
const RealRange kNonNegativeReal{0.0, false, std::nullopt, false};

std::string int_expectation(const IntRange& range) {
  if (range.min == 1) return "a positive integer";
  if (range.min == 0) return "a non-negative integer";
  return "an integer >= " + std::to_string(range.min);
}

std::string real_expectation(const RealRange& range) {
  // Bounds are round numbers such as 0 and 1: written without a fractional part.
  auto bound = [](double value) {
    std::string text = format_float(value, false);
    if (text.size() > 2 && text.compare(text.size() - 2, 2, ".0") == 0) {
      text.resize(text.size() - 2);
    }
    return text;
  };
  if (range.low && range.high) {
    return std::string("a number in ") + (range.low_open ? "(" : "[") + bound(*range.low) + ", " +
           bound(*range.high) + (range.high_open ? ")" : "]");
  }
  if (range.low) {
    return std::string("a number ") + (range.low_open ? "> " : ">= ") + bound(*range.low);
  }
  if (range.high) {
    return std::string("a number ") + (range.high_open ? "< " : "<= ") + bound(*range.high);
  }
  return "a finite number";
}

bool in_range(double value, const RealRange& range) {
  if (range.low && (range.low_open ? !(value > *range.low) : !(value >= *range.low))) return false;
  if (range.high && (range.high_open ? !(value < *range.high) : !(value <= *range.high))) {
    return false;
  }
  return true;
}

// Words YAML readers take for null or booleans; strings spelled like them are written quoted.
bool is_reserved_word(const std::string& text) {
  static const std::set<std::string> kWords = {
      "",      "~",   "null", "Null", "NULL", "true", "True", "TRUE", "false", "False",
      "FALSE", "yes", "Yes",  "YES",  "no",   "No",   "NO",   "on",   "On",    "ON",
      "off",   "Off", "OFF",  "y",    "Y",    "n",    "N",    ".inf", ".nan",  "-.inf"};
  return kWords.count(text) > 0;
}

// Writes a string so that YAML reads it back as the same string (quoted when it would otherwise
// read as null, a boolean or a number).
void emit_string(YAML::Emitter& out, const std::string& text) {
  double number;
  int64_t integer;
  if (is_reserved_word(text) || parse_number_text(text, &number) ||
      parse_int_text(text, &integer)) {
    out << YAML::DoubleQuoted << text;
  } else {
    out << text;
  }
}

// ---------------------------------------------------------------------------------------------
// The parser: one per file, for the file name in messages. A file laid over a base_config is
// parsed as one tree, and a problem in a part that came from a base names the base's file.

class Parser {
 public:
  explicit Parser(KeyOrigins origins)
      : origins_(std::move(origins)), file_(origins_.top_file()) {}

  RunConfig parse(const YAML::Node& root);

 private:
  [[noreturn]] void fail(const std::string& path, int line, const std::string& problem) const {
    throw ConfigError(origins_.file_of(path), path, line, problem);
  }
  [[noreturn]] void fail(const Val& value, const std::string& problem) const {
    fail(value.path, value.line, problem);
  }
  [[noreturn]] void fail_expected(const Val& value, const std::string& expectation) const {
    fail(value, "expected " + expectation + ", got " + describe(value.node));
  }

  // Structure.
  void for_each_entry(const Val& map,
                      const std::function<void(const std::string&, const Val&)>& visit) const;
  void dispatch(const Val& map, const std::vector<KeyHandler>& keys) const;
  std::optional<Val> find_entry(const Val& map, const std::string& key) const;

  // Scalars.
  int64_t read_int(const Val& value, const IntRange& range) const;
  int read_int32(const Val& value, const IntRange& range) const {
    return static_cast<int>(read_int(value, range));
  }
  double read_real(const Val& value, const RealRange& range) const;
  float read_float(const Val& value, const RealRange& range) const;
  bool read_bool(const Val& value) const;
  std::string read_string(const Val& value, bool null_is_empty) const;
  template <typename T>
  T read_choice(const Val& value, const std::vector<std::pair<std::string, T>>& choices) const;
  Schedule read_schedule(const Val& value) const;

  // Sections.
  void parse_behavior(const Val& value, BehaviorDraft* draft, Val* size_location) const;
  void parse_hyperparameters(const Val& value, Hyperparameters* hyper, Val* size_location) const;
  void parse_network_settings(const Val& value, NetworkSettings* network) const;
  void parse_reward_signals(const Val& value, RewardSignal* extrinsic) const;
  void parse_self_play(const Val& value, BehaviorDraft* draft) const;
  BehaviorConfig finish_behavior(const BehaviorDraft& draft, const Val& size_location) const;
  void parse_env_settings(const std::optional<Val>& value, EnvSettings* env) const;
  void parse_checkpoint_settings(const Val& value, CheckpointSettings* checkpoint) const;
  void parse_environment_parameters(
      const Val& value, const RunConfig& config,
      std::map<std::string, EnvironmentParameterSettings>* parameters) const;
  SamplerSettings parse_sampler(const Val& value) const;
  std::vector<Lesson> parse_curriculum(const Val& value, const std::string& parameter,
                                       const RunConfig& config) const;
  Staircase parse_staircase(const Val& value) const;
  // the staircase of `lesson` of the curriculum of `parameter` moves a constant of the lesson, and
  // the lesson's criteria judge its episodes
  void check_staircase(const Val& at, const Lesson& lesson, const std::string& parameter) const;
  CompletionCriteria parse_completion_criteria(const Val& value, const RunConfig& config) const;
  // Fails at `at` when `behavior` is not one the run trains. Without default_settings only the
  // listed behaviors are trained; with it, the environment may have behaviors the file does not
  // list.
  void check_behavior_configured(const Val& at, const std::string& behavior,
                                 const RunConfig& config) const;
  void parse_torch_settings(const Val& value) const;
  void parse_engine_settings(const Val& value) const;

  KeyOrigins origins_;
  std::string file_;
};

void Parser::for_each_entry(
    const Val& map, const std::function<void(const std::string&, const Val&)>& visit) const {
  if (map.node.IsNull()) return;  // a section with nothing after it: nothing given
  if (!map.node.IsMap()) fail_expected(map, "a mapping");
  std::set<std::string> seen;
  for (auto it = map.node.begin(); it != map.node.end(); ++it) {
    const YAML::Node key = it->first;
    const int key_line = line_of(key);
    if (!key.IsScalar()) {
      fail(map.path, key_line, "keys must be names, got " + describe(key) + " as a key");
    }
    const std::string name = key.Scalar();
    if (!seen.insert(name).second) fail(map.path, key_line, "key '" + name + "' appears twice");
    visit(name, Val{it->second, join_path(map.path, name), key_line});
  }
}

void Parser::dispatch(const Val& map, const std::vector<KeyHandler>& keys) const {
  for_each_entry(map, [&](const std::string& name, const Val& value) {
    for (const KeyHandler& key : keys) {
      if (key.name == name) {
        key.handle(value);
        return;
      }
    }
    std::vector<std::string> names;
    for (const KeyHandler& key : keys) names.push_back(key.name);
    const std::string suggestion = did_you_mean(name, names);
    // the file is the key's own (a merged mapping's keys may come from several files)
    const std::string& file = origins_.file_of(value.path);
    if (name == "<<") {
      throw ConfigError(file, map.path, value.line, "YAML merge keys ('<<') are not supported");
    }
    throw ConfigError(
        file, map.path, value.line,
        "unknown key '" + name + "'" +
            (suggestion.empty() ? " (expected one of: " + join_names(names) + ")" : suggestion));
  });
}

std::optional<Val> Parser::find_entry(const Val& map, const std::string& key) const {
  if (!map.node.IsMap()) return std::nullopt;
  for (auto it = map.node.begin(); it != map.node.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == key) {
      return Val{it->second, join_path(map.path, key), line_of(it->first)};
    }
  }
  return std::nullopt;
}

int64_t Parser::read_int(const Val& value, const IntRange& range) const {
  const std::string expectation = int_expectation(range);
  if (!value.node.IsScalar() || is_quoted(value.node)) fail_expected(value, expectation);
  const std::string& text = value.node.Scalar();
  int64_t integer = 0;
  if (!parse_int_text(text, &integer)) {
    // ML-Agents accepts step counts written as floats (max_steps: 5.0e5); so do we, when the
    // value is a whole number.
    double real = 0;
    if (!parse_number_text(text, &real) || real != std::floor(real)) {
      fail_expected(value, expectation);
    }
    if (real < -9.0e18) fail_expected(value, expectation);
    if (real > 9.0e18) {
      fail_expected(value, expectation + " no larger than " + std::to_string(range.max));
    }
    integer = static_cast<int64_t>(real);
  }
  if (integer < range.min) fail_expected(value, expectation);
  if (integer > range.max) {
    fail_expected(value, expectation + " no larger than " + std::to_string(range.max));
  }
  return integer;
}

double Parser::read_real(const Val& value, const RealRange& range) const {
  const std::string expectation = real_expectation(range);
  double real = 0;
  if (!value.node.IsScalar() || is_quoted(value.node) ||
      !parse_number_text(value.node.Scalar(), &real) || !in_range(real, range)) {
    fail_expected(value, expectation);
  }
  return real;
}

float Parser::read_float(const Val& value, const RealRange& range) const {
  read_real(value, range);  // type and range
  // Read the text again as a float so that written values read back bit for bit.
  float single = 0;
  if (!parse_number_text(value.node.Scalar(), &single)) {
    fail(value, "'" + value.node.Scalar() + "' is out of the range of a 32-bit float");
  }
  if (!in_range(single, range)) fail_expected(value, real_expectation(range));
  return single;
}

bool Parser::read_bool(const Val& value) const {
  if (const std::optional<bool> b = plain_bool(value.node)) return *b;
  fail_expected(value, "true or false");
}

std::string Parser::read_string(const Val& value, bool null_is_empty) const {
  if (value.node.IsNull() && null_is_empty) return "";
  if (!value.node.IsScalar()) fail_expected(value, "a string");
  return value.node.Scalar();
}

template <typename T>
T Parser::read_choice(const Val& value,
                      const std::vector<std::pair<std::string, T>>& choices) const {
  std::vector<std::string> names;
  for (const auto& [name, choice] : choices) {
    if (value.node.IsScalar() && value.node.Scalar() == name) return choice;
    names.push_back(name);
  }
  const std::string suggestion =
      value.node.IsScalar() ? did_you_mean(value.node.Scalar(), names) : "";
  fail(value,
       "expected one of " + join_names(names) + ", got " + describe(value.node) + suggestion);
}

Schedule Parser::read_schedule(const Val& value) const {
  return read_choice<Schedule>(value,
                               {{"linear", Schedule::kLinear}, {"constant", Schedule::kConstant}});
}

// ---------------------------------------------------------------------------------------------
// Behaviors.

void Parser::parse_behavior(const Val& value, BehaviorDraft* draft, Val* size_location) const {
  BehaviorConfig& config = draft->config;
  if (!value.node.IsNull() && !value.node.IsMap()) fail_expected(value, "a mapping");
  // trainer_type first, so that a trainer we do not have is reported before its settings.
  if (const std::optional<Val> trainer = find_entry(value, "trainer_type")) {
    const std::string type = trainer->node.IsScalar() ? trainer->node.Scalar() : "";
    if (type == "sac" || type == "coma") {
      fail(*trainer, "trainer_type '" + type + "' is not supported (supported: ppo, poca)");
    }
    config.trainer_type = read_choice<std::string>(*trainer, {{"ppo", "ppo"}, {"poca", "poca"}});
  }
  dispatch(
      value,
      {
          {"trainer_type", [](const Val&) {}},  // read above
          {"hyperparameters",
           [&](const Val& v) { parse_hyperparameters(v, &config.hyperparameters, size_location); }},
          {"network_settings",
           [&](const Val& v) { parse_network_settings(v, &config.network_settings); }},
          {"reward_signals", [&](const Val& v) { parse_reward_signals(v, &config.extrinsic); }},
          {"init_path", [&](const Val& v) { config.init_path = read_string(v, true); }},
          {"keep_checkpoints",
           [&](const Val& v) { config.keep_checkpoints = read_int32(v, kPositiveInt); }},
          {"even_checkpoints", [&](const Val& v) { draft->even_checkpoints = read_bool(v); }},
          {"checkpoint_interval",
           [&](const Val& v) { config.checkpoint_interval = read_int(v, kPositiveInt64); }},
          {"max_steps", [&](const Val& v) { config.max_steps = read_int(v, kPositiveInt64); }},
          {"time_horizon",
           [&](const Val& v) { config.time_horizon = read_int32(v, kPositiveInt); }},
          {"summary_freq",
           [&](const Val& v) { config.summary_freq = read_int(v, kPositiveInt64); }},
          {"threaded", [&](const Val& v) { config.threaded = read_bool(v); }},
          {"self_play", [&](const Val& v) { parse_self_play(v, draft); }},
          {"behavioral_cloning",
           [&](const Val& v) {
             if (!v.node.IsNull()) fail(v, "behavioral_cloning is not supported");
           }},
      });
}

void Parser::parse_hyperparameters(const Val& value, Hyperparameters* hyper,
                                   Val* size_location) const {
  dispatch(
      value,
      {
          {"batch_size",
           [&](const Val& v) {
             hyper->batch_size = read_int32(v, kPositiveInt);
             if (size_location->path.empty()) *size_location = v;
           }},
          {"buffer_size",
           [&](const Val& v) {
             hyper->buffer_size = read_int32(v, kPositiveInt);
             *size_location = v;  // preferred over batch_size
           }},
          {"learning_rate",
           [&](const Val& v) { hyper->learning_rate = read_float(v, kPositiveReal); }},
          {"learning_rate_schedule",
           [&](const Val& v) { hyper->learning_rate_schedule = read_schedule(v); }},
          {"beta", [&](const Val& v) { hyper->beta = read_float(v, kNonNegativeReal); }},
          {"beta_schedule", [&](const Val& v) { hyper->beta_schedule = read_schedule(v); }},
          {"discrete_beta",
           [&](const Val& v) { hyper->discrete_beta = read_float(v, kNonNegativeReal); }},
          {"discrete_beta_end",
           [&](const Val& v) { hyper->discrete_beta_end = read_float(v, kNonNegativeReal); }},
          {"discrete_beta_steps",
           [&](const Val& v) { hyper->discrete_beta_steps = read_int(v, kPositiveInt64); }},
          {"epsilon",
           [&](const Val& v) {
             hyper->epsilon = read_float(v, RealRange{0.0, true, 1.0, true});
           }},
          {"epsilon_schedule", [&](const Val& v) { hyper->epsilon_schedule = read_schedule(v); }},
          {"lambd",
           [&](const Val& v) {
             hyper->lambd = read_float(v, RealRange{0.0, false, 1.0, false});
           }},
          {"num_epoch", [&](const Val& v) { hyper->num_epoch = read_int32(v, kPositiveInt); }},
          {"shared_critic", [&](const Val& v) { hyper->shared_critic = read_bool(v); }},
          {"max_grad_norm",
           [&](const Val& v) { hyper->max_grad_norm = read_float(v, kNonNegativeReal); }},
          {"value_loss_coef",
           [&](const Val& v) { hyper->value_loss_coef = read_float(v, kNonNegativeReal); }},
      });
}

void Parser::parse_network_settings(const Val& value, NetworkSettings* network) const {
  dispatch(
      value,
      {
          {"normalize", [&](const Val& v) { network->normalize = read_bool(v); }},
          {"normalize_grids", [&](const Val& v) { network->normalize_grids = read_bool(v); }},
          {"hidden_units",
           [&](const Val& v) { network->hidden_units = read_int32(v, kPositiveInt); }},
          {"num_layers", [&](const Val& v) { network->num_layers = read_int32(v, kPositiveInt); }},
          {"vis_encode_type",
           [&](const Val& v) {
             network->vis_encode_type =
                 read_choice<std::string>(v, {{"simple", "simple"},
                                              {"nature_cnn", "nature_cnn"},
                                              {"resnet", "resnet"},
                                              {"match3", "match3"},
                                              {"fully_connected", "fully_connected"}});
           }},
          {"memory",
           [&](const Val& v) {
             if (!v.node.IsNull()) fail(v, "memory (LSTM) is not supported");
           }},
          {"goal_conditioning_type",
           [&](const Val& v) {
             read_choice<int>(v, {{"hyper", 0}, {"none", 1}});  // checked, not used
           }},
          {"deterministic", [&](const Val& v) { network->deterministic = read_bool(v); }},
          {"activation",
           [&](const Val& v) {
             network->activation = read_choice<Activation>(v, {{"swish", Activation::kSwish},
                                                               {"tanh", Activation::kTanh},
                                                               {"relu", Activation::kRelu}});
           }},
      });
}

void Parser::parse_reward_signals(const Val& value, RewardSignal* extrinsic) const {
  auto unsupported = [&](const Val& v) {
    const std::string name = v.path.substr(v.path.rfind('.') + 1);
    fail(v, "the " + name + " reward signal is not supported (only extrinsic)");
  };
  dispatch(value,
           {
               {"extrinsic",
                [&](const Val& v) {
                  dispatch(
                      v, {
                             {"gamma",
                              [&](const Val& g) {
                                extrinsic->gamma = read_float(g, RealRange{0.0, true, 1.0, false});
                              }},
                             {"strength",
                              [&](const Val& s) { extrinsic->strength = read_float(s, kAnyReal); }},
                             {"network_settings",
                              [&](const Val& n) {
                                // ML-Agents sizes reward-signal networks with it; the
                                // extrinsic signal has no network, so only the shape is
                                // checked.
                                if (!n.node.IsNull() && !n.node.IsMap()) {
                                  fail_expected(n, "a mapping");
                                }
                              }},
                         });
                }},
               {"curiosity", unsupported},
               {"gail", unsupported},
               {"rnd", unsupported},
           });
}

void Parser::parse_self_play(const Val& value, BehaviorDraft* draft) const {
  std::optional<SelfPlaySettings>& self_play = draft->config.self_play;
  if (value.node.IsNull()) {
    // ML-Agents writes `self_play: null` for "no self-play"; it also switches off a self_play of
    // default_settings, as in ML-Agents' merge.
    self_play.reset();
    draft->team_change_given = false;
    return;
  }
  if (!value.node.IsMap()) fail_expected(value, "a mapping");
  if (!self_play) {
    self_play.emplace();
    draft->team_change_given = false;
  }
  SelfPlaySettings& settings = *self_play;
  dispatch(
      value,
      {
          {"save_steps", [&](const Val& v) { settings.save_steps = read_int(v, kPositiveInt64); }},
          {"team_change",
           [&](const Val& v) {
             settings.team_change = read_int(v, kPositiveInt64);
             draft->team_change_given = true;
           }},
          {"swap_steps", [&](const Val& v) { settings.swap_steps = read_int(v, kPositiveInt64); }},
          {"window", [&](const Val& v) { settings.window = read_int32(v, kPositiveInt); }},
          {"play_against_latest_model_ratio",
           [&](const Val& v) {
             settings.play_against_latest_model_ratio =
                 read_float(v, RealRange{0.0, false, 1.0, false});
           }},
          {"initial_elo", [&](const Val& v) { settings.initial_elo = read_real(v, kAnyReal); }},
          {"turn_parameters",
           [&](const Val& v) {
             settings.turn_parameters.clear();
             for_each_entry(v, [&](const std::string& name, const Val& p) {
               settings.turn_parameters[name] = read_float(p, kAnyReal);
             });
           }},
      });
}

BehaviorConfig Parser::finish_behavior(const BehaviorDraft& draft, const Val& size_location) const {
  BehaviorConfig config = draft.config;
  Hyperparameters& hyper = config.hyperparameters;
  if (hyper.buffer_size < hyper.batch_size) {
    fail(size_location, "buffer_size (" + std::to_string(hyper.buffer_size) +
                            ") must be at least batch_size (" + std::to_string(hyper.batch_size) +
                            ")");
  }
  if (!hyper.beta_schedule) hyper.beta_schedule = hyper.learning_rate_schedule;
  if (!hyper.discrete_beta) hyper.discrete_beta = hyper.beta;
  if (hyper.discrete_beta_end.has_value() != (hyper.discrete_beta_steps > 0))
    fail(size_location, std::string("hyperparameters: discrete_beta_end and discrete_beta_steps ") +
                            "go together (the bonus moves to the one over the other); only " +
                            (hyper.discrete_beta_end ? "discrete_beta_end" : "discrete_beta_steps") +
                            " is given");
  if (!hyper.epsilon_schedule) hyper.epsilon_schedule = hyper.learning_rate_schedule;
  if (draft.even_checkpoints) {
    config.checkpoint_interval = std::max<int64_t>(1, config.max_steps / config.keep_checkpoints);
  }
  if (config.self_play && !draft.team_change_given) {  // ML-Agents: 5 * save_steps
    const int64_t save_steps = config.self_play->save_steps;
    config.self_play->team_change = save_steps > kInt64Max / 5 ? kInt64Max : 5 * save_steps;
  }
  return config;
}

// ---------------------------------------------------------------------------------------------
// Run-level sections.

void Parser::parse_env_settings(const std::optional<Val>& value, EnvSettings* env) const {
  const std::string env_id_hint =
      "name a registered environment with env_settings.env_id (`rlt envs` lists them)";
  bool has_env_id = false;
  if (value) {
    auto ignored = [](const Val&) {};
    dispatch(*value,
             {
                 {"env_id",
                  [&](const Val& v) {
                    env->env_id = read_string(v, false);
                    if (env->env_id.empty()) fail(v, "must not be empty: " + env_id_hint);
                    has_env_id = true;
                  }},
                 {"num_envs", [&](const Val& v) { env->num_envs = read_int32(v, kPositiveInt); }},
                 {"seed",
                  [&](const Val& v) {
                    env->seed = read_int(v, IntRange{-1, kInt64Max});
                  }},
                 {"num_threads",
                  [&](const Val& v) {
                    env->num_threads = read_int32(v, IntRange{0, kIntMax});
                  }},
                 {"stagger_steps",
                  [&](const Val& v) {
                    env->stagger_steps = read_int32(v, IntRange{0, kIntMax});
                  }},
                 {"params",
                  [&](const Val& v) {
                    for_each_entry(v, [&](const std::string& name, const Val& p) {
                      env->params[name] = read_float(p, kAnyReal);
                    });
                  }},
                 {"env_path",
                  [&](const Val& v) {
                    if (!v.node.IsNull()) {
                      fail(v,
                           "ML-Agents' env_path (a Unity build) is not supported: " + env_id_hint);
                    }
                  }},
                 // ML-Agents' Unity process settings: nothing to launch here.
                 {"env_args", ignored},
                 {"base_port", ignored},
                 {"num_areas", ignored},
                 {"timeout_wait", ignored},
                 {"max_lifetime_restarts", ignored},
                 {"restarts_rate_limit_n", ignored},
                 {"restarts_rate_limit_period_s", ignored},
             });
  }
  if (!has_env_id) {
    fail(value ? join_path(value->path, "env_id") : "env_settings.env_id", value ? value->line : 0,
         "missing: " + env_id_hint);
  }
}

void Parser::parse_checkpoint_settings(const Val& value, CheckpointSettings* checkpoint) const {
  auto folder_name = [this](const Val& v) {
    const std::string name = read_string(v, false);
    if (name.empty()) fail(v, "must not be empty");
    return name;
  };
  dispatch(value,
           {
               {"run_id",
                [&](const Val& v) {
                  checkpoint->run_id = folder_name(v);
                  if (checkpoint->run_id.find_first_of("/\\") != std::string::npos ||
                      checkpoint->run_id == "." || checkpoint->run_id == "..") {
                    fail(v, "expected a folder name without '/', got '" + checkpoint->run_id + "'");
                  }
                }},
               {"initialize_from",
                [&](const Val& v) { checkpoint->initialize_from = read_string(v, true); }},
               {"resume", [&](const Val& v) { checkpoint->resume = read_bool(v); }},
               {"force", [&](const Val& v) { checkpoint->force = read_bool(v); }},
               {"results_dir", [&](const Val& v) { checkpoint->results_dir = folder_name(v); }},
               {"load_model",
                [&](const Val& v) {
                  if (read_bool(v)) fail(v, "load_model is deprecated; use resume: true");
                }},
               {"train_model", [&](const Val& v) { read_bool(v); }},  // training is the default
               {"inference",
                [&](const Val& v) {
                  if (read_bool(v)) {
                    fail(v, "inference runs are not configured here; use `rlt eval`");
                  }
                }},
           });
}

void Parser::parse_environment_parameters(
    const Val& value, const RunConfig& config,
    std::map<std::string, EnvironmentParameterSettings>* parameters) const {
  std::map<std::string, int> lines;  // of each entry, for the errors below
  for_each_entry(value, [&](const std::string& name, const Val& v) {
    lines[name] = v.line;
    EnvironmentParameterSettings& parameter = (*parameters)[name];
    if (v.node.IsScalar()) {
      parameter.sampler = SamplerSettings::constant(read_float(v, kAnyReal));
      return;
    }
    if (!v.node.IsMap()) {
      fail_expected(v,
                    "a number, a sampler (sampler_type, sampler_parameters) or a curriculum "
                    "(a list of lessons)");
    }
    // The keys of both forms first, so that a misspelled key gets a suggestion.
    auto none = [](const Val&) {};
    dispatch(v, {{"curriculum", none}, {"sampler_type", none}, {"sampler_parameters", none}});
    if (const std::optional<Val> curriculum = find_entry(v, "curriculum")) {
      for (const char* key : {"sampler_type", "sampler_parameters"}) {
        if (const std::optional<Val> entry = find_entry(v, key)) {
          fail(*entry,
               std::string(key) + " does not go with curriculum: give each lesson its own value");
        }
      }
      parameter.curriculum = parse_curriculum(*curriculum, name, config);
    } else {
      parameter.sampler = parse_sampler(v);
    }
  });
  // a parameter that some curriculum's lessons set is set there only
  std::map<std::string, std::string> set_by;  // parameter -> the curriculum setting it
  for (const auto& [name, parameter] : *parameters) {
    for (const auto& [other, sampler] : parameter.other_parameters()) {
      std::string clash;
      if (parameters->count(other)) clash = "it has its own entry";
      if (other == name) clash = "it is the curriculum's own parameter (give it as the value)";
      if (set_by.count(other)) clash = "the lessons of " + set_by[other] + " set it too";
      if (!clash.empty()) {
        fail(join_path(value.path, name), lines[name],
             "the lessons of " + name + " set " + other + " (other_parameters), but " + clash);
      }
      set_by[other] = name;
    }
  }
}

SamplerSettings Parser::parse_sampler(const Val& value) const {
  if (value.node.IsScalar()) return SamplerSettings::constant(read_float(value, kAnyReal));
  if (!value.node.IsMap()) {
    fail_expected(value, "a number or a sampler (sampler_type, sampler_parameters)");
  }
  const std::string types = "uniform, gaussian, multirangeuniform or constant";
  std::optional<Val> type_entry, parameters_entry;
  dispatch(value, {{"sampler_type", [&](const Val& v) { type_entry = v; }},
                   {"sampler_parameters", [&](const Val& v) { parameters_entry = v; }}});
  if (!type_entry) {
    fail(join_path(value.path, "sampler_type"), value.line, "missing: the sampler (" + types + ")");
  }
  SamplerSettings sampler;
  sampler.type =
      read_choice<SamplerType>(*type_entry, {{"uniform", SamplerType::kUniform},
                                             {"gaussian", SamplerType::kGaussian},
                                             {"multirangeuniform", SamplerType::kMultiRangeUniform},
                                             {"constant", SamplerType::kConstant}});
  if (!parameters_entry) {
    fail(join_path(value.path, "sampler_parameters"), value.line,
         "missing: the settings of the " + type_entry->node.Scalar() + " sampler");
  }
  const Val& parameters = *parameters_entry;
  if (!parameters.node.IsMap()) fail_expected(parameters, "a mapping");
  // ML-Agents' per-sampler seed: accepted and not used (draws come from the run's seeded engine).
  const KeyHandler seed{"seed", [&](const Val& v) { read_int(v, IntRange{-1, kInt64Max}); }};
  switch (sampler.type) {
    case SamplerType::kConstant:
      dispatch(parameters,
               {{"value", [&](const Val& v) { sampler.value = read_float(v, kAnyReal); }}, seed});
      break;
    case SamplerType::kUniform:
      dispatch(parameters,
               {{"min_value", [&](const Val& v) { sampler.min_value = read_float(v, kAnyReal); }},
                {"max_value", [&](const Val& v) { sampler.max_value = read_float(v, kAnyReal); }},
                seed});
      if (sampler.min_value > sampler.max_value) {
        fail(parameters, "min_value (" + format_float(sampler.min_value, true) +
                             ") must not be greater than max_value (" +
                             format_float(sampler.max_value, true) + ")");
      }
      break;
    case SamplerType::kGaussian:
      dispatch(parameters,
               {{"mean", [&](const Val& v) { sampler.mean = read_float(v, kAnyReal); }},
                {"st_dev", [&](const Val& v) { sampler.st_dev = read_float(v, kNonNegativeReal); }},
                seed});
      break;
    case SamplerType::kMultiRangeUniform:
      dispatch(
          parameters,
          {{"intervals",
            [&](const Val& v) {
              const std::string expectation = "a non-empty list of intervals [min, max]";
              if (!v.node.IsSequence() || v.node.size() == 0) {
                fail_expected(v, expectation);
              }
              sampler.intervals.clear();
              for (size_t i = 0; i < v.node.size(); ++i) {
                const YAML::Node item = v.node[i];
                const Val interval{item, v.path + "[" + std::to_string(i) + "]",
                                   line_of(item) > 0 ? line_of(item) : v.line};
                if (!item.IsSequence() || item.size() != 2) {
                  fail_expected(interval, "an interval [min, max]");
                }
                std::array<float, 2> bounds{};
                for (size_t j = 0; j < 2; ++j) {
                  bounds[j] = read_float(
                      Val{item[j], interval.path + "[" + std::to_string(j) + "]", interval.line},
                      kAnyReal);
                }
                if (bounds[0] > bounds[1]) {
                  fail(interval, "min (" + format_float(bounds[0], true) +
                                     ") must not be greater than max (" +
                                     format_float(bounds[1], true) + ")");
                }
                sampler.intervals.push_back(bounds);
              }
            }},
           seed});
      break;
  }
  return sampler;
}

std::vector<Lesson> Parser::parse_curriculum(const Val& value, const std::string& parameter,
                                             const RunConfig& config) const {
  if (!value.node.IsSequence() || value.node.size() == 0) {
    fail_expected(value, "a non-empty list of lessons (name, value, completion_criteria)");
  }
  std::vector<Lesson> lessons;
  std::vector<Val> locations;
  for (size_t i = 0; i < value.node.size(); ++i) {
    const YAML::Node item = value.node[i];
    const Val entry{item, value.path + "[" + std::to_string(i) + "]",
                    line_of(item) > 0 ? line_of(item) : value.line};
    if (!item.IsMap())
      fail_expected(entry, "a lesson (a mapping of name, value, completion_criteria)");
    Lesson lesson;
    bool has_name = false, has_value = false;
    std::optional<Val> staircase_at;
    dispatch(entry, {
                        {"name",
                         [&](const Val& v) {
                           lesson.name = read_string(v, false);
                           if (lesson.name.empty()) fail(v, "must not be empty");
                           has_name = true;
                         }},
                        {"value",
                         [&](const Val& v) {
                           lesson.value = parse_sampler(v);
                           has_value = true;
                         }},
                        {"other_parameters",
                         [&](const Val& v) {
                           if (!v.node.IsMap())
                             fail_expected(v, "a mapping of env parameter names to values");
                           for_each_entry(v, [&](const std::string& key, const Val& x) {
                             lesson.other_parameters[key] = parse_sampler(x);
                           });
                         }},
                        {"behavior_max_steps",
                         [&](const Val& v) {
                           if (!v.node.IsMap())
                             fail_expected(v, "a mapping of behavior names to step totals");
                           for_each_entry(v, [&](const std::string& key, const Val& x) {
                             check_behavior_configured(x, key, config);
                             lesson.behavior_max_steps[key] = read_int(x, kPositiveInt64);
                           });
                         }},
                        {"completion_criteria",
                         [&](const Val& v) {
                           if (!v.node.IsNull()) {
                             lesson.completion_criteria = parse_completion_criteria(v, config);
                           }
                         }},
                        {"staircase",
                         [&](const Val& v) {
                           lesson.staircase = parse_staircase(v);
                           staircase_at = v;
                         }},
                    });
    if (!has_name) fail(join_path(entry.path, "name"), entry.line, "missing: the lesson's name");
    if (!has_value) {
      fail(join_path(entry.path, "value"), entry.line,
           "missing: the parameter's value during the lesson (a number or a sampler)");
    }
    if (lesson.staircase) check_staircase(*staircase_at, lesson, parameter);
    lessons.push_back(std::move(lesson));
    locations.push_back(entry);
  }
  const auto names = [](const Lesson& l) {
    std::string out;
    for (const auto& [key, sampler] : l.other_parameters) out += (out.empty() ? "" : ", ") + key;
    return out.empty() ? std::string("none") : out;
  };
  for (size_t i = 1; i < lessons.size(); ++i) {
    if (names(lessons[i]) != names(lessons[0])) {
      fail(join_path(locations[i].path, "other_parameters"), locations[i].line,
           "lesson '" + lessons[i].name + "' sets " + names(lessons[i]) + ", the first lesson sets " +
               names(lessons[0]) + ": every lesson must set the same other parameters");
    }
  }
  for (size_t i = 0; i + 1 < lessons.size(); ++i) {
    if (!lessons[i].completion_criteria) {
      fail(join_path(locations[i].path, "completion_criteria"), locations[i].line,
           "missing: lesson '" + lessons[i].name +
               "' is not the last lesson, so it needs a completion_criteria");
    }
  }
  return lessons;
}

Staircase Parser::parse_staircase(const Val& value) const {
  if (!value.node.IsMap()) fail_expected(value, "a mapping of parameter, end, step_up, step_down");
  Staircase staircase;
  bool has_parameter = false, has_end = false, has_up = false, has_down = false;
  dispatch(value, {
                      {"parameter",
                       [&](const Val& v) {
                         staircase.parameter = read_string(v, false);
                         has_parameter = true;
                       }},
                      {"end",
                       [&](const Val& v) {
                         staircase.end = read_real(v, kAnyReal);
                         has_end = true;
                       }},
                      {"step_up",
                       [&](const Val& v) {
                         staircase.step_up = read_real(v, kPositiveReal);
                         has_up = true;
                       }},
                      {"step_down",
                       [&](const Val& v) {
                         staircase.step_down = read_real(v, kNonNegativeReal);
                         has_down = true;
                       }},
                  });
  const auto missing = [&](const char* key, const std::string& what) {
    fail(join_path(value.path, key), value.line, "missing: " + what);
  };
  if (!has_parameter) missing("parameter", "the parameter whose value the staircase moves");
  if (!has_end) missing("end", "the value at which the lesson completes");
  if (!has_up) missing("step_up", "how far an episode above the threshold moves the value");
  if (!has_down) missing("step_down", "how far any other counted episode moves it back");
  return staircase;
}

void Parser::check_staircase(const Val& at, const Lesson& lesson,
                             const std::string& parameter) const {
  const Staircase& staircase = *lesson.staircase;
  const SamplerSettings* start = nullptr;
  if (staircase.parameter == parameter) {
    start = &lesson.value;
  } else if (const auto found = lesson.other_parameters.find(staircase.parameter);
             found != lesson.other_parameters.end()) {
    start = &found->second;
  } else {
    std::string known = parameter;
    for (const auto& [key, sampler] : lesson.other_parameters) known += ", " + key;
    fail(join_path(at.path, "parameter"), at.line,
         "'" + staircase.parameter + "' is not a parameter of lesson '" + lesson.name +
             "' (it sets: " + known + ")");
  }
  if (start->type != SamplerType::kConstant) {
    fail(join_path(at.path, "parameter"), at.line,
         "lesson '" + lesson.name + "' draws " + staircase.parameter +
             " from a sampler; a staircase starts from a constant value");
  }
  // compared as the env gets it (a float): 0.3 and 0.3f are one value there
  if (start->value == float(staircase.end)) {
    fail(join_path(at.path, "end"), at.line,
         "equals the start (" + format_float(start->value, true) + ", lesson '" + lesson.name +
             "''s value of " + staircase.parameter + "): the staircase would have nowhere to go");
  }
  if (!lesson.completion_criteria ||
      lesson.completion_criteria->measure == CompletionMeasure::kProgress) {
    fail(at, "needs the lesson's completion_criteria with measure: reward or metric (what each "
             "counted episode is judged on against its threshold)");
  }
}

void Parser::check_behavior_configured(const Val& at, const std::string& behavior,
                                       const RunConfig& config) const {
  if (config.default_settings || config.behaviors.count(behavior)) return;
  std::vector<std::string> names;
  for (const auto& [name, settings] : config.behaviors) names.push_back(name);
  fail(at, "behavior '" + behavior + "' is not configured (configured: " + join_names(names) +
               ")" + did_you_mean(behavior, names));
}

CompletionCriteria Parser::parse_completion_criteria(const Val& value,
                                                     const RunConfig& config) const {
  if (!value.node.IsMap()) fail_expected(value, "a mapping");
  CompletionCriteria criteria;
  bool has_behavior = false;
  std::optional<Val> threshold;
  std::optional<Val> metric;
  std::optional<Val> fallback, fallback_length;
  dispatch(
      value,
      {
          {"behavior",
           [&](const Val& v) {
             criteria.behavior = read_string(v, false);
             if (criteria.behavior.empty()) fail(v, "must not be empty");
             check_behavior_configured(v, criteria.behavior, config);
             has_behavior = true;
           }},
          {"measure",
           [&](const Val& v) {
             criteria.measure =
                 read_choice<CompletionMeasure>(v, {{"reward", CompletionMeasure::kReward},
                                                    {"progress", CompletionMeasure::kProgress},
                                                    {"metric", CompletionMeasure::kMetric}});
           }},
          {"metric",
           [&](const Val& v) {
             criteria.metric = read_string(v, false);
             if (criteria.metric.empty()) fail(v, "must not be empty");
             metric = v;
           }},
          {"min_lesson_length",
           [&](const Val& v) {
             criteria.min_lesson_length = read_int32(v, IntRange{0, kIntMax});
           }},
          {"signal_smoothing", [&](const Val& v) { criteria.signal_smoothing = read_bool(v); }},
          {"threshold",
           [&](const Val& v) {
             criteria.threshold = read_real(v, kAnyReal);
             threshold = v;
           }},
          {"require_reset", [&](const Val& v) { criteria.require_reset = read_bool(v); }},
          {"fallback_threshold",
           [&](const Val& v) {
             criteria.fallback_threshold = read_real(v, kAnyReal);
             fallback = v;
           }},
          {"fallback_length",
           [&](const Val& v) {
             criteria.fallback_length = read_int32(v, IntRange{1, kIntMax});
             fallback_length = v;
           }},
          {"after_emerged",
           [&](const Val& v) {
             // which names the env declares is checked when training starts
             if (!v.node.IsSequence())
               fail_expected(v, "a list of strategy names (e.g. [running_and_chasing])");
             criteria.after_emerged.clear();
             for (size_t i = 0; i < v.node.size(); ++i) {
               const Val item{v.node[i], v.path + "[" + std::to_string(i) + "]",
                              line_of(v.node[i]) > 0 ? line_of(v.node[i]) : v.line};
               const std::string name = read_string(item, false);
               if (name.empty()) fail(item, "must not be empty");
               if (std::find(criteria.after_emerged.begin(), criteria.after_emerged.end(),
                             name) != criteria.after_emerged.end())
                 fail(item, "names the strategy '" + name + "' twice");
               criteria.after_emerged.push_back(name);
             }
           }},
      });
  if (criteria.measure == CompletionMeasure::kMetric) {
    if (!metric) {
      fail(join_path(value.path, "metric"), value.line,
           "missing: with measure: metric, the env's episode metric that completes the lesson "
           "(e.g. fort_rate)");
    }
  } else {
    if (metric) fail(*metric, "is only read with measure: metric");
    if (!has_behavior) {
      fail(join_path(value.path, "behavior"), value.line,
           "missing: the behavior whose progress or reward completes the lesson");
    }
  }
  if (threshold && criteria.measure == CompletionMeasure::kProgress &&
      !in_range(criteria.threshold, RealRange{0.0, false, 1.0, false})) {
    fail(*threshold,
         "with measure: progress, expected a number in [0, 1] (a fraction of "
         "max_steps), got " +
             describe(threshold->node));
  }
  if (fallback && criteria.measure == CompletionMeasure::kProgress)
    fail(*fallback, "is only read with measure: reward or metric (progress never falls back)");
  if (fallback_length && !fallback)
    fail(*fallback_length, "is only read with fallback_threshold");
  if (fallback && !(*criteria.fallback_threshold < criteria.threshold)) {
    fail(*fallback, "expected a number below threshold (" + format_float(criteria.threshold, false) +
                        "), got " + describe(fallback->node) +
                        ": a lesson that falls back at its own threshold would never end");
  }
  return criteria;
}

void Parser::parse_torch_settings(const Val& value) const {
  dispatch(value, {{"device", [&](const Val& v) {
                      if (v.node.IsNull()) return;  // ML-Agents: pick automatically
                      const std::string device = read_string(v, false);
                      if (device != "cpu") {
                        fail(v, "only 'cpu' is supported, got '" + device + "'");
                      }
                    }}});
}

void Parser::parse_engine_settings(const Val& value) const {
  // Unity player settings: there is no Unity engine, so they are accepted and have no effect.
  std::vector<KeyHandler> keys;
  for (const char* name : {"width", "height", "quality_level", "time_scale", "target_frame_rate",
                           "capture_frame_rate", "no_graphics"}) {
    keys.push_back({name, [](const Val&) {}});
  }
  dispatch(value, keys);
}

RunConfig Parser::parse(const YAML::Node& root) {
  RunConfig config;
  config.source_file = file_;
  const Val top{root, "", line_of(root)};
  if (!root.IsMap()) {
    fail_expected(top, "a mapping of sections (behaviors, default_settings, env_settings, ...)");
  }
  std::optional<Val> behaviors, defaults, env, checkpoint, parameters, torch, engine;
  auto keep = [](std::optional<Val>* slot) { return [slot](const Val& v) { *slot = v; }; };
  dispatch(top, {
                    // laid under this file before parsing (load_run_config)
                    {"base_config", [](const Val&) {}},
                    {"behaviors", keep(&behaviors)},
                    {"default_settings", keep(&defaults)},
                    {"env_settings", keep(&env)},
                    {"checkpoint_settings", keep(&checkpoint)},
                    {"environment_parameters", keep(&parameters)},
                    {"torch_settings", keep(&torch)},
                    {"engine_settings", keep(&engine)},
                    {"debug", [&](const Val& v) { read_bool(v); }},  // no debug logging mode
                });

  // default_settings is the base layer of every behavior.
  BehaviorDraft base;
  if (defaults && !defaults->node.IsNull()) {
    Val size_location{YAML::Node(), join_path(defaults->path, "hyperparameters.buffer_size"),
                      defaults->line};
    Val layer_size_location;
    parse_behavior(*defaults, &base, &layer_size_location);
    if (!layer_size_location.path.empty()) size_location = layer_size_location;
    config.default_settings = finish_behavior(base, size_location);
    // Behaviors inherit the resolved self_play (team_change included), as ML-Agents merges the
    // structured default_settings into each behavior.
    base.config.self_play = config.default_settings->self_play;
    base.team_change_given = base.config.self_play.has_value();
  }
  if (behaviors) {
    for_each_entry(*behaviors, [&](const std::string& name, const Val& v) {
      if (name.empty()) fail(v, "behavior names must not be empty");
      BehaviorDraft draft = base;
      Val size_location{YAML::Node(), join_path(v.path, "hyperparameters.buffer_size"), v.line};
      Val layer_size_location;
      parse_behavior(v, &draft, &layer_size_location);
      if (!layer_size_location.path.empty()) size_location = layer_size_location;
      config.behaviors[name] = finish_behavior(draft, size_location);
    });
  }
  if (config.behaviors.empty() && !config.default_settings) {
    fail(behaviors ? behaviors->path : "", behaviors ? behaviors->line : 0,
         "no behaviors configured: give `behaviors` (settings per behavior name) or "
         "`default_settings`");
  }

  parse_env_settings(env, &config.env_settings);
  if (checkpoint) parse_checkpoint_settings(*checkpoint, &config.checkpoint_settings);
  if (parameters) {
    parse_environment_parameters(*parameters, config, &config.environment_parameters);
  }
  if (torch) parse_torch_settings(*torch);
  if (engine) parse_engine_settings(*engine);
  return config;
}

// ---------------------------------------------------------------------------------------------
// Writing.

void emit_float(YAML::Emitter& out, float value) { out << format_float(value, true); }

void emit_float_map(YAML::Emitter& out, const std::map<std::string, float>& values) {
  if (values.empty()) {
    out << YAML::Flow << YAML::BeginMap << YAML::EndMap;
    return;
  }
  out << YAML::BeginMap;
  for (const auto& [name, value] : values) {
    out << YAML::Key;
    emit_string(out, name);
    out << YAML::Value;
    emit_float(out, value);
  }
  out << YAML::EndMap;
}

void emit_behavior(YAML::Emitter& out, const BehaviorConfig& config) {
  const Hyperparameters& hyper = config.hyperparameters;
  const NetworkSettings& network = config.network_settings;
  out << YAML::BeginMap;
  out << YAML::Key << "trainer_type" << YAML::Value << config.trainer_type;

  out << YAML::Key << "hyperparameters" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "batch_size" << YAML::Value << hyper.batch_size;
  out << YAML::Key << "buffer_size" << YAML::Value << hyper.buffer_size;
  out << YAML::Key << "learning_rate" << YAML::Value;
  emit_float(out, hyper.learning_rate);
  out << YAML::Key << "learning_rate_schedule" << YAML::Value
      << schedule_name(hyper.learning_rate_schedule);
  out << YAML::Key << "beta" << YAML::Value;
  emit_float(out, hyper.beta);
  out << YAML::Key << "beta_schedule" << YAML::Value
      << schedule_name(hyper.beta_schedule.value_or(hyper.learning_rate_schedule));
  out << YAML::Key << "discrete_beta" << YAML::Value;
  emit_float(out, hyper.discrete_beta.value_or(hyper.beta));
  if (hyper.discrete_beta_steps > 0 && hyper.discrete_beta_end) {
    out << YAML::Key << "discrete_beta_end" << YAML::Value;
    emit_float(out, *hyper.discrete_beta_end);
    out << YAML::Key << "discrete_beta_steps" << YAML::Value << hyper.discrete_beta_steps;
  }
  out << YAML::Key << "epsilon" << YAML::Value;
  emit_float(out, hyper.epsilon);
  out << YAML::Key << "epsilon_schedule" << YAML::Value
      << schedule_name(hyper.epsilon_schedule.value_or(hyper.learning_rate_schedule));
  out << YAML::Key << "lambd" << YAML::Value;
  emit_float(out, hyper.lambd);
  out << YAML::Key << "num_epoch" << YAML::Value << hyper.num_epoch;
  out << YAML::Key << "shared_critic" << YAML::Value << hyper.shared_critic;
  out << YAML::Key << "max_grad_norm" << YAML::Value;
  emit_float(out, hyper.max_grad_norm);
  out << YAML::Key << "value_loss_coef" << YAML::Value;
  emit_float(out, hyper.value_loss_coef);
  out << YAML::EndMap;

  out << YAML::Key << "network_settings" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "normalize" << YAML::Value << network.normalize;
  out << YAML::Key << "normalize_grids" << YAML::Value << network.normalize_grids;
  out << YAML::Key << "hidden_units" << YAML::Value << network.hidden_units;
  out << YAML::Key << "num_layers" << YAML::Value << network.num_layers;
  out << YAML::Key << "vis_encode_type" << YAML::Value << network.vis_encode_type;
  out << YAML::Key << "deterministic" << YAML::Value << network.deterministic;
  out << YAML::Key << "activation" << YAML::Value << activation_name(network.activation);
  out << YAML::EndMap;

  out << YAML::Key << "reward_signals" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "extrinsic" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "gamma" << YAML::Value;
  emit_float(out, config.extrinsic.gamma);
  out << YAML::Key << "strength" << YAML::Value;
  emit_float(out, config.extrinsic.strength);
  out << YAML::EndMap << YAML::EndMap;

  out << YAML::Key << "init_path" << YAML::Value;
  if (config.init_path.empty()) {
    out << YAML::Null;
  } else {
    emit_string(out, config.init_path);
  }
  out << YAML::Key << "keep_checkpoints" << YAML::Value << config.keep_checkpoints;
  out << YAML::Key << "checkpoint_interval" << YAML::Value
      << static_cast<long long>(config.checkpoint_interval);
  out << YAML::Key << "max_steps" << YAML::Value << static_cast<long long>(config.max_steps);
  out << YAML::Key << "time_horizon" << YAML::Value << config.time_horizon;
  out << YAML::Key << "summary_freq" << YAML::Value << static_cast<long long>(config.summary_freq);
  out << YAML::Key << "threaded" << YAML::Value << config.threaded;
  out << YAML::Key << "self_play" << YAML::Value;
  if (config.self_play) {
    const SelfPlaySettings& self_play = *config.self_play;
    out << YAML::BeginMap;
    out << YAML::Key << "save_steps" << YAML::Value << static_cast<long long>(self_play.save_steps);
    out << YAML::Key << "team_change" << YAML::Value
        << static_cast<long long>(self_play.team_change);
    out << YAML::Key << "swap_steps" << YAML::Value << static_cast<long long>(self_play.swap_steps);
    out << YAML::Key << "window" << YAML::Value << self_play.window;
    out << YAML::Key << "play_against_latest_model_ratio" << YAML::Value;
    emit_float(out, self_play.play_against_latest_model_ratio);
    out << YAML::Key << "initial_elo" << YAML::Value << format_float(self_play.initial_elo, false);
    if (!self_play.turn_parameters.empty()) {
      out << YAML::Key << "turn_parameters" << YAML::Value;
      emit_float_map(out, self_play.turn_parameters);
    }
    out << YAML::EndMap;
  } else {
    out << YAML::Null;
  }
  out << YAML::EndMap;
}


const char* sampler_type_name(SamplerType type) {
  switch (type) {
    case SamplerType::kConstant:
      return "constant";
    case SamplerType::kUniform:
      return "uniform";
    case SamplerType::kGaussian:
      return "gaussian";
    case SamplerType::kMultiRangeUniform:
      return "multirangeuniform";
  }
  return "constant";
}

// A constant as a plain number, any other sampler as {sampler_type, sampler_parameters}.
void emit_sampler(YAML::Emitter& out, const SamplerSettings& sampler) {
  if (sampler.type == SamplerType::kConstant) {
    emit_float(out, sampler.value);
    return;
  }
  out << YAML::BeginMap;
  out << YAML::Key << "sampler_type" << YAML::Value << sampler_type_name(sampler.type);
  out << YAML::Key << "sampler_parameters" << YAML::Value << YAML::BeginMap;
  switch (sampler.type) {
    case SamplerType::kConstant:
      break;
    case SamplerType::kUniform:
      out << YAML::Key << "min_value" << YAML::Value;
      emit_float(out, sampler.min_value);
      out << YAML::Key << "max_value" << YAML::Value;
      emit_float(out, sampler.max_value);
      break;
    case SamplerType::kGaussian:
      out << YAML::Key << "mean" << YAML::Value;
      emit_float(out, sampler.mean);
      out << YAML::Key << "st_dev" << YAML::Value;
      emit_float(out, sampler.st_dev);
      break;
    case SamplerType::kMultiRangeUniform:
      out << YAML::Key << "intervals" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const std::array<float, 2>& interval : sampler.intervals) {
        out << YAML::Flow << YAML::BeginSeq;
        emit_float(out, interval[0]);
        emit_float(out, interval[1]);
        out << YAML::EndSeq;
      }
      out << YAML::EndSeq;
      break;
  }
  out << YAML::EndMap << YAML::EndMap;
}

void emit_environment_parameters(
    YAML::Emitter& out, const std::map<std::string, EnvironmentParameterSettings>& parameters) {
  if (parameters.empty()) {
    out << YAML::Flow << YAML::BeginMap << YAML::EndMap;
    return;
  }
  out << YAML::BeginMap;
  for (const auto& [name, parameter] : parameters) {
    out << YAML::Key;
    emit_string(out, name);
    out << YAML::Value;
    if (!parameter.is_curriculum()) {
      emit_sampler(out, parameter.sampler);
      continue;
    }
    out << YAML::BeginMap << YAML::Key << "curriculum" << YAML::Value << YAML::BeginSeq;
    for (const Lesson& lesson : parameter.curriculum) {
      out << YAML::BeginMap;
      out << YAML::Key << "name" << YAML::Value;
      emit_string(out, lesson.name);
      out << YAML::Key << "value" << YAML::Value;
      emit_sampler(out, lesson.value);
      if (!lesson.other_parameters.empty()) {
        out << YAML::Key << "other_parameters" << YAML::Value << YAML::BeginMap;
        for (const auto& [key, sampler] : lesson.other_parameters) {
          out << YAML::Key;
          emit_string(out, key);
          out << YAML::Value;
          emit_sampler(out, sampler);
        }
        out << YAML::EndMap;
      }
      if (!lesson.behavior_max_steps.empty()) {
        out << YAML::Key << "behavior_max_steps" << YAML::Value << YAML::BeginMap;
        for (const auto& [behavior, steps] : lesson.behavior_max_steps) {
          out << YAML::Key;
          emit_string(out, behavior);
          out << YAML::Value << steps;
        }
        out << YAML::EndMap;
      }
      if (lesson.completion_criteria) {
        const CompletionCriteria& criteria = *lesson.completion_criteria;
        out << YAML::Key << "completion_criteria" << YAML::Value << YAML::BeginMap;
        if (!criteria.behavior.empty()) {
          out << YAML::Key << "behavior" << YAML::Value;
          emit_string(out, criteria.behavior);
        }
        out << YAML::Key << "measure" << YAML::Value
            << (criteria.measure == CompletionMeasure::kReward     ? "reward"
                : criteria.measure == CompletionMeasure::kProgress ? "progress"
                                                                   : "metric");
        if (criteria.measure == CompletionMeasure::kMetric) {
          out << YAML::Key << "metric" << YAML::Value;
          emit_string(out, criteria.metric);
        }
        out << YAML::Key << "min_lesson_length" << YAML::Value << criteria.min_lesson_length;
        out << YAML::Key << "signal_smoothing" << YAML::Value << criteria.signal_smoothing;
        out << YAML::Key << "threshold" << YAML::Value << format_float(criteria.threshold, false);
        out << YAML::Key << "require_reset" << YAML::Value << criteria.require_reset;
        if (criteria.fallback_threshold) {
          out << YAML::Key << "fallback_threshold" << YAML::Value
              << format_float(*criteria.fallback_threshold, false);
          if (criteria.fallback_length > 0)
            out << YAML::Key << "fallback_length" << YAML::Value << criteria.fallback_length;
        }
        if (!criteria.after_emerged.empty()) {
          out << YAML::Key << "after_emerged" << YAML::Value << YAML::Flow << YAML::BeginSeq;
          for (const std::string& name : criteria.after_emerged) emit_string(out, name);
          out << YAML::EndSeq;
        }
        out << YAML::EndMap;
      }
      if (lesson.staircase) {
        const Staircase& staircase = *lesson.staircase;
        out << YAML::Key << "staircase" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "parameter" << YAML::Value;
        emit_string(out, staircase.parameter);
        out << YAML::Key << "end" << YAML::Value << format_float(staircase.end, false);
        out << YAML::Key << "step_up" << YAML::Value << format_float(staircase.step_up, false);
        out << YAML::Key << "step_down" << YAML::Value << format_float(staircase.step_down, false);
        out << YAML::EndMap;
      }
      out << YAML::EndMap;
    }
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndMap;
}

}  // namespace

namespace {

// The one YAML document of a configuration's text; problems name `file`.
YAML::Node read_document(const std::string& yaml, const std::string& file) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(yaml);
  } catch (const YAML::ParserException& error) {
    const int line = error.mark.is_null() ? 0 : error.mark.line + 1;
    const std::string column =
        error.mark.is_null() ? "" : " (column " + std::to_string(error.mark.column + 1) + ")";
    throw ConfigError(file, "", line, "YAML syntax error: " + error.msg + column);
  } catch (const YAML::Exception& error) {
    throw ConfigError(file, "", 0, std::string("cannot read the YAML: ") + error.what());
  }
  if (documents.empty() || (documents.size() == 1 && documents[0].IsNull())) {
    throw ConfigError(file, "", 0,
                      "the configuration is empty (expected `behaviors` or `default_settings`)");
  }
  if (documents.size() > 1) {
    throw ConfigError(file, "", line_of(documents[1]),
                      "expected one YAML document, found " + std::to_string(documents.size()));
  }
  return documents[0];
}

// The text of the file at `path`; problems name `file` (the path itself, or the file naming it
// as a base) with `key_path` and `line`, and say which path could not be read.
std::string read_text(const std::string& path, const std::string& file,
                      const std::string& key_path, int line) {
  const std::string what = file == path ? "" : " " + path;
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw ConfigError(file, key_path, line,
                      "cannot read the configuration" + what + ": it is a directory");
  }
  std::ifstream stream(path, std::ios::binary);
  if (!stream) {
    throw ConfigError(file, key_path, line,
                      "cannot read the configuration" + what + ": " + std::strerror(errno));
  }
  std::ostringstream text;
  text << stream.rdbuf();
  if (stream.bad()) {
    throw ConfigError(file, key_path, line, "cannot read the configuration" + what + ": read error");
  }
  return text.str();
}

// The file at `path` as one name for every way of writing it: symbolic links and ".." resolved
// as far as the path exists, else the absolute path as written.
std::string file_identity(const std::string& path) {
  std::error_code error;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, error);
  if (!error) return canonical.string();
  const std::filesystem::path absolute = std::filesystem::absolute(path, error);
  return (error ? std::filesystem::path(path) : absolute).lexically_normal().string();
}

// `root`, the document of `file`, with the chain of base_config files it names laid under it.
// Each base is read as a configuration on its own first, so that its problems name it. `chain`
// holds the files that named this one, to refuse a cycle.
YAML::Node lay_over_bases(const YAML::Node& root, const std::string& file,
                          std::vector<std::string>* chain, KeyOrigins* origins) {
  *origins = KeyOrigins(file);
  if (!root.IsMap()) return root;  // the parser says what is wrong with it
  bool has_base = false;
  YAML::Node base_key, base_value;
  YAML::Node over(YAML::NodeType::Map);  // the file without its base_config
  for (auto it = root.begin(); it != root.end(); ++it) {
    if (it->first.IsScalar() && it->first.Scalar() == "base_config") {
      if (has_base) {
        throw ConfigError(file, "", line_of(it->first), "key 'base_config' appears twice");
      }
      has_base = true;
      base_key.reset(it->first);
      base_value.reset(it->second);
    } else {
      over.force_insert(it->first, it->second);
    }
  }
  if (!has_base) return root;
  const int line = line_of(base_key);
  if (!base_value.IsScalar() || base_value.Scalar().empty()) {
    throw ConfigError(file, "base_config", line,
                      "expected the path of a run configuration (relative to this file), got " +
                          describe(base_value));
  }
  std::filesystem::path base_path(base_value.Scalar());
  if (base_path.is_relative()) base_path = std::filesystem::path(file).parent_path() / base_path;
  const std::string base = base_path.lexically_normal().string();  // read and named as this
  chain->push_back(file_identity(file));
  const std::string identity = file_identity(base);
  for (const std::string& named : *chain) {
    if (named == identity) {
      std::string files;
      for (const std::string& f : *chain) files += f + " -> ";
      throw ConfigError(file, "base_config", line,
                        base + " is this file or one of the files it is a base of, so the bases "
                               "would never end (" + files + identity + ")");
    }
  }
  const YAML::Node base_root = read_document(read_text(base, file, "base_config", line), base);
  KeyOrigins base_origins(base);
  const YAML::Node base_tree = lay_over_bases(base_root, base, chain, &base_origins);
  refuse_removals(base_tree, base_origins);
  Parser(base_origins).parse(base_tree);  // the base must be a configuration on its own
  chain->pop_back();
  return lay_over(base_tree, base_origins, over, file, origins);
}

}  // namespace

RunConfig load_run_config_from_string(const std::string& yaml, const std::string& source_name) {
  const YAML::Node root = read_document(yaml, source_name);
  try {
    std::vector<std::string> chain;
    KeyOrigins origins(source_name);
    const YAML::Node tree = lay_over_bases(root, source_name, &chain, &origins);
    refuse_removals(tree, origins);
    return Parser(origins).parse(tree);
  } catch (const YAML::Exception& error) {  // not expected: the parser only reads checked nodes
    throw ConfigError(source_name, "", 0, std::string("cannot read the YAML: ") + error.what());
  }
}

RunConfig load_run_config(const std::string& path) {
  return load_run_config_from_string(read_text(path, path, "", 0), path);
}

std::string run_config_to_yaml(const RunConfig& config) {
  YAML::Emitter out;
  out.SetNullFormat(YAML::LowerNull);  // "null", as ML-Agents writes it
  out << YAML::BeginMap;

  if (config.default_settings) {
    out << YAML::Key << "default_settings" << YAML::Value;
    emit_behavior(out, *config.default_settings);
  }
  out << YAML::Key << "behaviors" << YAML::Value;
  if (config.behaviors.empty()) {
    out << YAML::Flow << YAML::BeginMap << YAML::EndMap;
  } else {
    out << YAML::BeginMap;
    for (const auto& [name, behavior] : config.behaviors) {
      out << YAML::Key;
      emit_string(out, name);
      out << YAML::Value;
      emit_behavior(out, behavior);
    }
    out << YAML::EndMap;
  }

  const EnvSettings& env = config.env_settings;
  out << YAML::Key << "env_settings" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "env_id" << YAML::Value;
  emit_string(out, env.env_id);
  out << YAML::Key << "num_envs" << YAML::Value << env.num_envs;
  out << YAML::Key << "seed" << YAML::Value << static_cast<long long>(env.seed);
  out << YAML::Key << "num_threads" << YAML::Value << env.num_threads;
  out << YAML::Key << "stagger_steps" << YAML::Value << env.stagger_steps;
  out << YAML::Key << "params" << YAML::Value;
  emit_float_map(out, env.params);
  out << YAML::EndMap;

  const CheckpointSettings& checkpoint = config.checkpoint_settings;
  out << YAML::Key << "checkpoint_settings" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "run_id" << YAML::Value;
  emit_string(out, checkpoint.run_id);
  out << YAML::Key << "initialize_from" << YAML::Value;
  if (checkpoint.initialize_from.empty()) {
    out << YAML::Null;
  } else {
    emit_string(out, checkpoint.initialize_from);
  }
  out << YAML::Key << "resume" << YAML::Value << checkpoint.resume;
  out << YAML::Key << "force" << YAML::Value << checkpoint.force;
  out << YAML::Key << "results_dir" << YAML::Value;
  emit_string(out, checkpoint.results_dir);
  out << YAML::EndMap;

  out << YAML::Key << "environment_parameters" << YAML::Value;
  emit_environment_parameters(out, config.environment_parameters);

  out << YAML::Key << "torch_settings" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "device" << YAML::Value << "cpu";
  out << YAML::EndMap;

  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

const BehaviorConfig& behavior_config(const RunConfig& config, const std::string& behavior) {
  const auto found = config.behaviors.find(behavior);
  if (found != config.behaviors.end()) return found->second;
  if (config.default_settings) return *config.default_settings;
  std::vector<std::string> names;
  for (const auto& [name, settings] : config.behaviors) names.push_back(name);
  throw ConfigError(config.source_file, "behaviors." + behavior, 0,
                    "behavior '" + behavior +
                        "' is not configured and there is no default_settings (configured: " +
                        (names.empty() ? "none" : join_names(names)) + ")" +
                        did_you_mean(behavior, names));
}

}  // namespace rlt
