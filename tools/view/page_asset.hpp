#pragma once
// The viewer's pages (page/index.html, page/calibrate.html, their page/common.css), compiled into
// the binary so nothing is fetched from anywhere else.

#include <string_view>

namespace stereoball::view {
std::string_view page_html();
std::string_view calibrate_page_html();
std::string_view common_css();
}  // namespace stereoball::view
