// The pieces of a self-contained HTML page (inline CSS, no script or font
// from the network) that the survey report is written with; HtmlEscape is
// every report's (laserscale's scale report too).
#pragma once

#include <string>
#include <vector>

namespace uw {

// Text safe inside an element or a double-quoted attribute.
std::string HtmlEscape(const std::string& text);

// A table with a header row; cells are escaped. Numeric-looking cells are
// right-aligned by the page's CSS (every column but the first).
std::string HtmlTable(const std::vector<std::string>& header,
                      const std::vector<std::vector<std::string>>& rows);

// A whole page: <head> with the title and the inline style sheet, then
// `body_html` (trusted, already escaped). The page carries a small inline
// script that, once every image has loaded or failed, writes
// "<loaded>/<total>" into <body data-images-ok>, where loaded counts the
// <img> elements with complete && naturalWidth > 0: a headless browser's
// --dump-dom shows whether any image is missing.
std::string HtmlPage(const std::string& title, const std::string& body_html);

// The src attributes of the page's <img> elements, in order (as written,
// not unescaped beyond &amp; &quot; &lt; &gt;).
std::vector<std::string> ImageSources(const std::string& html);

}  // namespace uw
