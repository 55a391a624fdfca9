// SPDX-License-Identifier: BSL-1.0
#include "report.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>

#include "support/json_writer.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

using support::json_layout;
using support::json_style;
using support::json_writer;

/// Rounds to 1e-4 relative steps so the JSON stays short (still deterministic).
float tidy(float v) {
  if (!std::isfinite(v) || v == 0.0f) return v;
  const double magnitude = std::pow(10.0, std::floor(std::log10(std::abs(static_cast<double>(v)))) - 5.0);
  return static_cast<float>(std::round(static_cast<double>(v) / magnitude) * magnitude);
}

void write_pixel(json_writer& json, std::string_view key, pixel p) {
  json.key(key).begin_array(json_layout::single_line).value(p.x).value(p.y).end_array();
}

void write_site(json_writer& json, const perch_site& s) {
  const window_measures& m = s.window;
  json.begin_object();
  json.member("x", m.centre.x).member("y", m.centre.y);
  json.member("slope_deg", tidy(m.slope_deg));
  json.member("diameter_mm", tidy(m.claw_diameter_mm));
  json.member("curvature_per_mm", tidy(m.curvature_max_per_mm));
  json.member("slope_max_deg", tidy(m.slope_max_deg)).member("bend_deg", tidy(m.bend_deg));
  json.member("penalty", tidy(s.penalty));
  json.member("branch", m.branch).member("component", m.component);
  json.member("rank", s.rank + 1);
  json.member("heading_deg", tidy(m.heading_deg));
  write_pixel(json, "base_end", m.base_end);
  write_pixel(json, "tip_end", m.tip_end);
  if (m.has_position) {
    write_point3(json, "position_m", m.position_m);
    write_point3(json, "base_end_m", m.base_end_m);
    write_point3(json, "tip_end_m", m.tip_end_m);
    write_point3(json, "axis_m", m.axis_m);
  }
  json.end_object();
}

point2f input_point(const perch_result& r, pixel local) {
  return r.mask.to_input(point2f(static_cast<float>(local.x + r.mask.offset.x),
                                 static_cast<float>(local.y + r.mask.offset.y)));
}

/// Writes an input-frame coordinate: an integer at factor 1, else a rounded float.
void write_coordinate(json_writer& json, const perch_result& r, float v) {
  if (r.mask.factor == 1.0f)
    json.value(static_cast<long>(std::lround(v)));
  else
    json.value(std::round(v * 100.0f) / 100.0f);
}

/// The length of the longest limb, in analysed pixels (steps of 1 or √2).
float longest_limb_px(const perch_result& r) {
  float longest = 0;
  for (const skeleton_limb& limb : r.limbs) {
    float length = 0;
    for (std::size_t i = 1; i < limb.points.size(); ++i) {
      const bool diagonal = limb.points[i].x != limb.points[i - 1].x && limb.points[i].y != limb.points[i - 1].y;
      length += diagonal ? std::numbers::sqrt2_v<float> : 1.0f;
    }
    longest = std::max(longest, length);
  }
  return longest;
}

std::string format_mm(float mm) { return std::to_string(static_cast<long>(std::lround(mm))) + " mm"; }

}  // namespace

std::string_view status_name(perch_outcome outcome) noexcept {
  switch (outcome) {
    case perch_outcome::found:
      return "ok";
    case perch_outcome::no_perch:
      return "no_perch";
    case perch_outcome::no_tree:
      break;
  }
  return "no_tree";
}

std::string no_perch_reason(const perch_result& r, const platform_geometry& geometry) {
  if (r.outcome == perch_outcome::found) return {};
  if (r.outcome == perch_outcome::no_tree) return "the mask has no tree pixel";
  if (r.windows > 0) return "no window passed every constraint (see rejected and near_misses)";
  if (r.limbs.empty()) return "no window measured: no limb is left after pruning (only twigs and spurs)";
  const float analysed_mm_per_px = r.mm_per_px / r.mask.factor;
  return "no window measured: no limb has a stretch clear of junctions one drone width (" +
         format_mm(geometry.drone_width_mm) + ") long; the longest limb is " +
         format_mm(longest_limb_px(r) * analysed_mm_per_px) + " end to end";
}

void write_point3(json_writer& json, std::string_view key, const point3f& v) {
  json.key(key).begin_array(json_layout::single_line);
  for (int i = 0; i < 3; ++i) json.value(tidy(v[i]));
  json.end_array();
}

void write_source(json_writer& json, const document_source& source) {
  json.member("version", version).member("input", source.input);
  if (source.warnings.empty()) return;
  json.key("warnings").begin_array();
  for (const std::string& w : source.warnings) json.value(w);
  json.end_array();
}

