// An episode as a replay viewer needs it: the bodies of the world, their poses at every physics
// frame and the events (grab, lock, tag, ...) that happened. Environments that support recording
// fill one EpisodeRecording per episode (Env::set_recording, Env::take_recording); `rlt eval
// --record FILE` writes them as JSON (format in docs/recording_format.md).
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
  // what the body sees: a cone of this full angle around its local +z axis, out to this range;
  // 0 for bodies that do not see
  float vision_cone_degrees = 0;
  float vision_range = 0;
};

// a hole between two areas of the world (a doorway, a window), fixed for the episode
struct RecordedOpening {
  std::string kind;               // "doorway" or "window"
  std::array<float, 3> centre{};  // centre of the hole (m)
  std::array<float, 3> normal{};  // unit, horizontal, pointing out of the enclosed area
  float width = 0, height = 0;    // size of the hole (m)
  bool open = true;               // false: filled by a wall chunk at this level
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
  // rewards paid in this frame (at decisions) by agent id; empty when every one is 0
  std::vector<float> rewards;        // [agents] each agent's own reward
  std::vector<float> group_rewards;  // [agents] its group's reward (MA-POCA)
};

struct EpisodeRecording {
  std::string env;
  float frame_rate = 0;  // frames per second
  std::vector<RecordedBody> bodies;
  std::vector<RecordedOpening> openings;  // indexed by the "closed" events
  std::vector<RecordedFrame> frames;
  std::vector<std::pair<std::string, float>> metrics;  // the episode's metrics, when known
};

}  // namespace rlt
