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

#include "api/body_guard.h"
#include "api/problem.h"

namespace thermocomp::api {
namespace {

using Clock = std::chrono::steady_clock;
using Ms = std::chrono::milliseconds;

// The largest request head (request line and headers) read at all.
constexpr size_t kMaxHeadBytes = 64 * 1024;
// The longest header line cpp-httplib reads (CPPHTTPLIB_HEADER_MAX_LENGTH).
constexpr size_t kMaxHeaderLine = 8192;
constexpr int kListenBacklog = 1024;

int MsUntil(Clock::time_point deadline) {
  auto ms = std::chrono::duration_cast<Ms>(deadline - Clock::now()).count();
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

// The syntax of a chunked body (RFC 9112 7.1), over its bytes as they are
// read: cpp-httplib takes a chunk-size line that is not hex and chunk data
// that CRLF does not follow, and reads what comes after as the next
// request (a smuggled one, behind a proxy that framed it otherwise).
class ChunkedSyntax {
 public:
  // False at the first byte that breaks the syntax; the body is then
  // refused and the connection closed.
  bool Accept(const char* p, size_t n) {
    for (size_t i = 0; i < n; ++i) {
      if (state_ == State::kData) {
        const size_t take = static_cast<size_t>(std::min<uint64_t>(left_, n - i));
        left_ -= take;
        i += take - 1;
        if (left_ == 0) state_ = State::kDataCr;
        continue;
      }
      if (!Step(p[i])) return false;
    }
    return true;
  }

 private:
  enum class State {
    kSize,
    kExt,
    kSizeLf,
    kData,
    kDataCr,
    kDataLf,
    kTrailer,
    kField,
    kFieldLf,
    kEndLf,
    kDone
  };
  static int Hex(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  }
  static bool Control(char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\t') || u == 0x7F;
  }
  bool Step(char c) {
    switch (state_) {
      case State::kSize:
        if (const int v = Hex(c); v >= 0) {
          // 15 hex digits are beyond any body this server takes.
          if (++digits_ > 15) return false;
          size_ = size_ * 16 + static_cast<uint64_t>(v);
          return true;
        }
        if (digits_ == 0) return false;
        if (c == ';' || c == ' ' || c == '\t') return (state_ = State::kExt), true;
        return c == '\r' && ((state_ = State::kSizeLf), true);
      case State::kExt:
        if (c == '\r') return (state_ = State::kSizeLf), true;
        return !Control(c);
      case State::kSizeLf:
        if (c != '\n') return false;
        left_ = size_;
        state_ = size_ == 0 ? State::kTrailer : State::kData;
        return true;
      case State::kData:
        return false;  // consumed in Accept
      case State::kDataCr:
        return c == '\r' && ((state_ = State::kDataLf), true);
      case State::kDataLf:
        if (c != '\n') return false;
        size_ = 0;
        digits_ = 0;
        state_ = State::kSize;
        return true;
      case State::kTrailer:
        if (c == '\r') return (state_ = State::kEndLf), true;
        return !Control(c) && ((state_ = State::kField), true);
      case State::kField:
        if (c == '\r') return (state_ = State::kFieldLf), true;
        return !Control(c);
      case State::kFieldLf:
        return c == '\n' && ((state_ = State::kTrailer), true);
      case State::kEndLf:
        return c == '\n' && ((state_ = State::kDone), true);
      case State::kDone:
        return false;  // the body ended: no byte of it is left to read
    }
    return false;
  }

  State state_ = State::kSize;
  uint64_t size_ = 0, left_ = 0;
  int digits_ = 0;
};

// One connection's bytes, request by request. The read buffer lives as
// long as the connection, so bytes of a pipelined next request are kept.
// Each request's head must arrive within the header timeout of its first
// byte and its body by its deadline (ExpectBody); body bytes beyond the
// limit end the request.
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
  bool AwaitRequest(Ms head_timeout) {
    if (pos_ == len_) {
      const auto deadline = Clock::now() + std::chrono::seconds(limits_.keep_alive_timeout_s);
      if (!WaitFor(fd_, POLLIN, deadline) || !Fill()) return false;
    }
    in_head_ = true;
    head_bytes_ = body_bytes_ = written_ = 0;
    line_end_ = 0;
    line_bytes_ = 0;
    head_line_ = 0;
    head_too_large_ = GuardedServer::HeadTooLarge::kNo;
    chunked_ = too_large_ = timed_out_ = close_after_ = false;
    chunk_syntax_ = ChunkedSyntax();
    deadline_ = Clock::now() + head_timeout;
    return true;
  }

  // The body's deadline: the grace plus the body at the minimum rate,
  // counted from the head's end, never beyond the body timeout.
  void ExpectBody(uint64_t content_length, bool chunked) {
    chunked_ = chunked;
    if (!in_head_) deadline_ = BodyDeadline(chunked ? body_bytes_ : content_length);
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
      if (head_too_large_ != GuardedServer::HeadTooLarge::kNo) close_after_ = true;
      if (head_bytes_ > kMaxHeadBytes) return -1;
    } else {
      if ((body_bytes_ += n) > limits_.max_body_bytes) {
        too_large_ = close_after_ = true;
        return -1;
      }
      // A chunked body's deadline grows with what has arrived; its framing
      // is checked as it is read.
      if (chunked_) {
        if (!chunk_syntax_.Accept(buf_ + pos_, n)) {
          close_after_ = true;
          return -1;
        }
        deadline_ = BodyDeadline(body_bytes_);
      }
    }
    std::memcpy(ptr, buf_ + pos_, n);
    pos_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    const auto deadline = Clock::now() + std::chrono::seconds(limits_.write_timeout_s);
    if (!SendAll(fd_, ptr, size, deadline)) return -1;
    written_ += size;
    return static_cast<ssize_t>(size);
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
  GuardedServer::HeadTooLarge head_too_large() const { return head_too_large_; }
  bool too_large() const { return too_large_; }
  bool timed_out() const { return timed_out_; }
  bool close_after() const { return close_after_; }
  void set_close_after() { close_after_ = true; }
  // Whether anything of a response was written for this request.
  bool answered() const { return written_ > 0; }

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
  Clock::time_point BodyDeadline(uint64_t bytes) const {
    const int64_t rate = std::max(1, limits_.body_min_rate_bytes_per_s);
    const auto cap = std::chrono::seconds(limits_.body_timeout_s);
    const auto allowed =
        std::chrono::seconds(limits_.body_grace_s) +
        Ms(static_cast<int64_t>(std::min<uint64_t>(bytes, 1ULL << 40)) * 1000 / rate);
    return head_end_ + std::min<Ms>(allowed, cap);
  }
  // Scans up to n buffered head bytes for the blank line that ends the
  // head; returns how many of them belong to the head (all n while it
  // goes on). From the head's end on, the request is busy and its body
  // has the body timeout until ExpectBody tells its length.
  size_t ConsumeHead(size_t n) {
    for (size_t i = 0; i < n; ++i) {
      const char c = buf_[pos_ + i];
      ++head_bytes_;
      ++line_bytes_;
      if (head_bytes_ > kMaxHeadBytes || (head_line_ > 0 && line_bytes_ > kMaxHeaderLine + 2)) {
        if (head_too_large_ == GuardedServer::HeadTooLarge::kNo) {
          head_too_large_ = head_line_ == 0 ? GuardedServer::HeadTooLarge::kRequestLine
                                            : GuardedServer::HeadTooLarge::kHeaders;
        }
      }
      if (c == '\n') {
        if (line_end_ > 0) {  // an empty line: the head is complete
          in_head_ = false;
          registry_.Set(fd_, ConnectionRegistry::State::kBusy);
          head_end_ = Clock::now();
          deadline_ = head_end_ + std::chrono::seconds(limits_.body_timeout_s);
          return i + 1;
        }
        line_end_ = 1;
        line_bytes_ = 0;
        ++head_line_;
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
  size_t line_bytes_ = 0, head_line_ = 0;
  size_t head_bytes_ = 0, body_bytes_ = 0, written_ = 0;
  GuardedServer::HeadTooLarge head_too_large_ = GuardedServer::HeadTooLarge::kNo;
  bool chunked_ = false, too_large_ = false, timed_out_ = false, close_after_ = false;
  ChunkedSyntax chunk_syntax_;
  Clock::time_point deadline_, head_end_;
};

// What the hooks learned about the request being served on this thread.
struct RequestContext {
  ConnectionStream* stream = nullptr;  // none for an in-memory request
  // The request's first byte: AwaitRequest returns when it arrived.
  Clock::time_point started = Clock::now();
  bool compressed = false;
  // Where the anonymous worker share taken by this request goes back to.
  std::atomic<int>* anonymous = nullptr;

  void ReleaseAnonymous() {
    if (anonymous) anonymous->fetch_sub(1);
    anonymous = nullptr;
  }
};

thread_local RequestContext* t_request = nullptr;

// Serves one request with `context` as this thread's, then gives back
// what the request held.
template <typename Serve>
bool WithContext(RequestContext& context, Serve serve) {
  t_request = &context;
  const bool ok = serve();
  context.ReleaseAnonymous();
  t_request = nullptr;
  return ok;
}

// A problem response written straight to the socket, for requests
// httplib cannot answer (no worker for them, or no request line read).
void WriteRawProblem(int fd, const ConnectionLimits& limits, int status, const std::string& title,
                     const std::string& detail, const std::string& extra_headers = "") {
  const std::string body = "{\"type\":\"about:blank\",\"title\":\"" + title +
                           "\",\"status\":" + std::to_string(status) + ",\"detail\":\"" + detail +
                           "\"}";
  const std::string response =
      "HTTP/1.1 " + std::to_string(status) + " " + title +
      "\r\nContent-Type: application/problem+json\r\n" + extra_headers +
      "Connection: close\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
  SendAll(fd, response.data(), response.size(),
          Clock::now() + std::chrono::seconds(limits.write_timeout_s));
}

void RejectConnection(int fd, const ConnectionLimits& limits) {
  WriteRawProblem(fd, limits, 503, "Service Unavailable",
                  "too many connections from this client: close idle ones or retry",
                  "Retry-After: 1\r\n");
}

}  // namespace

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

GuardedServer::HeadTooLarge GuardedServer::HeadTooLargeIn() {
  return t_request && t_request->stream ? t_request->stream->head_too_large() : HeadTooLarge::kNo;
}

bool GuardedServer::BodyTooLarge() {
  return t_request && t_request->stream && t_request->stream->too_large();
}

Clock::time_point GuardedServer::RequestStarted() {
  return t_request ? t_request->started : Clock::now();
}

bool GuardedServer::TimedOut() {
  return t_request && t_request->stream && t_request->stream->timed_out();
}

void GuardedServer::CloseAfterResponse() {
  if (t_request && t_request->stream) t_request->stream->set_close_after();
}

void GuardedServer::ExpectBody(uint64_t content_length, bool chunked) {
  if (t_request && t_request->stream) t_request->stream->ExpectBody(content_length, chunked);
}

void GuardedServer::ExpectCompressedBody() {
  if (t_request) t_request->compressed = true;
}

bool GuardedServer::HoldAnonymousWorker() {
  if (!t_request || t_request->anonymous) return true;
  const int share = std::max(1, static_cast<int>(limits_.workers * limits_.anonymous_worker_share));
  int held = anonymous_bodies_.load();
  do {
    if (held >= share) return false;
  } while (!anonymous_bodies_.compare_exchange_weak(held, held + 1));
  t_request->anonymous = &anonymous_bodies_;
  return true;
}

httplib::Server::Handler GuardedServer::Guarded(Handler handler) {
  return [this, handler = std::move(handler)](const httplib::Request& req, httplib::Response& res) {
    if (t_request) {
      t_request->ReleaseAnonymous();  // the body has been read
      if (t_request->compressed) {
        std::string inflated;
        switch (Inflate(req.body, limits_.max_body_bytes, &inflated)) {
          case InflateResult::kOk:
            break;
          case InflateResult::kTooLarge:
            return WriteProblem(res, 413,
                                "request body larger than server.max_body_bytes (" +
                                    std::to_string(limits_.max_body_bytes) +
                                    " bytes) once inflated (Content-Encoding)");
          case InflateResult::kCorrupt:
            return WriteProblem(res, 400,
                                "the body is not valid for its Content-Encoding (gzip or deflate)",
                                {{0, "Content-Encoding", "body does not inflate"}});
        }
        auto& body = const_cast<httplib::Request&>(req).body;
        body.swap(inflated);
      }
    }
    handler(req, res);
  };
}

GuardedServer& GuardedServer::Get(const std::string& pattern, Handler handler) {
  routes_.Add(pattern);
  httplib::Server::Get(pattern, std::move(handler));
  return *this;
}

GuardedServer& GuardedServer::Post(const std::string& pattern, Handler handler) {
  routes_.Add(pattern);
  httplib::Server::Post(pattern, Guarded(std::move(handler)));
  return *this;
}

GuardedServer& GuardedServer::Put(const std::string& pattern, Handler handler) {
  routes_.Add(pattern);
  httplib::Server::Put(pattern, Guarded(std::move(handler)));
  return *this;
}

GuardedServer& GuardedServer::Patch(const std::string& pattern, Handler handler) {
  routes_.Add(pattern);
  httplib::Server::Patch(pattern, Guarded(std::move(handler)));
  return *this;
}

GuardedServer& GuardedServer::Delete(const std::string& pattern, Handler handler) {
  routes_.Add(pattern);
  httplib::Server::Delete(pattern, Guarded(std::move(handler)));
  return *this;
}

bool GuardedServer::ServeOne(httplib::Stream& stream) {
  RequestContext context;
  return WithContext(context, [&] {
    bool closed = false;
    return process_request(stream, true, closed, nullptr);
  });
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
    if (stream.AwaitRequest(ConnectionRegistry::kSlowHead) && stream.IsHealthProbe()) {
      RequestContext context{&stream};
      ok = WithContext(context, [&] {
        bool closed = false;
        return process_request(stream, true, closed, nullptr);
      });
    } else {
      RejectConnection(sock, limits_);
    }
  } else {
    for (size_t left = keep_alive_max_count_; left > 0 && svr_sock_ != INVALID_SOCKET; --left) {
      registry_.Set(sock, ConnectionRegistry::State::kIdle);
      if (!stream.AwaitRequest(std::chrono::seconds(limits_.header_timeout_s))) break;
      registry_.Set(sock, ConnectionRegistry::State::kHead);
      bool closed = false;
      RequestContext context{&stream};
      ok = WithContext(context, [&] {
        return process_request(stream, left == 1 || svr_sock_ == INVALID_SOCKET, closed, nullptr);
      });
      // httplib gives up on a request line it could not read to its end
      // without answering: the client is told why before the close.
      if (!stream.answered() && stream.head_too_large() == HeadTooLarge::kRequestLine) {
        WriteRawProblem(sock, limits_, 414, "URI Too Long",
                        "request line longer than " + std::to_string(kMaxHeadBytes) + " bytes");
      }
      if (!ok || closed || stream.close_after()) break;
    }
    registry_.Remove(sock);
  }
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
  return ok;
}

}  // namespace thermocomp::api
