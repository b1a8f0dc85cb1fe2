// Running the real thermocomp binary as a separate process in tests.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>

namespace thermocomp::testing {

// A loopback port that was free a moment ago.
inline int FreePort() {
  int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof addr;
  const bool bound = bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
                     getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0;
  close(fd);
  return bound ? ntohs(addr.sin_port) : -1;
}

// `thermocomp serve --db db --listen 127.0.0.1:port [extra...]`, returned
// once /healthz answers; -1 if it did not start. Its log (stderr) goes to
// `log_path`.
inline pid_t StartServer(const std::string& db, int port, std::vector<std::string> extra = {},
                         const std::string& log_path = "/dev/null") {
  pid_t pid = fork();
  if (pid == 0) {
    freopen("/dev/null", "w", stdout);
    freopen(log_path.c_str(), "w", stderr);
    std::vector<std::string> args = {"thermocomp", "serve",    "--db",
                                     db,           "--listen", "127.0.0.1:" + std::to_string(port),
                                     "--create"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(THERMOCOMP_BINARY, argv.data());
    _exit(127);
  }
  httplib::Client c("127.0.0.1", port);
  for (int i = 0; i < 200; ++i) {
    if (auto r = c.Get("/healthz"); r && r->status == 200) return pid;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -1;
}

inline void KillServer(pid_t pid, int sig = SIGKILL) {
  kill(pid, sig);
  waitpid(pid, nullptr, 0);
}

// Kills the server when the test leaves, also on a failed assertion.
class ServerGuard {
 public:
  explicit ServerGuard(pid_t pid) : pid_(pid) {}
  ~ServerGuard() { Kill(); }
  void Kill(int sig = SIGKILL) {
    if (pid_ > 0) KillServer(pid_, sig);
    pid_ = -1;
  }
  void Reset(pid_t pid) {
    Kill();
    pid_ = pid;
  }
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_;
};

}  // namespace thermocomp::testing
