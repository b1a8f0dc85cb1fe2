// Raw HTTP on a loopback socket, for requests no well-behaved client sends:
// invalid UTF-8 in the path or headers, duplicate headers, chunked bodies
// of any size, bytes trickled slowly, connections held open.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <string>
#include <string_view>

namespace thermocomp::testing {

class RawConnection {
 public:
  explicit RawConnection(int port) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      close(fd_);
      fd_ = -1;
    }
  }
  ~RawConnection() {
    if (fd_ >= 0) close(fd_);
  }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  bool ok() const { return fd_ >= 0; }
  // False once the peer closed or reset the connection.
  bool Send(std::string_view bytes) {
    while (!bytes.empty()) {
      ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<size_t>(n));
    }
    return true;
  }
  // Reads until one whole response (head and Content-Length body) arrived,
  // the peer closed, or `timeout` passed.
  std::string ReadResponse(std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!Complete()) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) break;
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
      char buf[65536];
      ssize_t n = recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) {
        closed_ = true;
        break;
      }
      in_.append(buf, static_cast<size_t>(n));
    }
    std::string out = in_.substr(0, ResponseLength());
    in_.erase(0, out.size());
    return out;
  }
  // Whether the peer closed the connection within `timeout` (what it sent
  // before closing is read and dropped).
  bool ClosedWithin(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!closed_) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      pollfd p{fd_, POLLIN, 0};
      if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
      char buf[4096];
      if (recv(fd_, buf, sizeof buf, 0) <= 0) closed_ = true;
    }
    return true;
  }

  // The status code of a response text, or 0.
  static int Status(const std::string& response) {
    if (response.rfind("HTTP/1.", 0) != 0 || response.size() < 12) return 0;
    return std::atoi(response.c_str() + 9);
  }
  static std::string Body(const std::string& response) {
    auto head = response.find("\r\n\r\n");
    return head == std::string::npos ? "" : response.substr(head + 4);
  }

 private:
  // Length of the first response in in_ once its head arrived (head plus
  // Content-Length body); everything received when the peer closed first.
  size_t ResponseLength() const {
    auto head = in_.find("\r\n\r\n");
    if (head == std::string::npos) return in_.size();
    size_t length = 0;
    const std::string lower = Lower(in_.substr(0, head));
    if (auto cl = lower.find("\r\ncontent-length:"); cl != std::string::npos) {
      length = std::strtoul(lower.c_str() + cl + 17, nullptr, 10);
    }
    return std::min(in_.size(), head + 4 + length);
  }
  bool Complete() const {
    auto head = in_.find("\r\n\r\n");
    if (head == std::string::npos) return false;
    const std::string lower = Lower(in_.substr(0, head));
    size_t length = 0;
    if (auto cl = lower.find("\r\ncontent-length:"); cl != std::string::npos) {
      length = std::strtoul(lower.c_str() + cl + 17, nullptr, 10);
    }
    return in_.size() >= head + 4 + length;
  }
  static std::string Lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  }

  int fd_ = -1;
  bool closed_ = false;
  std::string in_;
};

// One request on a fresh connection; the whole response text.
inline std::string RawRequest(int port, std::string_view bytes) {
  RawConnection c(port);
  if (!c.ok() || !c.Send(bytes)) return "";
  return c.ReadResponse();
}

}  // namespace thermocomp::testing
