#include "apps/static_http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace fs = std::filesystem;

namespace rlt {

std::string content_type_of(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".png") return "image/png";
  if (ext == ".svg") return "image/svg+xml";
  return "application/octet-stream";
}

StaticHttpServer::StaticHttpServer(std::string root, const std::string& host, int port)
    : root_(std::move(root)) {
  socket_ = ::socket(AF_INET, SOCK_STREAM, 0);
  if (socket_ < 0)
    throw std::runtime_error(std::string("cannot open a socket: ") + std::strerror(errno));
  const int yes = 1;
  ::setsockopt(socket_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(uint16_t(port));
  const std::string where = host + ":" + std::to_string(port);
  if (::inet_pton(AF_INET, host.c_str(), &address.sin_addr) != 1) {
    ::close(socket_);
    throw std::runtime_error("'" + host + "' is not an IPv4 address (e.g. 127.0.0.1)");
  }
  if (::bind(socket_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      ::listen(socket_, 16) != 0) {
    const std::string why = std::strerror(errno);
    ::close(socket_);
    throw std::runtime_error("cannot listen on " + where + ": " + why);
  }
  socklen_t length = sizeof address;
  ::getsockname(socket_, reinterpret_cast<sockaddr*>(&address), &length);
  port_ = ntohs(address.sin_port);
}

StaticHttpServer::~StaticHttpServer() {
  if (socket_ >= 0) ::close(socket_);
}

void StaticHttpServer::map_file(const std::string& url_path, const std::string& file) {
  mapped_[url_path] = file;
}

void StaticHttpServer::serve_forever() {
  for (;;) serve_one();
}

void StaticHttpServer::serve_one() {
  const int connection = ::accept(socket_, nullptr, nullptr);
  if (connection < 0) return;
  answer(connection);
  ::close(connection);
}

namespace {

void send_all(int connection, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t sent = ::send(connection, data, size, MSG_NOSIGNAL);
    if (sent <= 0) return;  // the browser went away
    data += sent;
    size -= size_t(sent);
  }
}

// `with_body` false answers HEAD: the same head, no body
void respond(int connection, int status, const std::string& reason, const std::string& type,
             const std::string& body, bool with_body = true) {
  std::ostringstream head;
  head << "HTTP/1.1 " << status << ' ' << reason << "\r\nContent-Type: " << type
       << "\r\nContent-Length: " << body.size()
       << "\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n";
  const std::string text = head.str();
  send_all(connection, text.data(), text.size());
  if (with_body) send_all(connection, body.data(), body.size());
}

}  // namespace

void StaticHttpServer::answer(int connection) {
  // the request head, up to the blank line
  std::string request;
  char buffer[4096];
  while (request.find("\r\n\r\n") == std::string::npos && request.size() < 65536) {
    const ssize_t got = ::recv(connection, buffer, sizeof buffer, 0);
    if (got <= 0) return;
    request.append(buffer, size_t(got));
  }
  std::istringstream line(request.substr(0, request.find("\r\n")));
  std::string method, target;
  line >> method >> target;
  if (method != "GET" && method != "HEAD") {
    respond(connection, 405, "Method Not Allowed", "text/plain", "only GET\n");
    return;
  }
  std::string path = target.substr(0, target.find_first_of("?#"));
  if (path == "/") path = "/index.html";
  std::string file;
  if (auto it = mapped_.find(path); it != mapped_.end()) {
    file = it->second;
  } else if (path.find("..") == std::string::npos && path.rfind('/', 0) == 0) {
    file = root_ + path;  // nothing outside the root: ".." never reaches here
  }
  std::ifstream in(file, std::ios::binary);
  if (file.empty() || !fs::is_regular_file(file) || !in) {
    respond(connection, 404, "Not Found", "text/plain", "not found: " + path + "\n");
    return;
  }
  std::ostringstream body;
  body << in.rdbuf();
  respond(connection, 200, "OK", content_type_of(file), body.str(), method != "HEAD");
}

}  // namespace rlt