std::string detect_json(const perch_result& r, const document_source& source, const platform_geometry& geometry) {
  json_writer json(json_style::pretty);
  json.begin_object();
  write_source(json, source);
  json.member("status", status_name(r.outcome));
  if (r.outcome != perch_outcome::found) json.member("reason", no_perch_reason(r, geometry));
  json.key("image").begin_object(json_layout::single_line);
  json.member("width", r.width).member("height", r.height).end_object();
  json.member("mm_per_px", tidy(r.mm_per_px));
  json.member("scale", r.scale);
  json.member("scale_uncertainty", tidy(r.scale_uncertainty));
  json.member("platform", r.platform);
  json.key("perch");
  if (r.sites.empty())
    json.null();
  else
    write_site(json, r.sites.front());
  json.key("candidates").begin_array();
  for (const perch_site& s : r.sites) write_site(json, s);
  json.end_array();
  json.key("rejected").begin_object();
  for (const rejection_count& c : r.rejections) json.member(c.constraint, c.windows);
  json.end_object();
  json.key("near_misses").begin_array();
  for (const near_miss& m : r.near_misses) {
    if (!m.present) continue;
    const point2f c = to_point(m.window.centre);  // input-image pixels, like the sites
    json.begin_object(json_layout::single_line);
    json.member("constraint", m.constraint).member("miss", tidy(m.miss)).member("unit", m.unit);
    json.key("x");
    write_coordinate(json, r, c.x());
    json.key("y");
    write_coordinate(json, r, c.y());
    json.end_object();
  }
  json.end_array();
  json.key("windows").begin_object(json_layout::single_line);
  json.member("measured", r.windows).member("viable", r.viable).end_object();
  json.key("graph").begin_object(json_layout::single_line);
  json.member("nodes", r.graph.node_count()).member("edges", r.graph.branch_count());
  json.member("components", r.graph.component_count());
  json.member("holes_filled", r.holes.filled);
  json.end_object();
  json.key("bridges").begin_array();
  for (const perch_bridge& b : r.bridges) {
    json.begin_object(json_layout::single_line);
    write_pixel(json, "from", b.from);
    write_pixel(json, "to", b.to);
    json.member("gap_px", tidy(b.gap_px)).member("kind", to_string(b.kind));
    json.end_object();
  }
  json.end_array();
  const stage_timings& t = r.timing;
  json.key("timing_ms").begin_object(json_layout::single_line);
  json.member("prepare", tidy(t.prepare_ms)).member("distance", tidy(t.distance_ms));
  json.member("skeleton", tidy(t.skeleton_ms)).member("graph", tidy(t.graph_ms));
  json.member("prune", tidy(t.prune_ms)).member("bridge", tidy(t.bridge_ms));
  json.member("windows", tidy(t.windows_ms));
  json.member("ranking", tidy(t.ranking_ms)).member("total", tidy(t.total_ms));
  json.end_object();
  json.member("cold", r.cold);
  json.end_object();
  return std::move(json).take();
}

std::string graph_json(const perch_result& r, const document_source& source) {
  json_writer json(json_style::pretty);
  json.begin_object();
  write_source(json, source);
  json.member("components", r.graph.component_count());
  json.member("mm_per_px", tidy(r.mm_per_px));
  json.key("nodes").begin_array();
  {
    r.graph.for_each_node([&](const skeleton_node& n) {
      const point2f p = input_point(r, n.position);
      json.begin_object(json_layout::single_line);
      json.member("id", n.id);
      json.key("x");
      write_coordinate(json, r, p.x());
      json.key("y");
      write_coordinate(json, r, p.y());
      json.member("kind", to_string(n.kind)).member("component", n.component);
      json.member("trunk", n.trunk);
      json.end_object();
    });
  }
  json.end_array();
  json.key("edges").begin_array();
  {
    r.graph.for_each_branch([&](const skeleton_branch& b) {
      json.begin_object();
      json.member("id", b.id).member("from", b.from).member("to", b.to);
      json.member("length_px", tidy(b.length_px));
      json.member("mean_diameter_px", tidy(b.mean_diameter_px));
      json.member("type", to_string(b.type));
      json.key("polyline").begin_array(json_layout::single_line);
      for (const pixel q : b.points) {
        const point2f p = input_point(r, q);
        json.begin_array();
        write_coordinate(json, r, p.x());
        write_coordinate(json, r, p.y());
        json.end_array();
      }
      json.end_array();
      json.end_object();
    });
  }
  json.end_array();
  json.end_object();
  return std::move(json).take();
}

}  // namespace perch::tool
