// text_fields.h — the field parsing of the tab-separated preset tables
// (data/yarn-presets.tsv, data/fabric-bcsdf.tsv): whole-field numbers only.
#pragma once
#include <charconv>
#include <optional>
#include <string_view>
#include <vector>

namespace ft {

inline std::string_view trimField(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// The fields of one line, trimmed of spaces and a CR.
inline std::vector<std::string_view> splitTabs(std::string_view line) {
  std::vector<std::string_view> out;
  size_t start = 0;
  for (;;) {
    const size_t tab = line.find('\t', start);
    out.push_back(trimField(line.substr(start, tab == std::string_view::npos ? tab : tab - start)));
    if (tab == std::string_view::npos) return out;
    start = tab + 1;
  }
}

// Whole-field parses: from_chars must consume everything (no "1.5x", no " 2").
inline std::optional<long long> parseWholeInt(std::string_view s) {
  long long v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

inline std::optional<double> parseWholeReal(std::string_view s) {
  double v = 0.0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

}  // namespace ft
