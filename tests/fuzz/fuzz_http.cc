// Whole HTTP requests (request line, headers, body) through the real
// routes, auth, parsers, services and a real SQLite file, from an
// in-memory connection: whatever the bytes, a response is written, it is
// well-formed, and the process survives. The seeds include gzip and
// deflate bodies (one a bomb past the 1 MiB limit) and Range headers.
#include "service/app.h"  // first: Eigen before httplib.h

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "api/http_server.h"
#include "core/log.h"
#include "server/open_app.h"
#include "sim/virtual_machine.h"

namespace {

using namespace thermocomp;

// A connection whose request is the fuzzer's bytes and whose response is
// collected in memory.
class MemoryStream : public httplib::Stream {
 public:
  explicit MemoryStream(std::string in) : in_(std::move(in)) {}
  bool is_readable() const override { return pos_ < in_.size(); }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    if (pos_ >= in_.size()) return -1;
    const size_t n = std::min(size, in_.size() - pos_);
    std::copy(in_.data() + pos_, in_.data() + pos_ + n, ptr);
    pos_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    out_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 40000;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 8080;
  }
  socket_t socket() const override { return 0; }
  const std::string& out() const { return out_; }

 private:
  std::string in_, out_;
  size_t pos_ = 0;
};

struct Fixture {
  Fixture() {
    log::SetLevel("error");
    dir = std::filesystem::temp_directory_path() /
          ("thermocomp-fuzz-http-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    config.db_path = (dir / "f.db").string();
    config.synchronous = "normal";
    config.max_body_bytes = 1 << 20;
    app = std::move(OpenApp(config, clock)).value();
    app->machines().Register(VirtualMachine::Definition("m1"), "fuzz", nullptr);
    std::vector<TemperatureInput> samples;
    samples.reserve(60);
    for (int i = 0; i < 60; ++i)
      samples.push_back({"Tcb", clock.NowMs() - (60 - i) * 60000LL, 21.0});
    app->ingest().AddTemperatures("m1", samples, "fuzz");
    http = std::make_unique<api::HttpServer>(*app);
  }
  ~Fixture() {
    http.reset();
    app.reset();
    std::filesystem::remove_all(dir);
  }
  std::filesystem::path dir;
  Config config;
  ManualClock clock{1772409600000 + 14 * 86400000LL};
  std::unique_ptr<App> app;
  std::unique_ptr<api::HttpServer> http;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Fixture f;
  MemoryStream stream(std::string(reinterpret_cast<const char*>(data), size));
  f.http->ServeOne(stream);
  const std::string& out = stream.out();
  // A request that was read at all gets a response that is an HTTP status line.
  if (!out.empty() && out.rfind("HTTP/1.1 ", 0) != 0) __builtin_trap();
  // Byte ranges are never served: a Range header is dropped.
  if (out.rfind("HTTP/1.1 206", 0) == 0) __builtin_trap();
  return 0;
}
