#include "server/command_util.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/log.h"
#include "server/open_app.h"

namespace thermocomp::cli {

StatusOr<Args> Parse(const CommandSpec& spec, const std::vector<std::string>& in) {
  Args a;
  for (size_t i = 0; i < in.size(); ++i) {
    if (in[i].rfind("--", 0) != 0) {
      if (a.positional.size() >= spec.max_positional) {
        return Status::InvalidArgument("unexpected argument '" + in[i] + "'");
      }
      a.positional.push_back(in[i]);
      continue;
    }
    std::string key = in[i].substr(2);
    std::optional<std::string> value;
    if (auto eq = key.find('='); eq != std::string::npos) {
      value = key.substr(eq + 1);
      key = key.substr(0, eq);
    }
    const OptionSpec* option = nullptr;
    for (const auto& o : spec.options) {
      if (key == o.name) option = &o;
    }
    if (!option) return Status::InvalidArgument("unknown option --" + key);
    if (option->takes_value && !value) {
      if (i + 1 >= in.size() || in[i + 1].rfind("--", 0) == 0) {
        return Status::InvalidArgument("--" + key + " needs a value");
      }
      value = in[++i];
    } else if (!option->takes_value && value) {
      return Status::InvalidArgument("--" + key + " takes no value");
    }
    if (a.opts.count(key)) return Status::InvalidArgument("--" + key + " given twice");
    a.opts[key] = value.value_or("true");
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
  return c;
}

Status PrepareDatabasePath(const Args& a, const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(path, ec)) return Status::Ok();
  if (!a.Has("create")) {
    return Status::NotFound("database " + path +
                            " does not exist (check the path; --create makes a new one)");
  }
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty()) fs::create_directories(dir, ec);
  if (ec) return Status::Unavailable("cannot create " + dir.string() + ": " + ec.message());
  return Status::Ok();
}

StatusOr<std::unique_ptr<App>> OpenApp(const Args& a) {
  static const SystemClock clock;
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return config.status();
  if (Status s = PrepareDatabasePath(a, config->db_path); !s.ok()) return s;
  return OpenApp(*config, clock);
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
