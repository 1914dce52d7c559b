// The report's page assets, inlined at build time (cmake/embed_text.cmake writes their source):
// Apache ECharts as the pinned npm package ships it (x2car/report/web/package-lock.json), and the
// report's own script and style (x2car/report/web/report.js, report.css).
#pragma once

#include <string>

namespace x2car::report {

std::string echarts_js();  // node_modules/echarts/dist/echarts.min.js
std::string report_js();   // web/report.js
std::string report_css();  // web/report.css

}  // namespace x2car::report
