#include "rl/trainer/run_folder.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "rl/core/atomic_file.h"
#include "rl/core/json.h"

namespace fs = std::filesystem;

namespace rlt {

RunFolder::RunFolder(const std::string& results_dir, const std::string& run_id)
    : path_(results_dir + "/" + run_id), run_id_(run_id) {
  if (run_id.empty() || run_id.find('/') != std::string::npos || run_id == "." || run_id == "..")
    throw std::invalid_argument("invalid run id '" + run_id + "': use a plain folder name");
}

bool RunFolder::exists() const { return fs::exists(path_); }

void RunFolder::create(bool force) const {
  if (exists()) {
    if (!force)
      throw std::runtime_error("run folder " + path_ +
                               " already exists: use --resume to continue it or --force to overwrite it");
    fs::remove_all(path_);
  }
  fs::create_directories(path_ + "/checkpoints");
  fs::create_directories(path_ + "/metrics");
}

void RunFolder::write_status(const TrainingStatus& s) const {
  std::ostringstream os;
  os << "{\n  \"run_id\": " << json_string(s.run_id) << ",\n  \"finished\": "
     << (s.finished ? "true" : "false") << ",\n  \"lessons\": {";
  size_t k = 0;
  for (const auto& [name, lesson] : s.lessons) os << (k++ ? ", " : "") << json_string(name) << ": " << lesson;
  os << "},\n  \"elo\": {";
  k = 0;
  for (const auto& [name, elo] : s.elo) os << (k++ ? ", " : "") << json_string(name) << ": " << json_number(elo);
  os << "},\n  \"strategies\": {";
  k = 0;
  for (const auto& e : s.strategies) {
    os << (k++ ? "," : "") << "\n    " << json_string(e.strategy) << ": {\"metric\": "
       << json_string(e.metric) << ", \"behavior\": " << json_string(e.behavior)
       << ", \"emerged\": " << (e.step >= 0 ? "true" : "false");
    if (e.step >= 0)
      os << ", \"step\": " << e.step << ", \"elapsed_seconds\": " << json_number(e.elapsed_s)
         << ", \"rate\": " << json_number(e.rate);
    os << "}";
  }
  os << (k ? "\n  " : "") << "},\n  \"checkpoints\": [";
  for (size_t i = 0; i < s.checkpoints.size(); ++i) {
    const auto& c = s.checkpoints[i];
    os << (i ? "," : "") << "\n    {\"index\": " << c.index << ", \"file\": " << json_string(c.file)
       << ", \"elapsed_seconds\": " << json_number(c.elapsed_seconds) << ", \"steps\": {";
    size_t j = 0;
    for (const auto& [b, n] : c.steps) os << (j++ ? ", " : "") << json_string(b) << ": " << n;
    os << "}}";
  }
  os << "\n  ],\n  \"sessions\": [";
  for (size_t i = 0; i < s.sessions.size(); ++i) {
    const RunSession& r = s.sessions[i];
    os << (i ? "," : "") << "\n    {\"started\": " << json_string(r.started) << ", \"steps\": {";
    size_t j = 0;
    for (const auto& [b, n] : r.steps) os << (j++ ? ", " : "") << json_string(b) << ": " << n;
    os << "}, \"cpu\": " << json_string(r.machine.cpu) << ", \"cores\": " << r.machine.cores
       << ", \"blas_kernels\": " << json_string(r.machine.blas_kernels)
       << ", \"torch\": " << json_string(r.machine.torch_version)
       << ", \"rlt\": " << json_string(r.machine.rlt_commit) << "}";
  }
  os << "\n  ]\n}\n";
  write_file_atomically(status_path(), os.str());
}

TrainingStatus RunFolder::read_status() const {
  if (!fs::exists(status_path()))
    throw std::runtime_error(status_path() + " not found: is " + path_ + " a training run?");
  TrainingStatus s;
  try {
    YAML::Node root = YAML::LoadFile(status_path());
    s.run_id = root["run_id"].as<std::string>();
    s.finished = root["finished"].as<bool>();
    for (const auto& kv : root["lessons"]) s.lessons[kv.first.as<std::string>()] = kv.second.as<int>();
    for (const auto& kv : root["elo"]) s.elo[kv.first.as<std::string>()] = kv.second.as<double>();
    for (const auto& kv : root["strategies"]) {
      Emergence e;
      e.strategy = kv.first.as<std::string>();
      e.metric = kv.second["metric"].as<std::string>();
      e.behavior = kv.second["behavior"].as<std::string>();
      if (kv.second["emerged"].as<bool>()) {
        e.step = kv.second["step"].as<int64_t>();
        e.elapsed_s = kv.second["elapsed_seconds"].as<double>();
        e.rate = kv.second["rate"].as<double>();
      }
      s.strategies.push_back(e);
    }
    for (const auto& c : root["checkpoints"]) {
      CheckpointEntry e;
      e.index = c["index"].as<int64_t>();
      e.file = c["file"].as<std::string>();
      e.elapsed_seconds = c["elapsed_seconds"].as<double>();
      for (const auto& kv : c["steps"]) e.steps[kv.first.as<std::string>()] = kv.second.as<int64_t>();
      s.checkpoints.push_back(e);
    }
    for (const auto& r : root["sessions"]) {
      RunSession e;
      e.started = r["started"].as<std::string>();
      for (const auto& kv : r["steps"]) e.steps[kv.first.as<std::string>()] = kv.second.as<int64_t>();
      e.machine.cpu = r["cpu"].as<std::string>();
      e.machine.cores = r["cores"].as<int>();
      e.machine.blas_kernels = r["blas_kernels"].as<std::string>();
      e.machine.torch_version = r["torch"].as<std::string>();
      e.machine.rlt_commit = r["rlt"].as<std::string>();
      s.sessions.push_back(e);
    }
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(status_path() + ": corrupt training status: " + e.what());
  }
  return s;
}

}  // namespace rlt
