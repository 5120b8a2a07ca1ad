// rlt replay: serves the 3D replay viewer (viewer/) and a recording on localhost.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "apps/static_http_server.h"

namespace fs = std::filesystem;

namespace rlt {

const char* const kReplayHelp = R"(Usage: rlt replay FILE [options]

Plays a recorded episode (rlt eval --record FILE; format in docs/recording_format.md) in a 3D
viewer in the browser: the arena, the room and its openings, the props (locked ones marked), the
drones coloured by team with their vision cones, a timeline with play, pause and scrubbing, the
phase and every agent's rewards so far. Serves the page on this machine and prints its address;
the page and three.js come with rlt (nothing is fetched from the internet). Ctrl-C stops.

Options:
  --port P          port to listen on (default 8080; 0 picks a free one)
  --host ADDRESS    IPv4 address to listen on (default 127.0.0.1: this machine only)
  --viewer-dir DIR  the viewer's files (default: next to rlt, as the build or install put them)

Example:
  rlt eval results/hide_and_seek --episodes 1 --record replay.json
  rlt replay replay.json          # then open the printed address
)";

namespace {

// the viewer's folder: the build puts it at build/viewer/site (rlt is build/apps/rlt), the
// install at <prefix>/share/rlt/viewer (rlt is <prefix>/bin/rlt)
std::string find_viewer_dir() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    for (const fs::path& candidate :
         {exe.parent_path() / "../viewer/site", exe.parent_path() / "../share/rlt/viewer"})
      if (fs::exists(candidate / "index.html")) return fs::canonical(candidate).string();
  }
  throw std::runtime_error(
      "the replay viewer's files are not next to rlt (build/viewer/site or share/rlt/viewer): "
      "the build makes them when npm is installed (Debian: apt-get install npm); or pass "
      "--viewer-dir");
}

// a recording starts with {"format":"rlt-recording" (apps/recording_json.cpp)
void check_recording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!fs::is_regular_file(path) || !in) throw std::runtime_error("cannot read " + path);
  std::string head(256, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(in.gcount()));
  if (head.find("\"rlt-recording\"") == std::string::npos)
    throw std::runtime_error(
        path +
        " is not an rlt recording (it does not start with "
        "{\"format\":\"rlt-recording\"); write one with rlt eval --record FILE");
}

}  // namespace

int run_replay(const std::vector<std::string>& args) {
  CommandLine cl(args, {}, {"--port", "--host", "--viewer-dir"});
  if (cl.positional().size() != 1) throw UsageError("expected one recording FILE");
  const std::string file = cl.positional()[0];
  const int port = int(cl.integer("--port", 8080, 0));
  if (port > 65535) throw UsageError("--port must be at most 65535");
  check_recording(file);
  std::string viewer = cl.value("--viewer-dir");
  if (viewer.empty()) {
    viewer = find_viewer_dir();
  } else if (!fs::exists(fs::path(viewer) / "index.html")) {
    throw std::runtime_error("--viewer-dir " + viewer + " has no index.html");
  }
  const std::string host = cl.value("--host", "127.0.0.1");
  StaticHttpServer server(viewer, host, port);
  server.map_file("/recording.json", fs::absolute(file).string());
  std::cout << "Replay of " << file << ": http://" << host << ':' << server.port()
            << "/  (Ctrl-C stops)" << std::endl;
  server.serve_forever();
}

}  // namespace rlt
