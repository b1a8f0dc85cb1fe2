// Report pages: Markdown tables become HTML tables, our figures sit after
// the introduction, and markup inside report text is never passed through.
#include "api/report_page.h"

#include <gtest/gtest.h>

namespace thermocomp::api {
namespace {

TEST(ReportPageTest, TablesAreTablesAndFiguresFollowTheIntroduction) {
  const std::string page = ReportPage(
      "Check 1", "# Check 1\n\nIntro.\n\n## Results\n\n| a | b |\n|---|---|\n| 1 | 2 |\n",
      "<figure><svg></svg></figure>");
  EXPECT_NE(page.find("<title>Check 1</title>"), std::string::npos);
  EXPECT_NE(page.find("<table>"), std::string::npos);
  EXPECT_NE(page.find("<td>2</td>"), std::string::npos);
  const size_t figure = page.find("<figure>");
  ASSERT_NE(figure, std::string::npos);
  EXPECT_LT(page.find("Intro."), figure);
  EXPECT_LT(figure, page.find("<h2>Results</h2>"));
}

TEST(ReportPageTest, MarkupInTheTextIsNeverPassedThrough) {
  const std::string page =
      ReportPage("<script>t</script>",
                 "# R\n\nreason: <script>alert(1)</script> <img src=x onerror=alert(2)>\n\n"
                 "| note |\n|---|\n| <b onclick=x>bold</b> |\n\n<iframe src=//evil></iframe>\n");
  EXPECT_EQ(page.find("<script"), std::string::npos) << page;
  EXPECT_EQ(page.find("<img"), std::string::npos) << page;
  EXPECT_EQ(page.find("<iframe"), std::string::npos) << page;
  EXPECT_EQ(page.find("onclick="), std::string::npos) << page;
  EXPECT_NE(page.find("&lt;script&gt;t&lt;/script&gt;"), std::string::npos);
}

}  // namespace
}  // namespace thermocomp::api
