#include "api/guarded_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string_view>
#include <tuple>

namespace thermocomp::api {
namespace {

using Clock = std::chrono::steady_clock;

// A head that takes longer than this to arrive is not a client on a LAN
// sending one packet: under pressure its connection may be closed.
constexpr auto kSlowHead = std::chrono::milliseconds(250);
// The largest request head (request line and headers) read at all.
constexpr size_t kMaxHeadBytes = 64 * 1024;
constexpr int kListenBacklog = 1024;

int MsUntil(Clock::time_point deadline) {
  auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return ms < 0 ? 0 : static_cast<int>(std::min<int64_t>(ms, 1 << 30));
}

// Waits until fd has `events` or the deadline passed; false on timeout or
// an error (a shut-down socket reports readable and then reads 0).
bool WaitFor(int fd, short events, Clock::time_point deadline) {
  while (true) {
    pollfd p{fd, events, 0};
    const int r = poll(&p, 1, MsUntil(deadline));
    if (r > 0) return true;
    if (r == 0) return false;
    if (errno != EINTR) return false;
  }
}

std::pair<std::string, int> Address(int fd, bool peer) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  const int r = peer ? getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len)
                     : getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  if (r != 0) return {"", 0};
  char text[INET6_ADDRSTRLEN] = {0};
  if (addr.ss_family == AF_INET) {
    auto* a = reinterpret_cast<sockaddr_in*>(&addr);
    inet_ntop(AF_INET, &a->sin_addr, text, sizeof text);
    return {text, ntohs(a->sin_port)};
  }
  if (addr.ss_family == AF_INET6) {
    auto* a = reinterpret_cast<sockaddr_in6*>(&addr);
    inet_ntop(AF_INET6, &a->sin6_addr, text, sizeof text);
    return {text, ntohs(a->sin6_port)};
  }
  return {"", 0};
}

