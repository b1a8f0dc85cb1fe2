// GuardedServer: cpp-httplib's Server with the connection handling a server
// on a plant network needs and the library leaves out. cpp-httplib gives
// every connection a worker thread for as long as it stays open, reads
// headers with a per-byte timeout only, and does not count chunked bodies,
// so a few clients could hold every worker or fill the memory. Here:
//  - a request's head must arrive within `header_timeout_s` of its first
//    byte, its body within `body_timeout_s`;
//  - a body may not exceed `max_body_bytes` however it is framed (a chunked
//    body counts its framing too): 413, and the connection is closed;
//  - duplicate Content-Length, or Content-Length with Transfer-Encoding, is
//    refused (400) before any body is read: no request smuggling;
//  - connections are counted per client address. When a client holds
//    `max_connections_per_client`, or a connection waits for a worker, the
//    longest idle keep-alive connection, or a connection that has been
//    sending its head for longer than a legitimate client would, is closed
//    to make room (its client reconnects); a client with nothing that can
//    be closed gets 503 with Retry-After (its /healthz and /readyz are
//    still answered, so monitoring on the same host keeps working);
//  - a request answered before its body was read (401, 403, 415) closes
//    the connection, so the unread body is never taken for a request.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

// service/app.h first: glibc's resolv.h (pulled in by httplib.h) defines
// a macro `_res` that breaks Eigen's headers when they come after it.
#include "service/app.h"

#include <httplib.h>

namespace thermocomp::api {

struct ConnectionLimits {
  int workers = 64;
  int max_connections_per_client = 48;
  int header_timeout_s = 10;
  int body_timeout_s = 120;
  int keep_alive_timeout_s = 60;
  int write_timeout_s = 10;
  size_t max_body_bytes = 16 * 1024 * 1024;
};

// The open connections, what each is doing, and who may be closed.
class ConnectionRegistry {
 public:
  enum class State { kIdle, kHead, kBusy };

  explicit ConnectionRegistry(const ConnectionLimits& limits) : limits_(limits) {}
  // False when the client is at its limit and none of its connections can
  // be closed: the caller answers 503.
  bool Admit(int fd, const std::string& client);
  void Set(int fd, State state);
  void Remove(int fd);
  // Closes (shuts down) the connection it is best to lose: a head sent too
  // slowly, else the longest idle; of `client` only when given. False when
  // there is none.
  bool EvictOne(const std::string& client = "");
  void CloseAll();
  size_t size();

 private:
  struct Entry {
    std::string client;
    State state = State::kIdle;
    std::chrono::steady_clock::time_point since;
  };
  bool EvictLocked(const std::string& client);

  const ConnectionLimits& limits_;
  std::mutex mutex_;
  std::map<int, Entry> open_;
};

// A fixed pool of workers whose queue makes room: a connection that has to
// wait for a worker closes one that can be spared.
class GuardedTaskQueue : public httplib::TaskQueue {
 public:
  GuardedTaskQueue(int workers, ConnectionRegistry& registry);
  void enqueue(std::function<void()> fn) override;
  void shutdown() override;
  void on_idle() override;

 private:
  void Work();
  ConnectionRegistry& registry_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> jobs_;
  std::vector<std::thread> threads_;
  int idle_ = 0;
  bool stop_ = false;
};

class GuardedServer : public httplib::Server {
 public:
  explicit GuardedServer(const ConnectionLimits& limits);
  // Binds host:port (0: an ephemeral port, written to *bound_port) with a
  // listen backlog for bursts of clients. Serve with listen_after_bind().
  bool Listen(const std::string& host, int port, int* bound_port);
  // Closes every open connection, then stops listening.
  void Shutdown();
  ConnectionRegistry& registry() { return registry_; }

  // About the request being handled on this thread (for handlers): whether
  // its body went beyond the limit or it was not sent in time, and a way to
  // close the connection after the response.
  // Serves one request read from `stream` (an in-memory connection: the
  // HTTP fuzzer) through the same handlers as a socket.
  bool ServeOne(httplib::Stream& stream) {
    bool closed = false;
    return process_request(stream, true, closed, nullptr);
  }

  static bool BodyTooLarge();
  static bool TimedOut();
  static void CloseAfterResponse();

 private:
  bool process_and_close_socket(socket_t sock) override;

  ConnectionLimits limits_;
  ConnectionRegistry registry_;
};

}  // namespace thermocomp::api
