// Helpers of the tests that attack the server's connection handling
// (connection_guard_test, framing_guard_test, auth_throttle_test): the
// process's peak memory, gzip bodies made with zlib, raw connections from
// another loopback address (127.0.0.2 and up are this host too), and the
// server's /metrics once given series are in (also the feed-axis and
// parts routes' tests).
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <chrono>
#include <fstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace thermocomp::testing {

// The process's peak resident memory (VmHWM) in MiB; reset it with
// std::ofstream("/proc/self/clear_refs") << "5".
inline long PeakMb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6)) / 1024;
  }
  return 0;
}

// `repeat` copies of `piece`, compressed with gzip framing (zlib framing
// when `zlib_framing`), made piece by piece: a 512 MiB bomb takes little
// memory to make.
inline std::string Compressed(std::string_view piece, size_t repeat, bool zlib_framing = false) {
  z_stream z{};
  deflateInit2(&z, Z_BEST_COMPRESSION, Z_DEFLATED, zlib_framing ? 15 : 15 + 16, 9,
               Z_DEFAULT_STRATEGY);
  std::string out;
  char buffer[64 * 1024];
  for (size_t i = 0; i <= repeat; ++i) {
    const bool last = i == repeat;
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(piece.data()));
    z.avail_in = last ? 0 : static_cast<uInt>(piece.size());
    do {
      z.next_out = reinterpret_cast<Bytef*>(buffer);
      z.avail_out = sizeof buffer;
      deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
      out.append(buffer, sizeof buffer - z.avail_out);
    } while (z.avail_out == 0);
  }
  deflateEnd(&z);
  return out;
}

// A TCP connection to 127.0.0.1:port from `source` (another loopback
// address), for floods that must come from several clients.
class ConnectionFrom {
 public:
  ConnectionFrom(const std::string& source, int port) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in from{};
    from.sin_family = AF_INET;
    inet_pton(AF_INET, source.c_str(), &from.sin_addr);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (bind(fd_, reinterpret_cast<sockaddr*>(&from), sizeof from) != 0 ||
        connect(fd_, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
      close(fd_);
      fd_ = -1;
    }
  }
  ~ConnectionFrom() {
    if (fd_ >= 0) close(fd_);
  }
  ConnectionFrom(const ConnectionFrom&) = delete;
  ConnectionFrom& operator=(const ConnectionFrom&) = delete;

  bool ok() const { return fd_ >= 0 && !closed_; }
  bool Send(std::string_view bytes) {
    while (fd_ >= 0 && !bytes.empty()) {
      const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<size_t>(n));
    }
    return fd_ >= 0;
  }
  // Reads what has arrived without waiting; notes when the server closed.
  void Poll() {
    char buf[4096];
    while (fd_ >= 0 && !closed_) {
      const ssize_t n = recv(fd_, buf, sizeof buf, MSG_DONTWAIT);
      if (n > 0) {
        received_.append(buf, static_cast<size_t>(n));
      } else {
        if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) closed_ = true;
        return;
      }
    }
  }
  const std::string& received() const { return received_; }

 private:
  int fd_ = -1;
  bool closed_ = false;
  std::string received_;
};

// The text of GET /metrics from `client` (an httplib::Client) once it
// holds every line of `expected`, or the last one after a minute: a
// request is counted once its response is written, so a scrape on another
// connection may come first.
template <class Client>
std::string MetricsWith(Client& client, const std::vector<std::string>& expected) {
  std::string text;
  for (int i = 0; i < 600; ++i) {
    auto r = client.Get("/metrics");
    text = r ? r->body : "";
    bool all = true;
    for (const std::string& e : expected) all = all && text.find(e) != std::string::npos;
    if (all) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return text;
}

}  // namespace thermocomp::testing
