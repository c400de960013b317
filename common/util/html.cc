#include "common/util/html.h"

#include <regex>

namespace uw {
namespace {

// Print-friendly and readable on a laptop; figures never wider than the
// page.
const char kStyle[] =
    "body{font-family:sans-serif;margin:2em auto;max-width:1150px;"
    "padding:0 1em;color:#222;line-height:1.4}"
    "h1{margin-bottom:0.2em}h2{border-bottom:2px solid #2a6f97;"
    "padding-bottom:0.15em;margin-top:1.8em}"
    "table{border-collapse:collapse;margin:0.6em 0}"
    "td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
    "th{background:#eef3f7}td:first-child,th:first-child{text-align:left}"
    "img{max-width:100%;height:auto}"
    "figure{margin:0.8em 0}figcaption{color:#555;font-size:0.92em}"
    ".summary{border:2px solid #2a6f97;background:#f4f9fc;padding:0.6em 1.2em;"
    "border-radius:6px}.summary td{border:none;padding:2px 10px;"
    "text-align:left}"
    ".note{color:#8a5a00;background:#fff7e6;border-left:4px solid #e0a030;"
    "padding:0.3em 0.8em}"
    ".bad{color:#b00}.thumbs a{display:inline-block;margin:4px}"
    ".thumbs img{border:1px solid #999}";

// Counts the images once the page (and so every image) has loaded.
const char kImagesOkScript[] =
    "<script>\n"
    "window.addEventListener('load', function () {\n"
    "  var images = document.images, loaded = 0;\n"
    "  for (var i = 0; i < images.length; ++i)\n"
    "    if (images[i].complete && images[i].naturalWidth > 0) ++loaded;\n"
    "  document.body.dataset.imagesOk = loaded + '/' + images.length;\n"
    "});\n"
    "</script>\n";

std::string Unescape(std::string text) {
  const std::pair<const char*, const char*> kEntities[] = {
      {"&quot;", "\""}, {"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}};
  for (const auto& [entity, character] : kEntities) {
    for (size_t at = text.find(entity); at != std::string::npos;
         at = text.find(entity, at + 1)) {
      text.replace(at, std::char_traits<char>::length(entity), character);
    }
  }
  return text;
}

}  // namespace

std::string HtmlEscape(const std::string& text) {
  std::string escaped;
  escaped.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

std::string HtmlTable(const std::vector<std::string>& header,
                      const std::vector<std::vector<std::string>>& rows) {
  std::string html = "<table>\n<tr>";
  for (const std::string& cell : header) {
    html += "<th>" + HtmlEscape(cell) + "</th>";
  }
  html += "</tr>\n";
  for (const auto& row : rows) {
    html += "<tr>";
    for (const std::string& cell : row) {
      html += "<td>" + HtmlEscape(cell) + "</td>";
    }
    html += "</tr>\n";
  }
  return html + "</table>\n";
}

std::string HtmlPage(const std::string& title, const std::string& body_html) {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
         "<meta name=\"viewport\" content=\"width=device-width\">"
         "<title>" +
         HtmlEscape(title) + "</title>\n<style>" + kStyle +
         "</style>\n</head>\n<body data-images-ok=\"\">\n" + body_html +
         kImagesOkScript + "</body></html>\n";
}

std::vector<std::string> ImageSources(const std::string& html) {
  static const std::regex kImg("<img\\b[^>]*?\\bsrc=\"([^\"]*)\"",
                               std::regex::icase);
  std::vector<std::string> sources;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), kImg);
       it != std::sregex_iterator(); ++it) {
    sources.push_back(Unescape((*it)[1].str()));
  }
  return sources;
}

}  // namespace uw
