#include "server/command_util.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "server/log.h"

namespace thermocomp::cli {

Args Parse(const std::vector<std::string>& in) {
  Args a;
  for (size_t i = 0; i < in.size(); ++i) {
    if (in[i].rfind("--", 0) == 0) {
      std::string key = in[i].substr(2);
      if (auto eq = key.find('='); eq != std::string::npos) {
        a.opts[key.substr(0, eq)] = key.substr(eq + 1);
      } else if (i + 1 < in.size() && in[i + 1].rfind("--", 0) != 0) {
        a.opts[key] = in[++i];
      } else {
        a.opts[key] = "true";
      }
    } else {
      a.positional.push_back(in[i]);
    }
  }
  return a;
}

int Fail(const std::string& what) {
  std::fprintf(stderr, "thermocomp: %s\n", what.c_str());
  return 1;
}

StatusOr<Config> LoadWithOverrides(const Args& a) {
  auto c = LoadConfig(a.Get("config"));
  if (!c.ok()) return c;
  if (a.Has("db")) c->db_path = a.Get("db");
  if (a.Has("listen")) {
    if (Status s = ParseListen(a.Get("listen"), *c); !s.ok()) return s;
  }
  if (a.Has("dds-domain")) c->dds_domain = static_cast<uint32_t>(std::stoul(a.Get("dds-domain")));
  log::SetLevel(c->log_level);
  std::filesystem::path dir = std::filesystem::path(c->db_path).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
  return c;
}

StatusOr<std::unique_ptr<App>> OpenApp(const Args& a) {
  static const SystemClock clock;
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return config.status();
  return App::Open(*config, clock);
}

std::string ReadFile(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string Describe(const IngestResult& r) {
  if (r.status.ok()) {
    return std::to_string(r.accepted) + " accepted, " + std::to_string(r.duplicates) +
           " duplicates";
  }
  std::string s = r.status.message();
  for (size_t i = 0; i < r.errors.size() && i < 5; ++i) {
    s += "\n  item " + std::to_string(r.errors[i].index) + " " + r.errors[i].field + ": " +
         r.errors[i].message;
  }
  return s;
}

std::atomic<bool> g_stop{false};
void OnSignal(int) {
  g_stop = true;
}

}  // namespace thermocomp::cli
