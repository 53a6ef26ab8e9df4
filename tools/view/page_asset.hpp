#pragma once
// The viewer's page (page/index.html), compiled into the binary so nothing is fetched from
// anywhere else.

#include <string_view>

namespace stereoball::view {
std::string_view page_html();
}
