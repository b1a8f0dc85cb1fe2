#include "server/refit_scheduler.h"

#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

class RefitSchedulerTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.refit_after_new_runs = 3;
    c.refit_interval_min = 24 * 60;
  }
};

TEST_F(RefitSchedulerTest, FitsWhenDueAndOnlyThen) {
  VirtualMachine vm = Simulate("m1", 10);
  RefitScheduler& s = app_->scheduler();
  // No model yet: both axes with declared inputs are fitted.
  EXPECT_EQ(s.Tick(), 2);
  // Nothing new: nothing to do, however much time passes.
  EXPECT_EQ(s.Tick(), 0);
  clock_.Advance(2 * 86400000LL);
  EXPECT_EQ(s.Tick(), 0);
  // New runs arrive (a day of production holds four): refit.
  std::vector<TemperatureInput> samples;
  std::vector<ProbePointInput> points;
  while (vm.now_ms() + 60000 <= clock_.NowMs()) vm.Step(samples, points);
  Flush("m1", samples, points);
  EXPECT_EQ(s.Tick(), 2);
  auto models = app_->fits().Models("m1", "Y");
  ASSERT_TRUE(models.ok());
  EXPECT_EQ(models->size(), 2u);
}

TEST_F(RefitSchedulerTest, FailedRefitNeverReplacesTheActiveModel) {
  Simulate("m1", 10);
  FitRequest good;
  auto first = app_->fits().Fit("m1", "Y", good);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ((*first)["status"], "active");
  FitRequest bad;
  bad.inputs = std::vector<std::string>{"Tenv"};
  auto second = app_->fits().Fit("m1", "Y", bad);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ((*second)["status"], "rejected");
  auto models = app_->fits().Models("m1", "Y");
  EXPECT_EQ((*models)[0].status, "active");
  EXPECT_EQ((*models)[1].status, "rejected");
  auto comp = app_->compensation().Get("m1");
  ASSERT_TRUE(comp.ok());
  for (const auto& a : comp->axes) {
    if (a.axis == "Y") {
      EXPECT_EQ(a.model_version, 1);
    }
  }
}

}  // namespace
}  // namespace thermocomp
