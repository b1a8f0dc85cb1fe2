// The real thermocomp binary with its log captured, and files in a
// temporary directory: what the exposure tests share.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>

#include "tests/server_process.h"

namespace thermocomp::testing {

inline void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `program args...` with stdout and stderr into `log`; the child's pid.
inline pid_t Spawn(const std::string& program, std::vector<std::string> args,
                   const std::filesystem::path& log) {
  pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(log.c_str(), "w", stderr)) _exit(126);
    dup2(fileno(stderr), fileno(stdout));
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(program.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// Waits up to `timeout` for the child to exit; its exit code, or -1 when it
// is still running (then it is killed) or did not exit normally.
inline int WaitExit(pid_t pid, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -1;
}

// `thermocomp serve --config config --db dir/thermocomp.db --listen
// 127.0.0.1:port --create`, its log in dir/serve.log; returned once
// /healthz answers (generous for sanitizer builds), -1 otherwise.
inline pid_t StartLogged(const std::filesystem::path& dir, const std::filesystem::path& config,
                         int port) {
  const pid_t pid = Spawn(
      THERMOCOMP_BINARY,
      {"thermocomp", "serve", "--config", config.string(), "--db", (dir / "thermocomp.db").string(),
       "--listen", "127.0.0.1:" + std::to_string(port), "--create"},
      dir / "serve.log");
  httplib::Client c("127.0.0.1", port);
  for (int i = 0; i < 1200; ++i) {
    if (auto r = c.Get("/healthz"); r && r->status == 200) return pid;
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  KillServer(pid);
  return -1;
}

// The log's lines that contain every one of `needles`.
inline std::vector<std::string> LinesWith(const std::string& log,
                                          const std::vector<std::string>& needles) {
  std::vector<std::string> out;
  std::stringstream in(log);
  for (std::string line; std::getline(in, line);) {
    bool all = true;
    for (const auto& n : needles) all = all && line.find(n) != std::string::npos;
    if (all) out.push_back(line);
  }
  return out;
}

// Waits (up to a minute) until the log at `path` has a line with every
// one of `needles`: the server writes a request's line after answering it.
inline std::vector<std::string> AwaitLines(const std::filesystem::path& path,
                                           const std::vector<std::string>& needles) {
  for (int i = 0; i < 1200; ++i) {
    auto lines = LinesWith(ReadText(path), needles);
    if (!lines.empty()) return lines;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return {};
}

}  // namespace thermocomp::testing
