// A small HTTP/1.1 server for `rlt replay`: answers GET requests for the files of one folder, plus
// named files mapped to other paths (the recording), on a local address. One request per
// connection, served in turn; enough for a viewer page and its scripts.
#pragma once

#include <cstdint>
#include <map>
#include <string>

namespace rlt {

class StaticHttpServer {
 public:
  // Serves the files under `root` ("/" is root/index.html). Binds `host`:`port` at once (port 0:
  // a free one); throws naming the address when it cannot.
  StaticHttpServer(std::string root, const std::string& host, int port);
  ~StaticHttpServer();
  StaticHttpServer(const StaticHttpServer&) = delete;
  StaticHttpServer& operator=(const StaticHttpServer&) = delete;

  // `url_path` (e.g. "/recording.json") answers with the file at `file`
  void map_file(const std::string& url_path, const std::string& file);

  int port() const { return port_; }

  // Answers requests until the process is stopped.
  [[noreturn]] void serve_forever();

  // Answers one connection (blocks until one arrives).
  void serve_one();

 private:
  void answer(int connection);

  std::string root_;
  std::map<std::string, std::string> mapped_;
  int socket_ = -1;
  int port_ = 0;
};

// the Content-Type for a file name's extension (text/javascript for .js, so browsers load modules)
std::string content_type_of(const std::string& path);

}  // namespace rlt
