// GuardedServer: cpp-httplib's Server with the connection handling a server
// on a plant network needs and the library leaves out. cpp-httplib gives
// every connection a worker thread for as long as it stays open, reads
// headers with a per-byte timeout only, and does not count chunked bodies,
// so a few clients could hold every worker or fill the memory. Here:
//  - a request's head must arrive within `header_timeout_s` of its first
//    byte; a head over 64 KiB is answered 414 (request line) or 431;
//  - a body must arrive within `body_grace_s` plus its length at
//    `body_min_rate_bytes_per_s` (chunked: the bytes received so far, so
//    the deadline grows as data comes), never beyond `body_timeout_s`:
//    else 408, and the connection is closed;
//  - a body may not exceed `max_body_bytes` however it is framed (a chunked
//    body counts its framing too) or encoded (a gzip or deflate body is
//    inflated before the handler runs, and stops at the limit): 413, and
//    the connection is closed;
//  - anonymous requests may hold `anonymous_worker_share` of the workers
//    while their bodies arrive (HoldAnonymousWorker);
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

#include <atomic>
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

#include "api/route_table.h"

namespace thermocomp::api {

struct ConnectionLimits {
  int workers = 64;
  int max_connections_per_client = 48;
  int header_timeout_s = 10;
  int body_timeout_s = 120;
  int keep_alive_timeout_s = 60;
  int write_timeout_s = 10;
  size_t max_body_bytes = 16 * 1024 * 1024;
  int body_grace_s = 5;
  int body_min_rate_bytes_per_s = 16384;
  double anonymous_worker_share = 0.25;
};

// The open connections, what each is doing, and who may be closed.
class ConnectionRegistry {
 public:
  enum class State { kIdle, kHead, kBusy };
  // A head that takes longer than this to arrive is not a client on a LAN
  // sending one packet: under pressure its connection may be closed.
  static constexpr std::chrono::milliseconds kSlowHead{250};

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

  // Every route is also added to routes() (its template, for the
  // metrics and the access log).
  GuardedServer& Get(const std::string& pattern, Handler handler);
  const RouteTable& routes() const { return routes_; }
  // Routes whose requests carry a body. They hide httplib::Server's, so
  // that every such handler first gives back an anonymous worker share
  // (the body has been read) and gets a compressed body inflated within
  // max_body_bytes: beyond, 413; not inflatable, 400.
  GuardedServer& Post(const std::string& pattern, Handler handler);
  GuardedServer& Put(const std::string& pattern, Handler handler);
  GuardedServer& Patch(const std::string& pattern, Handler handler);
  GuardedServer& Delete(const std::string& pattern, Handler handler);

  // Serves one request read from `stream` (an in-memory connection: the
  // HTTP fuzzer) through the same handlers as a socket.
  bool ServeOne(httplib::Stream& stream);

  // About the request being handled on this thread, for the hooks and
  // handlers. Its head was too large: in the request line or the headers.
  enum class HeadTooLarge { kNo, kRequestLine, kHeaders };
  static HeadTooLarge HeadTooLargeIn();
  // Its body went beyond the limit, or was not sent in time.
  static bool BodyTooLarge();
  // When the request's first byte arrived (now for an in-memory request,
  // or outside a request).
  static std::chrono::steady_clock::time_point RequestStarted();
  static bool TimedOut();
  static void CloseAfterResponse();
  // Called once its head is parsed: the body's deadline follows from its
  // announced length, or from the bytes received when chunked.
  static void ExpectBody(uint64_t content_length, bool chunked);
  // Its body arrives gzip- or deflate-compressed (the Content-Encoding
  // header was taken off the request so httplib reads it as it is).
  static void ExpectCompressedBody();
  // Takes one of the workers anonymous requests may hold while their
  // bodies arrive, until the body was read or the request ends; false
  // when all of them are taken (the caller answers 503).
  bool HoldAnonymousWorker();

 private:
  bool process_and_close_socket(socket_t sock) override;
  Handler Guarded(Handler handler);

  ConnectionLimits limits_;
  ConnectionRegistry registry_;
  RouteTable routes_;
  std::atomic<int> anonymous_bodies_{0};
};
}  // namespace thermocomp::api
