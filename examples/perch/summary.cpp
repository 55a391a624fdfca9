// SPDX-License-Identifier: BSL-1.0
#include "summary.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "json_reader.hpp"
#include "support/json_writer.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

using support::json_layout;
using support::json_style;
using support::json_writer;

constexpr const char* statuses[] = {"ok", "no_perch", "no_tree", "error"};

void write_row(json_writer& json, const summary_row& row) {
  json.begin_object(json_layout::single_line);
  json.member("file", row.file).member("status", row.status).member("reason", row.reason);
  json.key("warnings").begin_array();
  for (const std::string& w : row.warnings) json.value(w);
  json.end_array();
  const auto number = [&](const char* key, const float* v) {
    if (v != nullptr)
      json.member(key, *v);
    else
      json.member(key, nullptr);
  };
  const summary_perch* p = row.perch ? &*row.perch : nullptr;
  number("x", p ? &p->x : nullptr);
  number("y", p ? &p->y : nullptr);
  number("slope_deg", p ? &p->slope_deg : nullptr);
  number("diameter_mm", p ? &p->diameter_mm : nullptr);
  number("penalty", p ? &p->penalty : nullptr);
  json.member("time_ms", row.time_ms);
  json.end_object();
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

/// Shortest text that reads back as `v` (as the JSON has it).
std::string csv_number(float v) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  return ec == std::errc{} ? std::string(buffer, end) : std::string();
}

std::string joined(const std::vector<std::string>& parts, const char* separator) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i == 0 ? "" : separator) + parts[i];
  return out;
}

/// Text of member `key` of `v` (empty when missing or not a string).
std::string text_of(const json_value& v, const char* key) {
  const json_value* m = v.find(key);
  return m != nullptr && m->is_string() ? m->text : std::string();
}

std::optional<double> number_of(const json_value& v, const char* key) {
  const json_value* m = v.find(key);
  if (m == nullptr || !m->is_number()) return std::nullopt;
  return m->number;
}

std::optional<float> float_of(const json_value& v, const char* key) {
  const auto n = number_of(v, key);
  if (!n) return std::nullopt;
  return static_cast<float>(*n);
}

summary_row row_from(const json_value& v) {
  summary_row row;
  row.file = text_of(v, "file");
  row.status = text_of(v, "status");
  row.reason = text_of(v, "reason");
  if (const json_value* w = v.find("warnings"))
    for (const json_value& item : w->items) row.warnings.push_back(item.text);
  const auto x = float_of(v, "x"), y = float_of(v, "y"), slope = float_of(v, "slope_deg"),
             diameter = float_of(v, "diameter_mm"), penalty = float_of(v, "penalty");
  if (x && y && slope && diameter && penalty) row.perch = summary_perch{*x, *y, *slope, *diameter, *penalty};
  row.time_ms = float_of(v, "time_ms").value_or(0.0f);
  return row;
}

}  // namespace

std::string summary_json(const batch_summary& s) {
  json_writer json(json_style::pretty);
  json.begin_object();
  json.member("version", version).member("input", s.input);
  json.key("shard");
  if (s.shard) {
    json.begin_object(json_layout::single_line);
    json.member("index", s.shard->index).member("count", s.shard->count).end_object();
  } else {
    json.null();
  }
  if (s.merged_shards > 0) json.member("merged_shards", s.merged_shards);
  json.member("files_in_input", s.files_in_input).member("exit_code", s.exit_code);
  json.key("counts").begin_object(json_layout::single_line);
  for (const char* status : statuses)
    json.member(status, std::count_if(s.rows.begin(), s.rows.end(),
                                      [&](const summary_row& r) { return r.status == status; }));
  json.end_object();
  json.key("rows").begin_array();
  for (const summary_row& row : s.rows) write_row(json, row);
  json.end_array();
  json.end_object();
  return std::move(json).take();
}

std::string summary_csv(const batch_summary& s) {
  std::string out = "file,status,reason,warnings,x,y,slope_deg,diameter_mm,penalty,time_ms\n";
  for (const summary_row& row : s.rows) {
    out += csv_field(row.file) + "," + csv_field(row.status) + "," + csv_field(row.reason) + "," +
           csv_field(joined(row.warnings, "; "));
    if (row.perch) {
      for (const float v : {row.perch->x, row.perch->y, row.perch->slope_deg, row.perch->diameter_mm,
                             row.perch->penalty})
        out += "," + csv_number(v);
    } else {
      out += ",,,,,";
    }
    out += "," + csv_number(row.time_ms) + "\n";
  }
  return out;
}

std::string read_summary(const std::filesystem::path& dir, batch_summary& out) {
  const std::filesystem::path path = dir / "summary.json";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return path.string() + " does not exist: not a batch's output";
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  std::string error;
  const auto doc = parse_json(text.str(), error);
  if (!doc || !doc->is_object()) return path.string() + ": not a summary (" + error + ")";
  out = batch_summary{};
  out.input = text_of(*doc, "input");
  if (const json_value* shard = doc->find("shard"); shard != nullptr && shard->is_object()) {
    const auto index = number_of(*shard, "index"), count = number_of(*shard, "count");
    if (index && count) out.shard = shard_spec{static_cast<int>(*index), static_cast<int>(*count)};
  }
  out.files_in_input = static_cast<std::size_t>(number_of(*doc, "files_in_input").value_or(0.0));
  out.exit_code = static_cast<int>(number_of(*doc, "exit_code").value_or(0.0));
  const json_value* rows = doc->find("rows");
  if (rows == nullptr || !rows->is_array()) return path.string() + ": no \"rows\" array";
  for (const json_value& row : rows->items) out.rows.push_back(row_from(row));
  return {};
}

std::string merge_summaries(std::vector<batch_summary> shards, batch_summary& merged) {
  merged = batch_summary{};
  if (shards.empty()) return "nothing to merge";
  std::map<int, int> seen;  // shard index -> how many times
  const int count = shards.front().shard ? shards.front().shard->count : 0;
  for (const batch_summary& s : shards) {
    if (!s.shard) return "a summary of a whole folder (no --shard) cannot be merged";
    if (s.shard->count != count)
      return "shards of different counts (" + std::to_string(count) + " and " + std::to_string(s.shard->count) + ")";
    if (++seen[s.shard->index] > 1) return "shard " + std::to_string(s.shard->index) + " given twice";
    if (s.files_in_input != shards.front().files_in_input) return "shards of different folders (file counts differ)";
  }
  for (int k = 1; k <= count; ++k)
    if (seen.count(k) == 0) return "shard " + std::to_string(k) + "/" + std::to_string(count) + " is missing";
  merged.input = shards.front().input;
  merged.merged_shards = count;
  merged.files_in_input = shards.front().files_in_input;
  for (batch_summary& s : shards) {
    if (s.exit_code == exit_internal || merged.exit_code == exit_internal)
      merged.exit_code = exit_internal;
    else if (s.exit_code != exit_ok)
      merged.exit_code = s.exit_code;
    merged.rows.insert(merged.rows.end(), std::make_move_iterator(s.rows.begin()),
                       std::make_move_iterator(s.rows.end()));
  }
  std::sort(merged.rows.begin(), merged.rows.end(),
            [](const summary_row& a, const summary_row& b) { return a.file < b.file; });
  if (merged.rows.size() != merged.files_in_input)
    return "the shards hold " + std::to_string(merged.rows.size()) + " rows, the folder " +
           std::to_string(merged.files_in_input) + " files";
  return {};
}

}  // namespace perch::tool
