// SPDX-License-Identifier: BSL-1.0
// ascii_art.hpp's mask parser, compiled once into perch_support.
#include "support/ascii_art.hpp"

namespace perch::support {

image<std::uint8_t> mask_from_ascii(std::string_view art) {
  std::vector<std::string_view> rows;
  std::size_t start = 0;
  while (start <= art.size()) {
    std::size_t end = art.find('\n', start);
    if (end == std::string_view::npos) end = art.size();
    rows.push_back(art.substr(start, end - start));
    start = end + 1;
  }
  auto blank = [](std::string_view r) {
    return std::all_of(r.begin(), r.end(), [](char c) { return c == ' ' || c == '\t'; });
  };
  while (!rows.empty() && blank(rows.front())) rows.erase(rows.begin());
  while (!rows.empty() && blank(rows.back())) rows.pop_back();
  std::size_t indent = std::string_view::npos;
  for (auto r : rows)
    if (!blank(r)) indent = std::min(indent, r.find_first_not_of(" \t"));
  for (auto& r : rows) r = r.size() > indent ? r.substr(indent) : std::string_view{};
  std::size_t width = 0;
  for (auto r : rows) width = std::max(width, r.find_last_not_of(" \t") + 1);
  image<std::uint8_t> mask(static_cast<int>(width), static_cast<int>(rows.size()), 0);
  for (std::size_t y = 0; y < rows.size(); ++y)
    for (std::size_t x = 0; x < rows[y].size(); ++x)
      mask(static_cast<int>(x), static_cast<int>(y)) = is_ink(rows[y][x]) ? 1 : 0;
  return mask;
}

}  // namespace perch::support
