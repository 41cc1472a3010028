#include "validation/report.h"

#include <algorithm>
#include <chrono>
#include <fmt/format.h>
#include <fstream>

#include <nlohmann/json.hpp>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb/stb_image_write.h>

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

// Inline SVG bar chart of a log10 error histogram.
std::string histogramSvg(const ErrorHistogram& h) {
  const uint64_t top = std::max<uint64_t>(1, *std::max_element(h.counts.begin(), h.counts.end()));
  const int w = 16, height = 40;
  std::string s = fmt::format("<svg width='{}' height='{}' class='hist'>", w * h.counts.size(), height + 12);
  for (size_t i = 0; i < h.counts.size(); ++i) {
    const int bar = h.counts[i] ? std::max(1, static_cast<int>(height * h.counts[i] / top)) : 0;
    s += fmt::format("<rect x='{}' y='{}' width='{}' height='{}'><title>[1e{}, 1e{}): {}</title></rect>", i * w + 1,
                     height - bar, w - 2, bar, static_cast<int>(h.firstDecade) + int(i),
                     static_cast<int>(h.firstDecade) + int(i) + 1, h.counts[i]);
  }
  s += fmt::format("<text x='0' y='{}'>1e{}</text><text x='{}' y='{}' text-anchor='end'>1e{}</text></svg>",
                   height + 11, static_cast<int>(h.firstDecade), w * h.counts.size(), height + 11,
                   static_cast<int>(h.firstDecade) + int(h.counts.size()));
  return s;
}

}  // namespace

void writeReport(const HarnessOptions& options, const GlInfo& gl, const std::string& model, const RunSummary& run) {
  using nlohmann::json;
  std::filesystem::create_directories(options.reportDir);
  json j;
  j["tool"] = "fibertwin validate";
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
    c["timing"] = {{"cpu_ms", r.cpuMilliseconds}, {"gpu_ms", r.gpuMilliseconds}, {"gpu_method", r.gpuTiming}};
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
    c["error_histogram_log10"] = {{"first_decade", r.histogram.firstDecade}, {"counts", r.histogram.counts}};
    c["images"] = r.images;
    if (!r.details.empty()) c["details"] = r.details;
    cases.push_back(c);
  }
  j["cases"] = cases;
  std::ofstream(options.reportDir / "report.json") << j.dump(2) << "\n";

  size_t passed = 0;
  for (const CaseResult& r : run.results) passed += r.pass;
  std::ofstream h(options.reportDir / "index.html");
  h << "<!doctype html><html><head><meta charset='utf-8'><title>fibertwin validation</title><style>"
       "body{font:14px system-ui,sans-serif;margin:2em;color:#222}table{border-collapse:collapse}"
       "td,th{border:1px solid #ccc;padding:3px 6px;vertical-align:top}th{background:#eee}"
       ".ok{color:#060;font-weight:bold}.fail{color:#b00;font-weight:bold}.hist rect{fill:#48c}"
       ".hist text{font-size:9px}img{border:1px solid #999;margin-right:4px}pre{margin:0;font-size:11px}"
       "td.num{text-align:right;font-family:monospace}td.imgs{white-space:nowrap}figure{display:inline-block;margin:0 4px 0 0}"
       "figcaption{font-size:11px;color:#555}</style></head><body>\n";
  h << fmt::format("<h1>fibertwin validate — {}</h1>\n", escape(model));
  h << fmt::format("<p><b>{}</b> of {} cases passed{} in {:.1f} s. Renderer: {} ({}, {}, {}).</p>\n", passed,
                   run.results.size(), options.inject.empty() ? "" : ", injected fault <b>" + options.inject + "</b>",
                   run.seconds, escape(gl.renderer), escape(gl.vendor), escape(gl.version), escape(gl.backend));
  h << "<p>Each case compares the CPU reference with one GPU path. Metrics in <i>italics</i> are informational. "
       "The histogram shows per-vertex errors by decade, 1e-10 … 1e0 (world units; radians for frames). "
       "Thumbnails: the CPU reference's vertices, then the GPU path's own rendering, same view.</p>\n";
  h << "<table><tr><th>case</th><th>result</th><th>metrics (value ≤ tolerance)</th><th>error histogram</th>"
       "<th>CPU / GPU</th><th>ms (cpu / gpu)</th></tr>\n";
  for (const CaseResult& r : run.results) {
    h << "<tr><td>" << escape(r.name) << "</td><td class='" << (r.pass ? "ok'>pass" : "fail'>FAIL") << "</td><td>";
    if (!r.error.empty()) h << "<div class='fail'>" << escape(r.error) << "</div>";
    for (const Metric& m : r.metrics) {
      const std::string text = fmt::format("{} = {:.3g}{}", m.name, m.value,
                                           m.gating ? fmt::format(" ≤ {:.3g}", m.tolerance) : std::string());
      h << "<div title='" << escape(m.unit + ": " + m.justification) << "'"
        << (m.gating ? (m.pass() ? "" : " class='fail'") : " style='font-style:italic'") << ">" << escape(text)
        << "</div>";
    }
    if (!r.details.empty()) h << "<details><summary>first differences</summary><pre>" << escape(r.details) << "</pre></details>";
    h << "</td><td>" << histogramSvg(r.histogram) << "</td><td class='imgs'>";
    for (size_t i = 0; i < r.images.size(); ++i)
      h << "<figure><img src='" << escape(r.images[i]) << "' width='192'><figcaption>"
        << (i == 0 ? "CPU reference" : "GPU " + r.path) << "</figcaption></figure>";
    h << fmt::format("</td><td class='num'>{:.1f} / {:.1f}</td></tr>\n", r.cpuMilliseconds, r.gpuMilliseconds);
  }
  h << "</table><h2>Injectable faults</h2><ul>";
  for (const Fault& f : kFaults)
    h << "<li><code>" << f.name << "</code>: " << escape(f.description) << " (caught by " << f.caughtBy << ")</li>";
  h << "</ul></body></html>\n";
}

}  // namespace ft
