#include "validation/report.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fmt/format.h>
#include <fstream>

#include <nlohmann/json.hpp>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb/stb_image_write.h>

#include "validation/build_info.h"
#include "validation/faults.h"

namespace ft {

void writePng(const std::filesystem::path& path, const RgbaImage& image) {
  if (!stbi_write_png(path.string().c_str(), image.width, image.height, 4, image.pixels.data(), image.width * 4))
    throw std::runtime_error("cannot write " + path.string());
}

namespace {

std::string escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '&': o += "&amp;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

// "now" in UTC, ISO 8601.
std::string utcNow() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// A case name that may break after each '/'.
std::string breakableName(const std::string& caseName) {
  std::string o;
  for (char c : escape(caseName)) {
    o += c;
    if (c == '/') o += "<wbr>";
  }
  return o;
}

// "0.42", "3.1", "4260": how many times the tolerance a value is.
std::string ratioText(double ratio) {
  return ratio < 10.0 ? fmt::format("{:.2g}", ratio) : fmt::format("{:.0f}", ratio);
}

std::string anchor(const std::string& caseName) {
  std::string a = "case-";
  for (char c : caseName) a += std::isalnum(static_cast<unsigned char>(c)) ? c : '-';
  return a;
}

// The margin of one metric as a bar: value / tolerance on a log scale from
// 1e-8 (far inside) to 1e2 (far outside), the tolerance as a line at 1.
constexpr double kBarLogMin = -8.0, kBarLogMax = 2.0;
constexpr int kBarWidth = 150, kBarHeight = 14;

double barX(double ratio) {
  const double l = std::clamp(std::log10(ratio), kBarLogMin, kBarLogMax);
  return (l - kBarLogMin) / (kBarLogMax - kBarLogMin) * kBarWidth;
}

std::string marginSvg(const Metric& m) {
  const double tolX = barX(1.0);
  std::string s = fmt::format("<svg class='bar' width='{}' height='{}' role='img'>", kBarWidth, kBarHeight);
  s += fmt::format("<rect class='track' x='0' y='3' width='{}' height='{}'/>", kBarWidth, kBarHeight - 6);
  std::string label;
  if (m.tolerance > 0.0 && m.value > 0.0) {
    const double ratio = m.value / m.tolerance;
    s += fmt::format("<rect class='{}' x='0' y='3' width='{:.1f}' height='{}'/>", m.pass() ? "in" : "out",
                     std::max(1.0, barX(ratio)), kBarHeight - 6);
    label = "value / tolerance = " + ratioText(ratio);
  } else if (m.value <= 0.0) {
    label = m.tolerance > 0.0 ? "value 0" : "exact: value 0 = tolerance 0";
    s += fmt::format("<circle class='in' cx='4' cy='{}' r='3'/>", kBarHeight / 2);
  } else {  // a positive value against an exact (zero) tolerance
    s += fmt::format("<rect class='out' x='0' y='3' width='{}' height='{}'/>", kBarWidth, kBarHeight - 6);
    label = "nonzero value against an exact (zero) tolerance";
  }
  s += fmt::format("<line class='tol' x1='{0:.1f}' x2='{0:.1f}' y1='0' y2='{1}'/>", tolX, kBarHeight);
  s += "<title>" + label + " (bar: log scale 1e-8 … 1e2, line: tolerance)</title></svg>";
  return s;
}

// The bar's number: how much of its tolerance a value uses ("0.29%"), or how
// many times the tolerance it is ("4260×").
std::string marginText(const Metric& m) {
  if (m.tolerance <= 0.0) return m.value <= 0.0 ? "" : "≠ 0";
  const double ratio = m.value / m.tolerance;
  if (ratio <= 1.0) return fmt::format("{:.2g}%", 100.0 * ratio);
  return ratioText(ratio) + "×";
}

// Inline SVG bar chart of a log10 error histogram, with the tolerance of the
// metric it bins as a vertical line (bins past it drawn as failures).
std::string histogramSvg(const ErrorHistogram& h, double tolerance) {
  const uint64_t top = std::max<uint64_t>(1, *std::max_element(h.counts.begin(), h.counts.end()));
  const int w = 18, height = 44, n = static_cast<int>(h.counts.size());
  const int first = static_cast<int>(h.firstDecade);
  std::string s = fmt::format("<svg width='{}' height='{}' class='hist' role='img'>", w * n + 2, height + 14);
  for (int i = 0; i < n; ++i) {
    const int bar = h.counts[i] ? std::max(2, static_cast<int>(height * h.counts[i] / top)) : 0;
    const bool past = tolerance > 0.0 && std::pow(10.0, first + i) >= tolerance;
    s += fmt::format("<rect class='{}' x='{}' y='{}' width='{}' height='{}'><title>[1e{}, 1e{}): {}</title></rect>",
                     past ? "out" : "in", i * w + 1, height - bar, w - 2, bar, first + i, first + i + 1, h.counts[i]);
  }
  s += fmt::format("<line class='axis' x1='0' x2='{}' y1='{}' y2='{}'/>", w * n + 2, height + 0.5, height + 0.5);
  if (tolerance > 0.0) {
    const double x = std::clamp((std::log10(tolerance) - first) * w + 1, 0.0, double(w * n + 1));
    s += fmt::format("<line class='tol' x1='{0:.1f}' x2='{0:.1f}' y1='0' y2='{1}'><title>tolerance {2:.3g}</title></line>",
                     x, height, tolerance);
  }
  s += fmt::format("<text x='0' y='{}'>1e{}</text><text x='{}' y='{}' text-anchor='end'>1e{}</text></svg>",
                   height + 12, first, w * n + 2, height + 12, first + n);
  return s;
}

const char* kStyle = R"css(
body{font:14px/1.45 system-ui,-apple-system,"Segoe UI",sans-serif;margin:0;color:#1d2330;background:#f6f7f9}
main{max-width:1500px;margin:0 auto;padding:18px 28px 40px}
h1{font-size:22px;margin:0}h2{font-size:17px;margin:26px 0 8px}
.verdict{padding:16px 28px;color:#fff}.verdict.pass{background:#1f7a3a}.verdict.fail{background:#b3261e}
.verdict p{margin:4px 0 0;opacity:.9}
table{border-collapse:collapse;background:#fff}
table.meta td,table.meta th{padding:3px 12px 3px 0;text-align:left;vertical-align:top;border:0}
table.meta th{color:#555;font-weight:600;white-space:nowrap}
code{font:12px ui-monospace,Menlo,Consolas,monospace;background:#eef0f3;padding:1px 4px;border-radius:3px;word-break:break-all}
table.cases{width:100%;box-shadow:0 1px 2px rgba(0,0,0,.08)}
table.cases>thead th{position:sticky;top:0;background:#e8ebf0;text-align:left;padding:6px 8px;font-weight:600}
table.cases>tbody>tr>td{border-top:1px solid #e3e6eb;padding:6px 8px;vertical-align:top}
tr.case.failed>td:first-child{border-left:4px solid #b3261e}tr.case.passed>td:first-child{border-left:4px solid #1f7a3a}
td.name{font:12px ui-monospace,Menlo,Consolas,monospace;min-width:150px;max-width:200px}
.badge{display:inline-block;padding:1px 8px;border-radius:10px;font-size:12px;font-weight:700;color:#fff}
.badge.pass{background:#1f7a3a}.badge.fail{background:#b3261e}
table.metrics{background:none}table.metrics td{padding:1px 8px 1px 0;border:0;white-space:nowrap;font-size:12px}
table.metrics td.v{font-family:ui-monospace,Menlo,Consolas,monospace;text-align:right}
table.metrics td.ratio{font-size:11px;color:#555;text-align:right;min-width:44px}table.metrics tr.bad td.ratio{color:#b3261e}
table.metrics tr.bad td{color:#b3261e;font-weight:600}table.metrics tr.info td{color:#777;font-style:italic}
svg.bar .track{fill:#e9ecef}svg.bar .in{fill:#3b8f5a}svg.bar .out{fill:#c62828}svg .tol{stroke:#222;stroke-width:1.5;stroke-dasharray:3 2}
svg.hist rect.in{fill:#4a7fc1}svg.hist rect.out{fill:#c62828}svg.hist text{font-size:9px;fill:#555}svg.hist .axis{stroke:#999}
figure{display:inline-block;margin:0 6px 0 0}figure img{border:1px solid #c8ccd2;display:block}
figcaption{font-size:11px;color:#555}td.num{text-align:right;font-family:ui-monospace,Menlo,Consolas,monospace;white-space:nowrap}
ul.failures>li{margin:6px 0}ul.failures ul{margin:2px 0;padding-left:22px;list-style:circle}td.imgs{white-space:nowrap}
tr.exact td{color:#3b6e4a;font-size:12px;white-space:normal!important;max-width:340px}tr.exact .check{font-weight:700}
tr.exact .names{color:#777}.caption{font-size:11px;color:#555;max-width:190px}ul.failures .why{color:#b3261e}
.error{color:#b3261e;font-weight:600;white-space:pre-wrap}pre{margin:4px 0 0;font-size:11px;white-space:pre-wrap}
.controls{margin:6px 0 10px;display:flex;gap:18px;align-items:center}.controls input[type=search]{width:280px;padding:3px 6px}
.legend{color:#555;font-size:12px;max-width:1100px}
)css";

// Filter box and "only failures"; after load it marks the page ready and
// counts images that failed to load (tests/CMakeLists.txt: validate_report_html).
const char* kScript = R"js(
(function () {
  var rows = Array.prototype.slice.call(document.querySelectorAll('tr.case'));
  var box = document.getElementById('case-filter'), only = document.getElementById('only-failures');
  var shown = document.getElementById('shown-count');
  function apply() {
    var q = box.value.trim().toLowerCase(), n = 0;
    rows.forEach(function (r) {
      var hide = (only.checked && r.classList.contains('passed')) || (q && r.dataset.name.toLowerCase().indexOf(q) < 0);
      r.hidden = hide;
      if (!hide) n++;
    });
    shown.textContent = n + ' of ' + rows.length + ' cases shown';
  }
  box.addEventListener('input', apply);
  only.addEventListener('change', apply);
  apply();
  window.addEventListener('load', function () {
    var broken = Array.prototype.filter.call(document.images, function (i) { return !i.complete || i.naturalWidth === 0; });
    document.body.dataset.brokenImages = String(broken.length);
    document.body.dataset.ready = '1';
  });
})();
)js";

}  // namespace

void writeReport(const HarnessOptions& options, const GlInfo& gl, const std::string& model, const RunSummary& run) {
  using nlohmann::json;
  std::filesystem::create_directories(options.reportDir);
  json j;
  const std::string date = utcNow();
  j["tool"] = "fibertwin validate";
  j["version"] = buildVersion();
  j["commit"] = buildCommit();
  j["date_utc"] = date;
  j["command_line"] = options.commandLine;
  j["model"] = model;
  j["injected_fault"] = options.inject;
  j["filter"] = options.filter;
  j["all_passed"] = run.allPassed;
  j["seconds"] = run.seconds;
  j["renderer"] = {{"backend", gl.backend},        {"vendor", gl.vendor},
                   {"renderer", gl.renderer},      {"version", gl.version},
                   {"glsl_version", gl.glslVersion}, {"software", gl.isSoftware},
                   {"max_tess_gen_level", gl.maxTessGenLevel}};
  j["fiber_options"] = {{"regular_fibers_per_ply", options.fiber.regularFibersPerPly},
                        {"max_subdivisions", options.fiber.maxSubdivisions},
                        {"yarn_radius", run.yarnRadius},
                        {"yarn_radius_source", run.yarnRadiusSource},
                        {"fiber_radius", options.fiber.fiberRadius},
                        {"seed", options.fiber.seed},
                        {"lod_view", fmt::format("{}x{}", options.lodWidth, options.lodHeight)},
                        {"lod_threshold_px", options.lodThresholdPx}};
  json cases = json::array();
  for (const CaseResult& r : run.results) {
    json c;
    c["name"] = r.name;
    c["group"] = r.group;
    c["path"] = r.path;
    c["pass"] = r.pass;
    if (!r.error.empty()) c["error"] = r.error;
    c["timing"] = {{"cpu_ms", r.cpuMilliseconds}, {"gpu_ms", r.gpuMilliseconds}, {"gpu_method", r.gpuTiming},
                   {"wall_ms", r.wallMilliseconds}};
    json ms = json::array();
    for (const Metric& m : r.metrics)
      ms.push_back({{"name", m.name},
                    {"value", m.value},
                    {"tolerance", m.tolerance},
                    {"unit", m.unit},
                    {"justification", m.justification},
                    {"gating", m.gating},
                    {"pass", m.pass()}});
    c["metrics"] = ms;
    c["error_histogram_log10"] = {
        {"first_decade", r.histogram.firstDecade}, {"counts", r.histogram.counts}, {"metric", r.histogramMetric}};
    c["images"] = r.images;
    if (!r.imageCaptions.empty()) c["image_captions"] = r.imageCaptions;
    if (!r.details.empty()) c["details"] = r.details;
    cases.push_back(c);
  }
  j["cases"] = cases;
  json failedCases = json::array();
  for (const CaseResult& r : run.results)
    if (!r.pass) failedCases.push_back(r.name);
  j["failed_cases"] = failedCases;
  std::ofstream(options.reportDir / "report.json") << j.dump(2) << "\n";

  size_t passed = 0;
  for (const CaseResult& r : run.results) passed += r.pass;
  const size_t failed = run.results.size() - passed;
  // Failures first, otherwise in run order.
  std::vector<const CaseResult*> order;
  for (const CaseResult& r : run.results) order.push_back(&r);
  std::stable_partition(order.begin(), order.end(), [](const CaseResult* r) { return !r->pass; });

  std::ofstream h(options.reportDir / "index.html");
  const std::string verdict =
      run.results.empty() ? "no case ran"
      : failed == 0       ? fmt::format("all {} cases passed", run.results.size())
                          : fmt::format("{} of {} cases FAILED", failed, run.results.size());
  h << "<!doctype html><html lang='en'><head><meta charset='utf-8'>"
       "<meta name='viewport' content='width=device-width, initial-scale=1'>"
    << "<title>fibertwin validate — " << escape(model) << ": " << escape(verdict) << "</title><style>" << kStyle
    << "</style></head><body>\n";
  h << "<header id='verdict' class='verdict " << (run.allPassed ? "pass" : "fail") << "'><h1>fibertwin validate — "
    << escape(model) << ": " << escape(verdict) << "</h1><p>" << escape(gl.renderer) << " · " << escape(date) << " · "
    << fmt::format("{:.1f} s", run.seconds) << "</p></header><main>\n";

  h << "<table class='meta'>";
  auto row = [&](const char* k, const std::string& v) { h << "<tr><th>" << k << "</th><td>" << v << "</td></tr>"; };
  row("Command line", "<code>" + escape(options.commandLine.empty() ? "(library call)" : options.commandLine) + "</code>");
  row("Build", escape(versionLine()));
  row("Date", escape(date));
  row("Renderer", fmt::format("{} — {}, OpenGL {}, GLSL {}, backend {}{}", escape(gl.renderer), escape(gl.vendor),
                              escape(gl.version), escape(gl.glslVersion), escape(gl.backend),
                              gl.isSoftware ? " (software)" : ""));
  row("Model", escape(model));
  row("Fibers", fmt::format("{} regular fibers per ply, at most {} subdivisions (the screen decides), fiber radius {} "
                            "at the preset's scale, seed {}; presets fitted to yarn radius {:.4g} ({}); LoD view "
                            "{}×{}, threshold {} px",
                            options.fiber.regularFibersPerPly, options.fiber.maxSubdivisions,
                            options.fiber.fiberRadius, options.fiber.seed, run.yarnRadius,
                            escape(run.yarnRadiusSource), options.lodWidth, options.lodHeight,
                            options.lodThresholdPx));
  if (!options.filter.empty()) row("Filter", "<code>" + escape(options.filter) + "</code>");
  if (!options.inject.empty()) {
    const Fault* f = findFault(options.inject);
    row("Injected fault", "<b>" + escape(options.inject) + "</b>" + (f ? ": " + escape(f->description) : ""));
  }
  h << "</table>\n";

  h << fmt::format("<h2 id='failures'>Failures ({})</h2>\n", failed);
  if (failed == 0) {
    h << "<p>None: every gating metric of every case is within its tolerance.</p>\n";
  } else {
    h << "<ul class='failures'>";
    for (const CaseResult* r : order) {
      if (r->pass) break;
      h << "<li><a href='#" << anchor(r->name) << "'><code>" << escape(r->name) << "</code></a><ul>";
      if (!r->error.empty()) h << "<li class='why'>error: " << escape(r->error) << "</li>";
      for (const Metric& m : r->metrics)
        if (!m.pass())
          h << "<li class='why'>"
            << escape(fmt::format("{} = {:.3g} > {:.3g}{}", m.name, m.value, m.tolerance,
                                  m.tolerance > 0 ? ": " + ratioText(m.value / m.tolerance) + "× the tolerance"
                                                  : std::string(": must be exactly 0")))
            << "</li>";
      h << "</ul></li>";
    }
    h << "</ul>\n";
  }

  h << "<h2>Cases</h2>\n<p class='legend'>Each case compares the CPU reference with one GPU path. Each metric is "
       "drawn as its margin: the bar is value ÷ tolerance on a log scale from 1e-8 to 1e2, the dashed line is the "
       "tolerance (bars past it fail), the number beside it the share of the tolerance used (or how many times "
       "the tolerance the value is); a dot means a value of exactly 0. Italic metrics are informational. Hover a "
       "metric for its unit and why its tolerance is what it is. The histogram counts per-item errors by decade, "
       "with the tolerance of the metric it bins as a dashed line. Thumbnails: the CPU reference's output, then "
       "the GPU path's own, same view; the shading cases show the GPU image, the Embree ground truth and the FLIP "
       "error map.</p>\n";
  h << "<div class='controls'><label>Find <input id='case-filter' type='search' placeholder='case name'></label>"
       "<label><input id='only-failures' type='checkbox'> only failures</label><span id='shown-count'></span></div>\n";
  h << "<table class='cases'><thead><tr><th>case</th><th>result</th><th>metrics: value, tolerance, margin</th>"
       "<th>error histogram</th><th>images</th><th>ms<br>cpu / gpu / wall</th></tr></thead><tbody>\n";
  for (const CaseResult* rp : order) {
    const CaseResult& r = *rp;
    h << "<tr class='case " << (r.pass ? "passed" : "failed") << "' id='" << anchor(r.name) << "' data-name='"
      << escape(r.name) << "'><td class='name'>" << breakableName(r.name) << "</td><td><span class='badge "
      << (r.pass ? "pass'>pass" : "fail'>FAIL") << "</span></td><td>";
    if (!r.error.empty()) h << "<div class='error'>" << escape(r.error) << "</div>";
    h << "<table class='metrics'>";
    // Exact checks that hold (value 0, tolerance 0) share one line; a failing one gets its own row.
    std::string exactNames;
    size_t exactCount = 0;
    for (const Metric& m : r.metrics)
      if (m.gating && m.tolerance == 0.0 && m.value == 0.0) {
        exactNames += (exactCount++ ? ", " : "") + escape(m.name);
      }
    if (exactCount)
      h << "<tr class='exact'><td colspan='5'><span class='check'>✓</span> " << exactCount
        << " exact checks, all 0: <span class='names'>" << exactNames << "</span></td></tr>";
    double histogramTolerance = 0.0;
    for (const Metric& m : r.metrics) {
      if (m.name == r.histogramMetric) histogramTolerance = m.tolerance;
      if (m.gating && m.tolerance == 0.0 && m.value == 0.0) continue;
      const std::string cls = !m.gating ? "info" : m.pass() ? "ok" : "bad";
      h << "<tr class='" << cls << "' title='" << escape(m.unit + ": " + m.justification) << "'><td>"
        << escape(m.name) << "</td><td class='v'>" << fmt::format("{:.3g}", m.value) << "</td>";
      if (m.gating)
        h << "<td class='v'>" << (m.pass() ? "≤ " : "> ") << fmt::format("{:.3g}", m.tolerance) << "</td><td>"
          << marginSvg(m) << "</td><td class='ratio'>" << marginText(m) << "</td>";
      else
        h << "<td colspan='3'>" << escape(m.unit) << "</td>";
      h << "</tr>";
    }
    h << "</table>";
    if (!r.details.empty())
      h << "<details><summary>first differences</summary><pre>" << escape(r.details) << "</pre></details>";
    uint64_t binned = 0;
    for (uint64_t c : r.histogram.counts) binned += c;
    h << "</td><td>";
    if (binned)
      h << histogramSvg(r.histogram, histogramTolerance) << "<div class='caption'>"
        << escape(r.histogramMetric.empty() ? std::string("errors") : r.histogramMetric)
        << (histogramTolerance > 0 ? fmt::format(", tolerance {:.2g}", histogramTolerance) : std::string())
        << "</div>";
    h << "</td><td class='imgs'>";
    for (size_t i = 0; i < r.images.size(); ++i) {
      const std::string caption = i < r.imageCaptions.size() ? r.imageCaptions[i]
                                  : i == 0                   ? std::string("CPU reference")
                                                             : "GPU " + r.path;
      h << "<figure><img src='" << escape(r.images[i]) << "' width='120' alt='" << escape(caption) << ", "
        << escape(r.name) << "'><figcaption>" << escape(caption) << "</figcaption></figure>";
    }
    h << fmt::format("</td><td class='num'>{:.1f} / {:.1f} / {:.0f}</td></tr>\n", r.cpuMilliseconds, r.gpuMilliseconds,
                     r.wallMilliseconds);
  }
  h << "</tbody></table>\n<h2>Injectable faults</h2><p class='legend'><code>fibertwin validate --inject NAME</code> "
       "builds the GPU side with one of these bugs; each must fail a case (validation/faults.def).</p><ul>";
  for (const Fault& f : kFaults)
    h << "<li><code>" << escape(f.name) << "</code>: " << escape(f.description) << " (caught by <code>"
      << escape(f.caughtBy) << "</code>)</li>";
  h << "</ul></main><script>" << kScript << "</script></body></html>\n";
}

}  // namespace ft
