// A stub MTConnect agent for the tests: a real httplib::Server on
// 127.0.0.1 (an ephemeral port) that answers /probe from a recorded
// document and /current and /sample?from=&count= from a buffer the test
// fills, with the agent's semantics: sequence numbers, a bounded buffer
// (the oldest dropped: a wrap), OUT_OF_RANGE for a `from` outside
// [firstSequence, nextSequence], and a restart (a new instanceId, the
// buffer emptied, every item UNAVAILABLE). A test can also make the next
// answer to a path be any text (malformed documents).
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

#include <httplib.h>

#include "core/time_format.h"

namespace thermocomp::testing {

class StubAgent {
 public:
  explicit StubAgent(uint64_t instance_id) : instance_id_(instance_id) {
    std::ifstream in(std::string(THERMOCOMP_SOURCE_DIR) + "/tests/data/mtconnect/probe.xml");
    std::stringstream text;
    text << in.rdbuf();
    probe_ = text.str();
    server_.Get("/vmc-1/probe", [this](const httplib::Request& req, httplib::Response& res) {
      Answer(req, res, [this](httplib::Response& r) { r.set_content(probe_, "application/xml"); });
    });
    server_.Get("/vmc-1/current", [this](const httplib::Request& req, httplib::Response& res) {
      Answer(req, res, [this](httplib::Response& r) { Current(r); });
    });
    server_.Get("/vmc-1/sample", [this](const httplib::Request& req, httplib::Response& res) {
      Answer(req, res, [this, &req](httplib::Response& r) {
        Sample(std::stoull(req.get_param_value("from")), std::stoull(req.get_param_value("count")),
               r);
      });
    });
    server_.Get("/big", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(std::string(1 << 20, 'x'), "application/xml");
    });
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
    // The socket listens once bound; connections queue until the thread
    // accepts them.
    while (!server_.is_running()) std::this_thread::yield();
  }
  ~StubAgent() {
    server_.stop();
    thread_.join();
  }
  StubAgent(const StubAgent&) = delete;
  StubAgent& operator=(const StubAgent&) = delete;

  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  void SetNow(int64_t ms) {
    const std::lock_guard<std::mutex> lock(mutex_);
    now_ms_ = ms;
  }
  // One observation; "UNAVAILABLE" or a number as text.
  void Add(const std::string& item, int64_t ts_ms, const std::string& value) {
    const std::lock_guard<std::mutex> lock(mutex_);
    AddLocked(item, ts_ms, value);
  }
  void SetCapacity(size_t n) {
    const std::lock_guard<std::mutex> lock(mutex_);
    capacity_ = n;
    Trim();
  }
  void Restart(uint64_t instance_id, int64_t ts_ms) {
    const std::lock_guard<std::mutex> lock(mutex_);
    instance_id_ = instance_id;
    buffer_.clear();
    next_ = 1;
    const std::map<std::string, Observation> known = latest_;
    for (const auto& [item, o] : known) AddLocked(item, ts_ms, "UNAVAILABLE");
  }
  // The next request for `path` is answered with `body` (status 200).
  void AnswerNextWith(const std::string& path, const std::string& body) {
    const std::lock_guard<std::mutex> lock(mutex_);
    once_[path] = body;
  }
  int requests() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return requests_;
  }

 private:
  struct Observation {
    uint64_t sequence = 0;
    std::string item;
    int64_t ts_ms = 0;
    std::string value;
  };

  template <typename Fn>
  void Answer(const httplib::Request& req, httplib::Response& res, Fn fn) {
    const std::lock_guard<std::mutex> lock(mutex_);
    ++requests_;
    const auto once = once_.find(req.path);
    if (once != once_.end()) {
      res.set_content(once->second, "application/xml");
      once_.erase(once);
      return;
    }
    fn(res);
  }
  void AddLocked(const std::string& item, int64_t ts_ms, const std::string& value) {
    Observation o{next_++, item, ts_ms, value};
    buffer_.push_back(o);
    latest_[item] = o;
    Trim();
  }
  void Trim() {
    while (buffer_.size() > capacity_) buffer_.pop_front();
  }
  uint64_t First() const { return buffer_.empty() ? next_ : buffer_.front().sequence; }
  std::string Header() const {
    return "<Header creationTime=\"" + FormatRfc3339(now_ms_) + "\" sender=\"stub\" instanceId=\"" +
           std::to_string(instance_id_) + "\" version=\"1.7.0.3\" bufferSize=\"" +
           std::to_string(capacity_) + "\" nextSequence=\"%NEXT%\" firstSequence=\"" +
           std::to_string(First()) + "\" lastSequence=\"" + std::to_string(next_ - 1) + "\"/>";
  }
  // The bed on the X axis, the rest on the C axis, as the probe declares.
  static std::string Component(const std::string& item) {
    return item == "bed_temp"
               ? "<ComponentStream component=\"Linear\" name=\"X\" componentId=\"x\">"
               : "<ComponentStream component=\"Rotary\" name=\"C\" componentId=\"c\">";
  }
  std::string Streams(const std::vector<Observation>& obs, uint64_t next) const {
    std::string header = Header();
    header.replace(header.find("%NEXT%"), 6, std::to_string(next));
    std::string x, c;
    for (const auto& o : obs) {
      const std::string line = "<Temperature dataItemId=\"" + o.item + "\" timestamp=\"" +
                               FormatRfc3339(o.ts_ms) + "\" sequence=\"" +
                               std::to_string(o.sequence) + "\">" + o.value + "</Temperature>";
      (o.item == "bed_temp" ? x : c) += line;
    }
    std::string out =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<MTConnectStreams "
        "xmlns=\"urn:mtconnect.org:MTConnectStreams:1.7\">" +
        header + "<Streams><DeviceStream name=\"vmc-1\" uuid=\"vmc-1-uuid\">";
    if (!x.empty()) out += Component("bed_temp") + "<Samples>" + x + "</Samples></ComponentStream>";
    if (!c.empty()) out += Component("c") + "<Samples>" + c + "</Samples></ComponentStream>";
    return out + "</DeviceStream></Streams></MTConnectStreams>";
  }
  void Current(httplib::Response& res) const {
    std::vector<Observation> obs;
    for (const auto& [item, o] : latest_) obs.push_back(o);
    res.set_content(Streams(obs, next_), "application/xml");
  }
  void Sample(uint64_t from, uint64_t count, httplib::Response& res) const {
    if (from < First() || from > next_) {
      res.status = 400;
      res.set_content(
          "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<MTConnectError "
          "xmlns=\"urn:mtconnect.org:MTConnectError:1.7\"><Header creationTime=\"" +
              FormatRfc3339(now_ms_) + "\" sender=\"stub\" instanceId=\"" +
              std::to_string(instance_id_) + "\" version=\"1.7.0.3\" bufferSize=\"" +
              std::to_string(capacity_) +
              "\"/><Errors><Error errorCode=\"OUT_OF_RANGE\">'from' must be within " +
              std::to_string(First()) + ".." + std::to_string(next_) +
              "</Error></Errors></MTConnectError>",
          "application/xml");
      return;
    }
    std::vector<Observation> obs;
    uint64_t next = from;
    for (const auto& o : buffer_) {
      if (o.sequence >= from && obs.size() < count) {
        obs.push_back(o);
        next = o.sequence + 1;
      }
    }
    res.set_content(Streams(obs, next), "application/xml");
  }

  mutable std::mutex mutex_;
  uint64_t instance_id_;
  std::string probe_;
  int64_t now_ms_ = 0;
  uint64_t next_ = 1;
  size_t capacity_ = 1000;
  std::deque<Observation> buffer_;
  std::map<std::string, Observation> latest_;
  std::map<std::string, std::string> once_;
  int requests_ = 0;
  httplib::Server server_;
  int port_ = 0;
  std::thread thread_;
};

}  // namespace thermocomp::testing
