// Who may import plates: a quality token (the part tests are its work) and
// admin; a reader may read them, not write; the importer is audited.
#include <gtest/gtest.h>

#include "tests/app_fixture.h"
#include "tests/parts/plates/plate_fixture.h"

namespace thermocomp::testing {
namespace {

const std::string kQuality(24, 'q'), kReader(24, 'r');

class PlateAuthTest : public AppFixture {
 protected:
  void Configure(Config& c) override {
    c.tokens = {{"qa-anna", kQuality, "quality", ""}, {"viewer", kReader, "reader", ""}};
  }
};

TEST_F(PlateAuthTest, QualityWritesReaderReads) {
  StartHttp();
  PlateSimOptions o;
  o.seed = 7;
  o.start_ms = clock_.NowMs() - 2 * 86400000LL;
  const SimulatedPlate plate = SimulatePlate(o);
  LoadPlateHistory(*app_, "m1", plate);
  auto client = TestClient(http_->port());
  const std::string path = "/api/v1/machines/m1/plates/qa";
  auto res = client->Post(path, {{"Authorization", "Bearer " + kReader}}, plate.Csv(), "text/csv");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 403) << res->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM plates"), 0);
  res = client->Post(path, {{"Authorization", "Bearer " + kQuality}}, plate.Csv(), "text/csv");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 201) << res->body;
  EXPECT_EQ(
      Count("SELECT COUNT(*) FROM audit WHERE action = 'import-plate' AND actor LIKE '%qa-anna%'"),
      1);
  res = client->Get(path, {{"Authorization", "Bearer " + kReader}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  res = client->Get(path);
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 401);
}

}  // namespace
}  // namespace thermocomp::testing
