// The configuration file: any bytes either load into a Config within its
// ranges or stop with a message; never a crash.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "service/config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace thermocomp;
  static const std::string path =
      "/tmp/thermocomp-fuzz-config-" + std::to_string(getpid()) + ".toml";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  auto c = LoadConfig(path);
  if (c.ok() && (c->http_threads < 1 || c->stale_after_s < 1 || c->holdout_runs < 1 ||
                 !(c->acceptance.min_r2 >= 0 && c->acceptance.min_r2 <= 1))) {
    __builtin_trap();
  }
  return 0;
}
