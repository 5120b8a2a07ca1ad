// Writes recorded episodes (rl/env_api/recording.h) as one JSON document; the format is described
// in docs/recording_format.md.
#pragma once

#include <memory>
#include <ostream>
#include <vector>

#include "rl/env_api/recording.h"

namespace rlt {

void write_recordings_json(std::ostream& out,
                           const std::vector<std::shared_ptr<EpisodeRecording>>& episodes);

}  // namespace rlt
