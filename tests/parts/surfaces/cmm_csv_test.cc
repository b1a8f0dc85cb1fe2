// The CMM CSV parser: both forms read, and every bad file refused with the
// data row (1 = first row after the header) and the column named, nothing
// returned.
#include "api/parts/cmm_csv.h"

#include <gtest/gtest.h>

namespace thermocomp::api {
namespace {

const std::string kHeader = "point,x_mm,y_mm,z_mm,i,j,k,mx_mm,my_mm,mz_mm\n";

struct Refusal {
  Status status;
  FieldErrors errors;
};
Refusal Parse(const std::string& body, std::vector<CmmPoint>* out = nullptr) {
  std::vector<CmmPoint> points;
  Refusal r;
  r.status = ParseCmmCsv(body, points, r.errors);
  if (!r.status.ok()) {
    EXPECT_TRUE(points.empty());
  }
  if (out) *out = points;
  return r;
}
void ExpectError(const std::string& body, size_t row, const std::string& field,
                 Status::Code code = Status::Code::kInvalidArgument) {
  SCOPED_TRACE(body.substr(0, 120));
  const Refusal r = Parse(body);
  ASSERT_FALSE(r.status.ok());
  EXPECT_EQ(r.status.code(), code);
  ASSERT_FALSE(r.errors.empty());
  EXPECT_EQ(r.errors.front().index, row) << r.errors.front().message;
  EXPECT_EQ(r.errors.front().field, field) << r.errors.front().message;
}

TEST(CmmCsv, ReadsBothForms) {
  std::vector<CmmPoint> points;
  ASSERT_TRUE(
      Parse("\xEF\xBB\xBF" + kHeader + "P1,1,2,3,0,0,1,1,2,3.01\r\n\nP2,\"4\",5,6,0,0,1,4,5,6\n",
            &points)
          .status.ok());
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].row, 1u);
  EXPECT_EQ(points[1].row, 3u);  // blank lines count
  EXPECT_DOUBLE_EQ(*points[0].mz_mm, 3.01);
  EXPECT_DOUBLE_EQ(points[1].nominal.x_mm, 4);
  ASSERT_TRUE(
      Parse("k,j,i,z_mm,y_mm,x_mm,point,dev_mm,allowance_mm\n1,0,0,3,2,1,A,-0.05,\n", &points)
          .status.ok());
  EXPECT_EQ(points[0].nominal.id, "A");
  EXPECT_DOUBLE_EQ(*points[0].dev_mm, -0.05);
  EXPECT_FALSE(points[0].allowance_mm.has_value());
  EXPECT_DOUBLE_EQ(points[0].nominal.z_mm, 3);
}

TEST(CmmCsv, RefusesBadHeaders) {
  ExpectError("", 0, "header");
  ExpectError("\n\n\n", 0, "header");
  ExpectError("point,x_mm,y_mm,z_mm,i,j,mx_mm,my_mm,mz_mm\nP,1,2,3,0,0,1,2,3\n", 0, "k");
  ExpectError("point,x_mm,y_mm,z_mm,i,j,k\nP,1,2,3,0,0,1\n", 0, "dev_mm");
  ExpectError("point,x_mm,y_mm,z_mm,i,j,k,mx_mm,my_mm\nP,1,2,3,0,0,1,1,2\n", 0, "mz_mm");
  ExpectError("point,x_mm,y_mm,z_mm,i,j,k,dev_mm,mx_mm,my_mm,mz_mm\n", 0, "dev_mm");
  ExpectError("point,x_mm,x_mm,y_mm,z_mm,i,j,k,dev_mm\n", 0, "x_mm");
  ExpectError("point,x,y_mm,z_mm,i,j,k,dev_mm\n", 0, "x");
  ExpectError(kHeader, 1, "row", Status::Code::kUnprocessable);
  ExpectError(kHeader + "\n\n", 1, "row", Status::Code::kUnprocessable);
}

TEST(CmmCsv, RefusesBadRowsNamingRowAndField) {
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3\nP2,1,2,3,0,0,1,1,2\n", 2, "row");
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3\nP2,1,nan,3,0,0,1,1,2,3\n", 2, "y_mm");
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,inf\n", 1, "mz_mm");
  ExpectError(kHeader + "P1,1e999,2,3,0,0,1,1,2,3\n", 1, "x_mm");
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3\nP1,1,2,3,0,0,1,1,2,3\n", 2, "point");
  ExpectError(kHeader + "P1,1,2,3,0,0,0,1,2,3\n", 1, "i");
  ExpectError(kHeader + "P1,1,2,3,0,0,1000,1,2,3\n", 1, "i");
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3,5\n", 1, "row");
  ExpectError(kHeader + "P 1,1,2,3,0,0,1,1,2,3\n", 1, "point");
  ExpectError(kHeader + ",1,2,3,0,0,1,1,2,3\n", 1, "point");
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3\nP2,1,2,3,0,0,1,1,2,3\nP3,1;5,2,3,0,0,1,1,2,3\n", 3,
              "x_mm");
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,\n", 1, "mz_mm");
  ExpectError("point,x_mm,y_mm,z_mm,i,j,k,dev_mm,allowance_mm\nP,1,2,3,0,0,1,0.1,-0.2\n", 1,
              "allowance_mm");
}

TEST(CmmCsv, RefusesInvalidUtf8AndHugeFiles) {
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3\nP\xC3\x28,1,2,3,0,0,1,1,2,3\n", 2, "row");
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3\nP\xED\xA0\x80,1,2,3,0,0,1,1,2,3\n", 2, "row");
  ExpectError("poi\xFFnt\n", 0, "header");
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3\nP2\xE2\x82", 2, "row");
  // A million empty rows: stopped at the line limit, not read to the end.
  const std::string empty(1000000, '\n');
  ExpectError(kHeader + "P1,1,2,3,0,0,1,1,2,3\n" + empty, kMaxCmmLines + 1, "row",
              Status::Code::kTooLarge);
  std::string many = kHeader;
  for (size_t p = 0; p <= kMaxCmmPoints; ++p)
    many += "P" + std::to_string(p) + ",1,2,3,0,0,1,1,2,3\n";
  ExpectError(many, kMaxCmmPoints + 1, "row", Status::Code::kTooLarge);
}

}  // namespace
}  // namespace thermocomp::api
