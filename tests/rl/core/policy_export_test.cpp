// export_policy: a perturbed network with a normalizer is exported, then loaded with
// torch::jit::load in a fresh process (policy_probe) and run on fixed observations; its actions
// equal the FastActor's deterministic actions (continuous mean clipped as the env receives it,
// masked argmax), and its spec_json attribute parses back to the behavior spec.
//
// The probe is LibTorch's (policy_probe.cpp) unless POLICY_PROBE_COMMAND names another with the
// same protocol: ctest's policy_export_python_test sets it to Python's torch (policy_probe.py).
#include "rl/core/policy_export.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "rl/core/action_distribution.h"
#include "rl/core/fast_actor.h"
#include "rl/core/policy_network.h"
#include "rl/core/running_normalizer.h"

#ifndef POLICY_PROBE
#error "POLICY_PROBE must name the policy_probe executable"
#endif

namespace fs = std::filesystem;

namespace rlt {
namespace {

// A small JSON reader, enough to check that spec_json is well formed and to read it back.
struct Json {
  enum Type { kNull, kBool, kNumber, kString, kArray, kObject } type = kNull;
  double number = 0;
  bool boolean = false;
  std::string text;
  std::vector<Json> items;
  std::vector<std::pair<std::string, Json>> fields;

  const Json& at(const std::string& key) const {
    for (const auto& [k, v] : fields)
      if (k == key) return v;
    throw std::runtime_error("no key " + key);
  }
};

class JsonReader {
 public:
  explicit JsonReader(const std::string& s) : s_(s) {}
  Json document() {
    Json v = value();
    skip();
    if (pos_ != s_.size()) fail("trailing text");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) {
    throw std::runtime_error("JSON: " + what + " at " + std::to_string(pos_));
  }
  void skip() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  void expect(char c) {
    skip();
    if (pos_ >= s_.size() || s_[pos_] != c) fail(std::string("expected ") + c);
    ++pos_;
  }
  bool peek(char c) {
    skip();
    return pos_ < s_.size() && s_[pos_] == c;
  }
  std::string string() {
    expect('"');
    std::string out;
    while (pos_ < s_.size() && s_[pos_] != '"') {
      if (s_[pos_] == '\\') ++pos_;
      if (pos_ >= s_.size()) fail("unterminated string");
      out += s_[pos_++];
    }
    expect('"');
    return out;
  }
  Json value() {
    skip();
    Json v;
    if (pos_ >= s_.size()) fail("unexpected end");
    const char c = s_[pos_];
    if (c == '{') {
      v.type = Json::kObject;
      ++pos_;
      if (peek('}')) return ++pos_, v;
      do {
        std::string key = string();
        expect(':');
        v.fields.emplace_back(key, value());
      } while (peek(',') && ++pos_);
      expect('}');
    } else if (c == '[') {
      v.type = Json::kArray;
      ++pos_;
      if (peek(']')) return ++pos_, v;
      do v.items.push_back(value());
      while (peek(',') && ++pos_);
      expect(']');
    } else if (c == '"') {
      v.type = Json::kString;
      v.text = string();
    } else if (s_.compare(pos_, 4, "true") == 0 || s_.compare(pos_, 5, "false") == 0) {
      v.type = Json::kBool;
      v.boolean = s_[pos_] == 't';
      pos_ += v.boolean ? 4 : 5;
    } else if (s_.compare(pos_, 4, "null") == 0) {
      pos_ += 4;
    } else {
      size_t used = 0;
      try {
        v.number = std::stod(s_.substr(pos_), &used);
      } catch (...) {
        fail("bad value");
      }
      v.type = Json::kNumber;
      pos_ += used;
    }
    return v;
  }