bool SendAll(int fd, const char* data, size_t size, Clock::time_point deadline) {
  while (size > 0) {
    if (!WaitFor(fd, POLLOUT, deadline)) return false;
    const ssize_t n = send(fd, data, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

// One connection's bytes, request by request. The read buffer lives as
// long as the connection, so bytes of a pipelined next request are kept.
// Each request's head must arrive within the header timeout of its first
// byte and its body within the body timeout; body bytes beyond the limit
// end the request.
class ConnectionStream : public httplib::Stream {
 public:
  ConnectionStream(int fd, const ConnectionLimits& limits, ConnectionRegistry& registry)
      : fd_(fd), limits_(limits), registry_(registry) {
    std::tie(remote_ip_, remote_port_) = Address(fd, true);
    std::tie(local_ip_, local_port_) = Address(fd, false);
  }

  // Waits for the next request's first byte; false when the connection
  // was closed, went idle too long or was evicted. The head must then
  // arrive within `head_timeout`.
  bool AwaitRequest(std::chrono::milliseconds head_timeout) {
    if (pos_ == len_) {
      const auto deadline = Clock::now() + std::chrono::seconds(limits_.keep_alive_timeout_s);
      if (!WaitFor(fd_, POLLIN, deadline) || !Fill()) return false;
    }
    in_head_ = true;
    head_bytes_ = body_bytes_ = 0;
    line_end_ = 0;
    too_large_ = timed_out_ = close_after_ = false;
    deadline_ = Clock::now() + head_timeout;
    return true;
  }

  bool is_readable() const override { return pos_ < len_ || WaitFor(fd_, POLLIN, deadline_); }
  bool is_writable() const override {
    return WaitFor(fd_, POLLOUT, Clock::now() + std::chrono::seconds(limits_.write_timeout_s));
  }
  ssize_t read(char* ptr, size_t size) override {
    if (pos_ == len_) {
      if (!WaitFor(fd_, POLLIN, deadline_)) {
        timed_out_ = close_after_ = true;
        return -1;
      }
      if (!Fill()) return -1;
    }
    size_t n = std::min(size, len_ - pos_);
    if (in_head_) {
      n = ConsumeHead(n);  // head bytes only: a read never spans head and body
      if (head_bytes_ > kMaxHeadBytes) return -1;
    } else if ((body_bytes_ += n) > limits_.max_body_bytes) {
      too_large_ = close_after_ = true;
      return -1;
    }
    std::memcpy(ptr, buf_ + pos_, n);
    pos_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    const auto deadline = Clock::now() + std::chrono::seconds(limits_.write_timeout_s);
    return SendAll(fd_, ptr, size, deadline) ? static_cast<ssize_t>(size) : -1;
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = remote_ip_;
    port = remote_port_;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = local_ip_;
    port = local_port_;
  }
  socket_t socket() const override { return fd_; }

  const std::string& client() const { return remote_ip_; }
  // Whether the buffered request line is GET /healthz or GET /readyz.
  bool IsHealthProbe() const {
    const std::string_view line(buf_ + pos_, len_ - pos_);
    for (std::string_view probe : {"GET /healthz ", "GET /readyz "}) {
      if (line.substr(0, probe.size()) == probe) return true;
    }
    return false;
  }
  bool too_large() const { return too_large_; }
  bool timed_out() const { return timed_out_; }
  bool close_after() const { return close_after_; }
  void set_close_after() { close_after_ = true; }

 private:
  bool Fill() {
    ssize_t n;
    do {
      n = recv(fd_, buf_, sizeof buf_, 0);
    } while (n < 0 && errno == EINTR);
    if (n <= 0) return false;
    pos_ = 0;
    len_ = static_cast<size_t>(n);
    return true;
  }
  // Scans up to n buffered head bytes for the blank line that ends the
  // head; returns how many of them belong to the head (all n while it
  // goes on). From the head's end on, the request is busy and its body
  // has the body timeout.
  size_t ConsumeHead(size_t n) {
    for (size_t i = 0; i < n; ++i) {
      const char c = buf_[pos_ + i];
      ++head_bytes_;
      if (c == '\n') {
        if (line_end_ > 0) {  // an empty line: the head is complete
          in_head_ = false;
          registry_.Set(fd_, ConnectionRegistry::State::kBusy);
          deadline_ = Clock::now() + std::chrono::seconds(limits_.body_timeout_s);
          return i + 1;
        }
        line_end_ = 1;
      } else if (c != '\r') {
        line_end_ = 0;
      }
    }
    return n;
  }

  int fd_;
  const ConnectionLimits& limits_;
  ConnectionRegistry& registry_;
  std::string remote_ip_, local_ip_;
  int remote_port_ = 0, local_port_ = 0;
  char buf_[8192];
  size_t pos_ = 0, len_ = 0;
  bool in_head_ = true;
  int line_end_ = 0;  // 1 right after a line feed
  size_t head_bytes_ = 0, body_bytes_ = 0;
  bool too_large_ = false, timed_out_ = false, close_after_ = false;
  Clock::time_point deadline_;
};

thread_local ConnectionStream* t_stream = nullptr;

void RejectConnection(int fd, const ConnectionLimits& limits) {
  static const std::string body =
      "{\"type\":\"about:blank\",\"title\":\"Service Unavailable\",\"status\":503,"
      "\"detail\":\"too many connections from this client: close idle ones or retry\"}";
  const std::string response =
      "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/problem+json\r\n"
      "Retry-After: 1\r\nConnection: close\r\nContent-Length: " +
      std::to_string(body.size()) + "\r\n\r\n" + body;
  SendAll(fd, response.data(), response.size(),
          Clock::now() + std::chrono::seconds(limits.write_timeout_s));
}

}  // namespace

// ------------------------------------------------------------ registry

bool ConnectionRegistry::Admit(int fd, const std::string& client) {
  std::lock_guard<std::mutex> lock(mutex_);
  int held = 0;
  for (const auto& [other, e] : open_) held += e.client == client;
  if (held >= limits_.max_connections_per_client && !EvictLocked(client)) return false;
  open_[fd] = {client, State::kIdle, Clock::now()};
  return true;
}

void ConnectionRegistry::Set(int fd, State state) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = open_.find(fd);
  if (it == open_.end() || it->second.state == state) return;
  it->second.state = state;
  it->second.since = Clock::now();
}

void ConnectionRegistry::Remove(int fd) {
  std::lock_guard<std::mutex> lock(mutex_);
  open_.erase(fd);
}

bool ConnectionRegistry::EvictOne(const std::string& client) {
  std::lock_guard<std::mutex> lock(mutex_);
  return EvictLocked(client);
}

bool ConnectionRegistry::EvictLocked(const std::string& client) {
  const auto now = Clock::now();
  auto victim = open_.end();
  // Lower is a better victim; -1 not at all. Nothing is closed within
  // kSlowHead of its last change: a connection just accepted, or idle
  // between two requests of a client that is still talking, is spared.
  auto rank = [&](const Entry& e) {
    if (now - e.since < kSlowHead) return -1;
    if (e.state == State::kHead) return 0;
    if (e.state == State::kIdle) return 1;
    return -1;
  };
  for (auto it = open_.begin(); it != open_.end(); ++it) {
    if (!client.empty() && it->second.client != client) continue;
    const int r = rank(it->second);
    if (r < 0) continue;
    if (victim == open_.end() || r < rank(victim->second) ||
        (r == rank(victim->second) && it->second.since < victim->second.since)) {
      victim = it;
    }
  }
  if (victim == open_.end()) return false;
  // The owner's wait wakes up, reads end of file and closes the socket; the
  // entry goes now, so the descriptor is never shut down twice.
  ::shutdown(victim->first, SHUT_RDWR);
  open_.erase(victim);
  return true;
}

void ConnectionRegistry::CloseAll() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [fd, e] : open_) ::shutdown(fd, SHUT_RDWR);
  open_.clear();
}

