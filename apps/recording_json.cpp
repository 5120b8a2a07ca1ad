#include "apps/recording_json.h"

#include <cmath>
#include <cstdio>

#include "rl/core/json.h"

namespace rlt {

namespace {

// a coordinate with 4 decimals (0.1 mm, 1e-4 of a unit quaternion): small files, exact enough
void write_value(std::ostream& out, float v) {
  if (!std::isfinite(v)) {
    out << "null";
    return;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.4f", v);
  // trim trailing zeros: "1.5000" -> "1.5", "2.0000" -> "2"
  std::string s(text);
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  out << s;
}

// [v0,v1,...] with write_value's precision: sizes, positions, poses, rewards
void write_numbers(std::ostream& out, const float* values, size_t count) {
  out << '[';
  for (size_t k = 0; k < count; ++k) {
    if (k) out << ',';
    write_value(out, values[k]);
  }
  out << ']';
}

template <size_t N>
void write_numbers(std::ostream& out, const std::array<float, N>& values) {
  write_numbers(out, values.data(), N);
}

void write_numbers(std::ostream& out, const std::vector<float>& values) {
  write_numbers(out, values.data(), values.size());
}

void write_episode(std::ostream& out, const EpisodeRecording& e) {
  out << "{\"env\":" << json_string(e.env) << ",\"frame_rate\":" << json_number(e.frame_rate)
      << ",\"metrics\":{";
  for (size_t i = 0; i < e.metrics.size(); ++i)
    out << (i ? "," : "") << json_string(e.metrics[i].first) << ':' << json_number(e.metrics[i].second);
  out << "},\"bodies\":[";
  std::vector<size_t> dynamic;
  for (size_t i = 0; i < e.bodies.size(); ++i) {
    const RecordedBody& b = e.bodies[i];
    if (b.dynamic) dynamic.push_back(i);
    out << (i ? ",\n" : "\n") << "{\"kind\":" << json_string(b.kind)
        << ",\"shape\":" << json_string(b.shape) << ",\"size\":";
    write_numbers(out, b.size);
    out << ",\"agent_id\":" << b.agent_id << ",\"dynamic\":" << (b.dynamic ? "true" : "false");
    if (b.vision_range > 0) {
      out << ",\"vision\":{\"cone_degrees\":";
      write_value(out, b.vision_cone_degrees);
      out << ",\"range\":";
      write_value(out, b.vision_range);
      out << '}';
    }
    out << ",\"pose\":";
    if (!e.frames.empty() && e.frames[0].present.at(i))
      write_numbers(out, e.frames[0].poses[i]);
    else
      out << "null";
    out << '}';
  }
  out << "],\"openings\":[";
  for (size_t i = 0; i < e.openings.size(); ++i) {
    const RecordedOpening& o = e.openings[i];
    out << (i ? "," : "") << "\n{\"kind\":" << json_string(o.kind) << ",\"centre\":";
    write_numbers(out, o.centre);
    out << ",\"normal\":";
    write_numbers(out, o.normal);
    out << ",\"width\":";
    write_value(out, o.width);
    out << ",\"height\":";
    write_value(out, o.height);
    out << ",\"open\":" << (o.open ? "true" : "false") << '}';
  }
  out << "],\"dynamic_bodies\":[";
  for (size_t j = 0; j < dynamic.size(); ++j) out << (j ? "," : "") << dynamic[j];
  out << "],\"frames\":[";
  for (size_t f = 0; f < e.frames.size(); ++f) {
    const RecordedFrame& frame = e.frames[f];
    out << (f ? ",\n" : "\n") << "{\"poses\":[";
    for (size_t j = 0; j < dynamic.size(); ++j) {
      if (j) out << ',';
      if (frame.present.at(dynamic[j]))
        write_numbers(out, frame.poses[dynamic[j]]);
      else
        out << "null";
    }
    out << ']';
    if (!frame.events.empty()) {
      out << ",\"events\":[";
      for (size_t k = 0; k < frame.events.size(); ++k) {
        const RecordedEvent& ev = frame.events[k];
        out << (k ? "," : "") << "{\"type\":" << json_string(ev.type) << ",\"body\":" << ev.body
            << ",\"other\":" << ev.other << '}';
      }
      out << ']';
    }
    if (!frame.rewards.empty()) {
      out << ",\"rewards\":";
      write_numbers(out, frame.rewards);
      out << ",\"group_rewards\":";
      write_numbers(out, frame.group_rewards);
    }
    out << '}';
  }
  out << "]}";
}

}  // namespace

void write_recordings_json(std::ostream& out,
                           const std::vector<std::shared_ptr<EpisodeRecording>>& episodes) {
  out << "{\"format\":\"rlt-recording\",\"version\":2,\"episodes\":[";
  for (size_t i = 0; i < episodes.size(); ++i) {
    out << (i ? ",\n" : "\n");
    write_episode(out, *episodes[i]);
  }
  out << "]}\n";
}

}  // namespace rlt
