#include "common/util/html.h"

#include <gtest/gtest.h>

namespace uw {
namespace {

TEST(Html, EscapesTextAndTableCells) {
  EXPECT_EQ(HtmlEscape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
  const std::string table = HtmlTable({"name", "x<y"}, {{"<i>", "1"}});
  EXPECT_NE(table.find("<th>x&lt;y</th>"), std::string::npos);
  EXPECT_NE(table.find("<td>&lt;i&gt;</td><td>1</td>"), std::string::npos);
}

// The page is self-contained (no http reference) and counts its images for
// a headless browser.
TEST(Html, PageIsSelfContainedAndCountsItsImages) {
  const std::string page = HtmlPage("T & t",
                                    "<img src=\"a.png\"><p>x</p><IMG alt=\"b\" "
                                    "src=\"dir/b&amp;c.jpg\">");
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.find("<title>T &amp; t</title>"), std::string::npos);
  EXPECT_NE(page.find("<body data-images-ok=\"\">"), std::string::npos);
  EXPECT_NE(page.find("document.body.dataset.imagesOk"), std::string::npos);
  EXPECT_NE(page.find("naturalWidth > 0"), std::string::npos);
  EXPECT_EQ(page.find("http"), std::string::npos);
  EXPECT_EQ(ImageSources(page),
            (std::vector<std::string>{"a.png", "dir/b&c.jpg"}));
}

}  // namespace
}  // namespace uw
