// A small command-line parser for `rlt`: positional arguments and --flags with or without values.
#pragma once

#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "rl/env_api/spec.h"

namespace rlt {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// TEXT as an integer of at least min_value; otherwise a UsageError that begins with WHAT
long long parse_integer(const std::string& text, const std::string& what, long long min_value);

class CommandLine {
 public:
  // `switches`: flags without a value; `options`: flags that take one value (may repeat)
  CommandLine(const std::vector<std::string>& args, const std::set<std::string>& switches,
              const std::set<std::string>& options);

  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& flag) const;
  std::string value(const std::string& flag, const std::string& fallback = "") const;
  std::vector<std::string> values(const std::string& flag) const;
  long long integer(const std::string& flag, long long fallback, long long min_value) const;
  // a number in [low, below); a malformed or out-of-range one is a UsageError naming the flag
  double number(const std::string& flag, double fallback, double low,
                double below = std::numeric_limits<double>::infinity()) const;
  // every --param NAME=VALUE (VALUE a number); a malformed one is a UsageError naming it
  Parameters parameters() const;

 private:
  std::vector<std::string> positional_;
  std::multimap<std::string, std::string> flags_;
};

}  // namespace rlt
