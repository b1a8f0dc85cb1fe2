// The webhook against a real receiver (httplib::Server on 127.0.0.1): an
// event raised while the receiver is down arrives once it is up, cleared
// events follow; and a receiver that hangs holds only the webhook's
// thread, never the API.
#include "tests/operations/alerts/alerts_fixture.h"  // first: Eigen before httplib.h

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "api/operations/alert_post.h"
#include "service/operations/alert_webhook.h"

namespace thermocomp {
namespace {

using nlohmann::json;
// Generous for sanitizer builds: the tests wait for conditions, never time them.
constexpr auto kPatience = std::chrono::seconds(120);

// Waits until `done` holds or kPatience passed; returns whether it holds.
template <typename Done>
bool WaitFor(Done done) {
  const auto until = std::chrono::steady_clock::now() + kPatience;
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

// A receiver that keeps every body POSTed to /hook.
class Receiver {
 public:
  Receiver() {
    server_.Post("/hook", [this](const httplib::Request& req, httplib::Response& res) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ++entered_;
        entered_cv_.notify_all();
        release_cv_.wait(lock, [this] { return !hang_; });
        bodies_.push_back(req.body);
      }
      res.status = 204;
    });
  }
  ~Receiver() { Stop(); }
  bool Listen(int port) {
    if (!server_.bind_to_port("127.0.0.1", port)) return false;
    // Bound means listening: connections wait in the backlog until accepted.
    thread_ = std::thread([this] { server_.listen_after_bind(); });
    return true;
  }
  void Stop() {
    Release();
    server_.stop();
    if (thread_.joinable()) thread_.join();
  }
  void Hang() {
    std::lock_guard<std::mutex> lock(mutex_);
    hang_ = true;
  }
  void Release() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      hang_ = false;
    }
    release_cv_.notify_all();
  }
  int entered() {
    std::lock_guard<std::mutex> lock(mutex_);
    return entered_;
  }
  std::vector<std::string> bodies() {
    std::lock_guard<std::mutex> lock(mutex_);
    return bodies_;
  }

 private:
  httplib::Server server_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable entered_cv_, release_cv_;
  bool hang_ = false;
  int entered_ = 0;
  std::vector<std::string> bodies_;
};

// A loopback port nothing listens on now: bound without listening, then
// closed (an httplib::Server that never ran keeps its socket listening).
int FreePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t size = sizeof addr;
  int port = -1;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &size) == 0) {
    port = ntohs(addr.sin_port);
  }
  close(fd);
  return port;
}

class AlertWebhookTest : public testing::AlertsFixture {
 protected:
  static AlertWebhook::Options Quick() {
    AlertWebhook::Options o;
    o.first_backoff = std::chrono::milliseconds(50);
    o.max_backoff = std::chrono::milliseconds(200);
    return o;
  }
};

TEST_F(AlertWebhookTest, AnEventRaisedWhileTheReceiverIsDownArrivesOnceItIsUp) {
  const int port = FreePort();
  ASSERT_GT(port, 0);
  AlertWebhook webhook("http://127.0.0.1:" + std::to_string(port) + "/hook", api::PostAlert,
                       Quick());
  webhook.Start();
  AlertMonitor monitor(*app_, &webhook);
  ActivateModel();  // no datum: compensation_invalid on Y
  EXPECT_EQ(monitor.Tick(), 1);
  EXPECT_EQ(monitor.Tick(), 0);                                 // still active: not sent again
  ASSERT_TRUE(WaitFor([&] { return webhook.failed() >= 2; }));  // down, retried
  EXPECT_EQ(webhook.sent(), 0u);

  Receiver receiver;
  ASSERT_TRUE(receiver.Listen(port));
  ASSERT_TRUE(WaitFor([&] { return !receiver.bodies().empty(); }));
  json raised = json::parse(receiver.bodies()[0]);
  EXPECT_EQ(raised["event"], "raised");
  EXPECT_EQ(raised["kind"], "compensation_invalid");
  EXPECT_EQ(raised["machine"], "m1");
  EXPECT_EQ(raised["axis"], "Y");
  EXPECT_FALSE(raised["detail"].get<std::string>().empty());
  EXPECT_TRUE(raised.contains("since") && raised.contains("at"));

  // The datum and a live sample clear it: one "cleared" event follows.
  Point(0, clock_.NowMs() - kH, 0.0, 20.0);
  Sample(clock_.NowMs() - 500, 21.0);
  EXPECT_EQ(monitor.Tick(), 1);
  ASSERT_TRUE(WaitFor([&] { return receiver.bodies().size() >= 2; }));
  json cleared = json::parse(receiver.bodies()[1]);
  EXPECT_EQ(cleared["event"], "cleared");
  EXPECT_EQ(cleared["kind"], "compensation_invalid");
  EXPECT_EQ(receiver.bodies().size(), 2u);
  EXPECT_EQ(webhook.sent(), 2u);
}

TEST_F(AlertWebhookTest, AReceiverThatHangsDoesNotDelayTheApi) {
  Receiver receiver;
  const int port = FreePort();
  ASSERT_TRUE(receiver.Listen(port));
  receiver.Hang();
  AlertWebhook webhook("http://127.0.0.1:" + std::to_string(port) + "/hook", api::PostAlert,
                       Quick());
  webhook.Start();
  AlertMonitor monitor(*app_, &webhook);
  ActivateModel();
  EXPECT_EQ(monitor.Tick(), 1);
  ASSERT_TRUE(WaitFor([&] { return receiver.entered() >= 1; }));  // the POST is held
  // While the receiver holds the webhook's thread the API answers, ticks
  // and ingest return, and further events only queue.
  for (int i = 0; i < 5; ++i) {
    auto r = client_->Get("/api/v1/alerts");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(client_->Get("/api/v1/machines/m1/compensation")->status, 200);
  }
  Point(0, clock_.NowMs() - kH, 0.0, 20.0);
  Sample(clock_.NowMs() - 500, 21.0);
  EXPECT_EQ(monitor.Tick(), 1);  // cleared: queued behind the held event
  EXPECT_GE(webhook.queued(), 1u);
  EXPECT_TRUE(receiver.bodies().empty());  // still held: nothing above waited for it
  receiver.Release();
  // In order; a POST held past the client's timeout is sent again, so the
  // raised event may arrive twice, never after the cleared one.
  ASSERT_TRUE(WaitFor([&] { return webhook.queued() == 0 && webhook.sent() >= 2; }));
  const std::vector<std::string> bodies = receiver.bodies();
  ASSERT_GE(bodies.size(), 2u);
  EXPECT_EQ(json::parse(bodies.front())["event"], "raised");
  EXPECT_EQ(json::parse(bodies.back())["event"], "cleared");
}

TEST(AlertPostTest, OnlyHttpUrlsAreAccepted) {
  EXPECT_TRUE(api::ValidAlertUrl(""));
  EXPECT_TRUE(api::ValidAlertUrl("http://127.0.0.1:9000/hook"));
  EXPECT_TRUE(api::ValidAlertUrl("https://alerts.example/hook"));
  EXPECT_FALSE(api::ValidAlertUrl("ftp://127.0.0.1/hook"));
  EXPECT_FALSE(api::ValidAlertUrl("http://"));
  EXPECT_FALSE(api::ValidAlertUrl("127.0.0.1:9000"));
  EXPECT_FALSE(api::ValidAlertUrl("http://127.0.0.1/ho ok"));
  EXPECT_EQ(api::PostAlert("nope", "{}").code(), Status::Code::kInvalidArgument);
}

}  // namespace
}  // namespace thermocomp
