#include "apps/command_line.h"

#include <cmath>
#include <sstream>

namespace rlt {

CommandLine::CommandLine(const std::vector<std::string>& args, const std::set<std::string>& switches,
                         const std::set<std::string>& options) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0) {
      positional_.push_back(a);
      continue;
    }
    std::string flag = a, val;
    const auto eq = a.find('=');
    if (eq != std::string::npos) {
      flag = a.substr(0, eq);
      val = a.substr(eq + 1);
    }
    if (switches.count(flag)) {
      if (eq != std::string::npos) throw UsageError(flag + " takes no value");
      flags_.emplace(flag, "");
    } else if (options.count(flag)) {
      if (eq == std::string::npos) {
        if (i + 1 >= args.size()) throw UsageError(flag + " needs a value");
        val = args[++i];
      }
      flags_.emplace(flag, val);
    } else {
      throw UsageError("unknown option " + flag);
    }
  }
}

bool CommandLine::has(const std::string& flag) const { return flags_.count(flag) > 0; }

std::string CommandLine::value(const std::string& flag, const std::string& fallback) const {
  auto it = flags_.find(flag);
  return it == flags_.end() ? fallback : it->second;
}

std::vector<std::string> CommandLine::values(const std::string& flag) const {
  std::vector<std::string> out;
  for (auto [it, end] = flags_.equal_range(flag); it != end; ++it) out.push_back(it->second);
  return out;
}

long long parse_integer(const std::string& text, const std::string& what, long long min_value) {
  size_t used = 0;
  long long n = 0;
  try {
    n = std::stoll(text, &used);
  } catch (...) {
    used = 0;
  }
  if (used != text.size() || text.empty())
    throw UsageError(what + ": expected an integer, got '" + text + "'");
  if (n < min_value)
    throw UsageError(what + ": must be at least " + std::to_string(min_value) + ", got " + text);
  return n;
}

long long CommandLine::integer(const std::string& flag, long long fallback, long long min_value) const {
  return has(flag) ? parse_integer(value(flag), flag, min_value) : fallback;
}

double CommandLine::number(const std::string& flag, double fallback, double low,
                           double below) const {
  if (!has(flag)) return fallback;
  const std::string v = value(flag);
  size_t used = 0;
  double x = 0;
  try {
    x = std::stod(v, &used);
  } catch (...) {
    used = 0;
  }
  if (used != v.size() || v.empty() || !std::isfinite(x))
    throw UsageError(flag + ": expected a number, got '" + v + "'");
  std::ostringstream range;
  range << "at least " << low;
  if (std::isfinite(below)) range << " and below " << below;
  if (!(x >= low && x < below)) throw UsageError(flag + ": must be " + range.str() + ", got " + v);
  return x;
}

Parameters CommandLine::parameters() const {
  Parameters params;
  for (const auto& p : values("--param")) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0)
      throw UsageError("--param expects NAME=VALUE, got '" + p + "'");
    const std::string value = p.substr(eq + 1);
    size_t used = 0;
    float v = 0;
    try {
      v = std::stof(value, &used);
    } catch (...) {
      used = 0;
    }
    if (used == 0 || used != value.size())
      throw UsageError("--param " + p + ": value '" + value + "' is not a number");
    params[p.substr(0, eq)] = v;
  }
  return params;
}

}  // namespace rlt
