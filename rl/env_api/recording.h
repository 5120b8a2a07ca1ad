// An episode as a replay viewer needs it: the bodies of the world, their poses at every physics
// frame and the events (grab, lock, tag, ...) that happened. Environments that support recording
// fill one EpisodeRecording per episode (Env::set_recording, Env::take_recording); `rlt eval
// --record FILE` writes them as JSON (format in apps/record_format.md).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rlt {

// one body, fixed for the episode
struct RecordedBody {
  std::string kind;               // e.g. "wall", "prop", "obstacle", "hider", "seeker"
  std::string shape;              // "box" or "sphere"
  std::array<float, 3> size{};    // box: full extents (m); sphere: diameter in all three
  int agent_id = -1;              // the agent that flies it, or -1
  bool dynamic = true;            // false for bodies that never move (walls): pose of frame 0
};

// something that happened in a frame; `body` and `other` index RecordedBody, -1 when unused
struct RecordedEvent {
  std::string type;  // e.g. "grab", "release", "lock", "unlock", "tag", "closed", "prep_end"
  int body = -1;     // who did it (or what it happened to)
  int other = -1;    // what it was done to
};

// poses of every body at one physics frame: [num_bodies] of x, y, z, qx, qy, qz, qw; a body that is
// not in the world (not yet, or no longer) has present = 0
struct RecordedFrame {
  std::vector<std::array<float, 7>> poses;  // [num_bodies]
  std::vector<uint8_t> present;             // [num_bodies]
  std::vector<RecordedEvent> events;
};

struct EpisodeRecording {
  std::string env;
  float frame_rate = 0;  // frames per second
  std::vector<RecordedBody> bodies;
  std::vector<RecordedFrame> frames;
  std::vector<std::pair<std::string, float>> metrics;  // the episode's metrics, when known
};

}  // namespace rlt