  const std::string& s_;
  size_t pos_ = 0;
};

constexpr int kObs = 6;  // "pos" [4] + "grid" [1, 2, 1]

BehaviorSpec make_behavior(int continuous, std::vector<int> branches) {
  BehaviorSpec spec;
  spec.name = "Probe \"Bot\"?team=0";  // not an identifier
  spec.observations.push_back({"pos", {4}, ObservationKind::kVector});
  spec.observations.push_back({"grid", {1, 2, 1}, ObservationKind::kGrid});
  spec.action.continuous_size = continuous;
  spec.action.discrete_branches = std::move(branches);
  spec.agent_slots = 3;
  return spec;
}

PolicyNetwork make_network(const ActionSpec& action, Activation act, uint64_t seed) {
  torch::manual_seed(seed);
  NetworkShape shape;
  shape.obs_size = kObs;
  shape.action = action;
  shape.hidden_units = 12;
  shape.num_layers = 2;
  shape.activation = act;
  PolicyNetwork net(shape);
  torch::NoGradGuard no_grad;
  for (auto& p : net->parameters()) p.add_(0.5f * torch::randn_like(p));
  // means beyond +-3 on some rows, so that the export's clipping is exercised
  if (action.continuous_size > 0) net->mean_head.weight.mul_(8.f);
  return net;
}

RunningNormalizer make_normalizer(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> dist(0.f, 1.f);
  std::vector<float> data(100 * kObs);
  for (int r = 0; r < 100; ++r)
    for (int i = 0; i < kObs; ++i) data[r * kObs + i] = 1.5f * i - 2.f + (0.3f + i) * dist(rng);
  RunningNormalizer norm(kObs);
  norm.update(data.data(), 100);
  return norm;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct ProbeResult {
  std::string spec_json;
  int format_version = -1;
  std::vector<std::vector<float>> continuous;  // [B][C]
  std::vector<std::vector<int>> discrete;      // [B][K]
};

class PolicyExportTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() / ("policy_export_test_" + std::to_string(::getpid()) + "_" +
                                     testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // runs policy_probe on `model` in a fresh process
  ProbeResult probe(const std::string& model, const RowMatrix& obs,
                    const std::vector<uint8_t>* mask, int mask_width) {
    const std::string input = (dir_ / "input.txt").string(),
                      output = (dir_ / "output.txt").string();
    {
      std::ofstream in(input);
      in.precision(9);
      in << obs.rows() << ' ' << (mask ? mask_width : 0) << " 2\n1 4\n3 1 2 1\n";
      for (int r = 0; r < obs.rows(); ++r) {
        for (int i = 0; i < kObs; ++i) in << obs(r, i) << ' ';
        in << '\n';
      }
      if (mask)
        for (int r = 0; r < obs.rows(); ++r) {
          for (int i = 0; i < mask_width; ++i) in << int((*mask)[r * mask_width + i]) << ' ';
          in << '\n';
        }
    }
    const char* other = std::getenv("POLICY_PROBE_COMMAND");
    const std::string probe_command = other && *other ? other : POLICY_PROBE;
    const std::string command = probe_command + " '" + model + "' '" + input + "' > '" + output +
                                "' 2> '" + output + ".err'";
    const int status = std::system(command.c_str());
    EXPECT_EQ(status, 0) << command << "\n" << read_file(output + ".err");
    ProbeResult result;
    std::ifstream out(output);
    std::string line;
    while (std::getline(out, line)) {
      if (line.rfind("spec_json ", 0) == 0) {
        result.spec_json = line.substr(10);
      } else if (line.rfind("format_version ", 0) == 0) {
        result.format_version = std::stoi(line.substr(15));
      } else {
        const auto bar = line.find('|');
        std::istringstream c(line.substr(0, bar)), d(line.substr(bar + 1));
        result.continuous.emplace_back();
        result.discrete.emplace_back();
        float v;
        while (c >> v) result.continuous.back().push_back(v);
        int k;
        while (d >> k) result.discrete.back().push_back(k);
      }
    }
    return result;
  }

  // exports `net`, probes it with and without masks, and compares with the FastActor
  void check_export(const BehaviorSpec& spec, const PolicyNetwork& net,
                    const RunningNormalizer* norm, uint64_t seed) {
    const std::string model = (dir_ / "policy.pt").string();
    export_policy(*net, norm, spec, model);
    ASSERT_TRUE(fs::exists(model));
    EXPECT_FALSE(fs::exists(model + ".tmp"));
    FastActor actor;
    actor.copy_from(*net, norm);

    std::mt19937_64 rng(seed);
    std::normal_distribution<float> dist(0.f, 4.f);
    const int rows = 24, m = spec.action.mask_size(), k = spec.action.num_branches();
    const int c = spec.action.continuous_size;
    RowMatrix obs(rows, kObs);
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < kObs; ++i) obs(r, i) = dist(rng);
    std::vector<uint8_t> mask(rows * m, 1);
    for (int r = 0; r < rows; ++r) {
      int offset = 0;
      for (int n : spec.action.discrete_branches) {
        const int keep = int(rng() % n);
        for (int o = 0; o < n; ++o)
          if (o != keep && rng() % 2) mask[r * m + offset + o] = 0;
        offset += n;
      }
    }
    int clipped = 0, mask_changed = 0;
    std::vector<std::vector<int>> unmasked_choices;
    for (bool masked : {false, true}) {
      SCOPED_TRACE(masked ? "masked" : "no mask");
      ProbeResult got = probe(model, obs, masked && k > 0 ? &mask : nullptr, m);
      ASSERT_EQ(got.continuous.size(), size_t(rows));
      ActBatch det;
      actor.act(obs, masked && k > 0 ? mask.data() : nullptr, true, rng, det);
      for (int r = 0; r < rows; ++r) {
        ASSERT_EQ(got.continuous[r].size(), size_t(c));
        ASSERT_EQ(got.discrete[r].size(), size_t(k));
        for (int j = 0; j < c; ++j) {
          EXPECT_NEAR(got.continuous[r][j], clip_continuous_action(det.continuous(r, j)), 1e-5)
              << "row " << r << " dim " << j;
          clipped += std::abs(det.continuous(r, j)) > 3.f;
        }
        for (int br = 0; br < k; ++br) EXPECT_EQ(got.discrete[r][br], det.discrete(r, br));
      }
      if (!masked) unmasked_choices = got.discrete;
      if (masked)
        for (int r = 0; r < rows; ++r) mask_changed += got.discrete[r] != unmasked_choices[r];

      // spec_json names the behavior's observations and actions
      EXPECT_EQ(got.format_version, 1);
      Json json = JsonReader(got.spec_json).document();
      EXPECT_EQ(got.spec_json, behavior_spec_json(spec));
      EXPECT_EQ(json.at("name").text, "Probe \"Bot\"?team=0");
      ASSERT_EQ(json.at("observations").items.size(), 2u);
      EXPECT_EQ(json.at("observations").items[0].at("name").text, "pos");
      EXPECT_EQ(json.at("observations").items[0].at("kind").text, "vector");
      EXPECT_EQ(json.at("observations").items[1].at("kind").text, "grid");
      const auto& shape = json.at("observations").items[1].at("shape").items;
      ASSERT_EQ(shape.size(), 3u);
      EXPECT_EQ(shape[1].number, 2.0);
      EXPECT_EQ(json.at("action").at("continuous_size").number, c);
      const auto& branches = json.at("action").at("discrete_branches").items;
      ASSERT_EQ(branches.size(), size_t(k));
      for (int br = 0; br < k; ++br)
        EXPECT_EQ(branches[br].number, spec.action.discrete_branches[br]);
      EXPECT_EQ(json.at("agent_slots").number, 3.0);
    }
    // the inputs reach the interesting regions
    if (c > 0) {
      EXPECT_GT(clipped, 0);
    }
    if (k > 0) {
      EXPECT_GT(mask_changed, 0);
    }
  }

  fs::path dir_;
};

TEST_F(PolicyExportTest, HybridWithNormalizer) {
  BehaviorSpec spec = make_behavior(2, {3, 2});
  PolicyNetwork net = make_network(spec.action, Activation::kSwish, 21);
  RunningNormalizer norm = make_normalizer(22);
  check_export(spec, net, &norm, 23);
}

TEST_F(PolicyExportTest, ContinuousTanhWithoutNormalizer) {
  BehaviorSpec spec = make_behavior(3, {});
  PolicyNetwork net = make_network(spec.action, Activation::kTanh, 31);
  check_export(spec, net, nullptr, 33);
}

TEST_F(PolicyExportTest, DiscreteReluWithNormalizer) {
  BehaviorSpec spec = make_behavior(0, {4, 3});
  PolicyNetwork net = make_network(spec.action, Activation::kRelu, 41);
  RunningNormalizer norm = make_normalizer(42);
  check_export(spec, net, &norm, 43);
}

TEST(BehaviorSpecJsonTest, IsValidJsonWithEscapedNames) {
  BehaviorSpec spec = make_behavior(1, {2});
  spec.observations[0].name = "a\\b\n";
  Json json = JsonReader(behavior_spec_json(spec)).document();
  EXPECT_EQ(json.type, Json::kObject);
  EXPECT_EQ(json.at("observations").items.size(), 2u);
  EXPECT_THROW(JsonReader("{\"a\":1,}").document(), std::runtime_error);
}

}  // namespace
}  // namespace rlt