size_t ConnectionRegistry::size() {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_.size();
}

// ------------------------------------------------------------ task queue

GuardedTaskQueue::GuardedTaskQueue(int workers, ConnectionRegistry& registry)
    : registry_(registry) {
  for (int i = 0; i < workers; ++i) threads_.emplace_back([this] { Work(); });
}

void GuardedTaskQueue::enqueue(std::function<void()> fn) {
  bool wait = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(fn));
    wait = static_cast<int>(jobs_.size()) > idle_;
  }
  cv_.notify_one();
  if (wait) registry_.EvictOne();
}

void GuardedTaskQueue::on_idle() {
  // Connections still waiting for a worker: make room for them.
  size_t waiting = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (static_cast<int>(jobs_.size()) > idle_) waiting = jobs_.size() - idle_;
  }
  for (size_t i = 0; i < waiting && registry_.EvictOne(); ++i) {
  }
}

void GuardedTaskQueue::shutdown() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  for (auto& t : threads_) t.join();
}

void GuardedTaskQueue::Work() {
  while (true) {
    std::function<void()> fn;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      ++idle_;
      cv_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
      --idle_;
      if (jobs_.empty()) return;  // stopping
      // Adaptive LIFO: while connections queue up (a flood), the newest is
      // served first. It is the one most likely to have a client still
      // waiting (a health probe, a retry); the flood's old ones wait.
      if (jobs_.size() > threads_.size()) {
        fn = std::move(jobs_.back());
        jobs_.pop_back();
      } else {
        fn = std::move(jobs_.front());
        jobs_.pop_front();
      }
    }
    fn();
  }
}

// ------------------------------------------------------------ server

GuardedServer::GuardedServer(const ConnectionLimits& limits) : limits_(limits), registry_(limits_) {
  new_task_queue = [this] { return new GuardedTaskQueue(limits_.workers, registry_); };
  // The accept loop wakes this often to make room for waiting connections.
  set_idle_interval(0, 200000);
  set_payload_max_length(limits_.max_body_bytes);
}

void GuardedServer::Shutdown() {
  stop();
  registry_.CloseAll();
}

bool GuardedServer::BodyTooLarge() {
  return t_stream && t_stream->too_large();
}

bool GuardedServer::TimedOut() {
  return t_stream && t_stream->timed_out();
}

void GuardedServer::CloseAfterResponse() {
  if (t_stream) t_stream->set_close_after();
}

bool GuardedServer::Listen(const std::string& host, int port, int* bound_port) {
  *bound_port = port == 0 ? bind_to_any_port(host) : (bind_to_port(host, port) ? port : -1);
  if (*bound_port < 0) return false;
  // cpp-httplib listens with a backlog of 5: a burst of clients (a line
  // reconnecting after a network blip) would be dropped by the kernel.
  ::listen(svr_sock_, kListenBacklog);
  return true;
}

bool GuardedServer::process_and_close_socket(socket_t sock) {
  ConnectionStream stream(sock, limits_, registry_);
  bool ok = false;
  if (svr_sock_ == INVALID_SOCKET) {
    RejectConnection(sock, limits_);
  } else if (!registry_.Admit(sock, stream.client())) {
    // Beyond its share a client is served its health probes, once per
    // connection, so monitoring on the same host keeps working; anything
    // else gets 503.
    bool closed = false;
    if (stream.AwaitRequest(kSlowHead) && stream.IsHealthProbe()) {
      t_stream = &stream;
      ok = process_request(stream, true, closed, nullptr);
      t_stream = nullptr;
    } else {
      RejectConnection(sock, limits_);
    }
  } else {
    for (size_t left = keep_alive_max_count_; left > 0 && svr_sock_ != INVALID_SOCKET; --left) {
      registry_.Set(sock, ConnectionRegistry::State::kIdle);
      if (!stream.AwaitRequest(std::chrono::seconds(limits_.header_timeout_s))) break;
      registry_.Set(sock, ConnectionRegistry::State::kHead);
      bool closed = false;
      t_stream = &stream;
      ok = process_request(stream, left == 1 || svr_sock_ == INVALID_SOCKET, closed, nullptr);
      t_stream = nullptr;
      if (!ok || closed || stream.close_after()) break;
    }
    registry_.Remove(sock);
  }
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
  return ok;
}

}  // namespace thermocomp::api
