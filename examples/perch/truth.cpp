// SPDX-License-Identifier: BSL-1.0
#include "truth.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "json_reader.hpp"
#include "support/json_writer.hpp"

namespace perch::tool {
namespace {

float round2(float v) { return std::round(v * 100.0f) / 100.0f; }

std::string_view kind_name(support::limb_kind k) {
  switch (k) {
    case support::limb_kind::trunk:
      return "trunk";
    case support::limb_kind::twig:
      return "twig";
    case support::limb_kind::fragment:
      return "fragment";
    case support::limb_kind::limb:
      break;
  }
  return "limb";
}

}  // namespace

std::string truth_json(const truth_file& truth) {
  support::json_writer json(support::json_style::pretty);
  json.begin_object();
  json.member("generator", "perch synth").member("kind", truth.kind).member("seed", truth.seed);
  json.member("width", truth.width).member("height", truth.height).member("mm_per_px", truth.mm_per_px);
  json.key("limbs").begin_array();
  for (const support::limb_truth& limb : truth.limbs) {
    json.begin_object();
    json.member("kind", kind_name(limb.kind)).member("level", limb.level).member("parent", limb.parent);
    json.member("base_heading_rad", limb.base_heading_rad).member("curvature_per_px", limb.curvature_per_px);
    json.member("tree", limb.tree).member("exact_arc", limb.exact_arc);
    json.key("centreline").begin_array(support::json_layout::single_line);
    for (const Eigen::Vector2f& p : limb.centreline)
      json.begin_array().value(round2(p.x())).value(round2(p.y())).end_array();
    json.end_array();
    json.key("diameter_px").begin_array(support::json_layout::single_line);
    for (const float d : limb.diameter_px) json.value(round2(d));
    json.end_array();
    json.end_object();
  }
  json.end_array();
  json.end_object();
  return std::move(json).take();
}

std::string read_truth(const std::filesystem::path& path, truth_file& truth) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return "cannot open " + path.string();
  std::stringstream buffer;
  buffer << file.rdbuf();
  std::string error;
  const auto doc = parse_json(buffer.str(), error);
  if (!doc) return path.string() + ": " + error;
  const auto number = [&](const json_value& v, std::string_view key, double& out) {
    const json_value* m = v.find(key);
    if (m == nullptr || !m->is_number()) return false;
    out = m->number;
    return true;
  };
  double w = 0, h = 0, mm = 0, seed = 0;
  if (!number(*doc, "width", w) || !number(*doc, "height", h) || !number(*doc, "mm_per_px", mm))
    return path.string() + ": missing width, height or mm_per_px";
  (void)number(*doc, "seed", seed);
  truth.width = static_cast<int>(w);
  truth.height = static_cast<int>(h);
  truth.mm_per_px = static_cast<float>(mm);
  truth.seed = static_cast<std::uint32_t>(seed);
  if (const json_value* k = doc->find("kind"); k != nullptr && k->is_string()) truth.kind = k->text;
  const json_value* limbs = doc->find("limbs");
  if (limbs == nullptr || !limbs->is_array()) return path.string() + ": missing limbs";
  for (const json_value& l : limbs->items) {
    support::limb_truth limb;
    double v = 0;
    if (number(l, "level", v)) limb.level = static_cast<int>(v);
    if (number(l, "parent", v)) limb.parent = static_cast<int>(v);
    if (number(l, "base_heading_rad", v)) limb.base_heading_rad = static_cast<float>(v);
    if (number(l, "curvature_per_px", v)) limb.curvature_per_px = static_cast<float>(v);
    if (number(l, "tree", v)) limb.tree = static_cast<int>(v);
    // The arc's heading and curvature answer tangents only when the centreline samples it.
    if (const json_value* e = l.find("exact_arc"); e != nullptr && e->kind == json_value::type::boolean)
      limb.exact_arc = e->boolean;
    if (const json_value* k = l.find("kind"); k != nullptr && k->is_string())
      limb.kind = k->text == "trunk" ? support::limb_kind::trunk
                  : k->text == "twig" ? support::limb_kind::twig
                  : k->text == "fragment" ? support::limb_kind::fragment
                                      : support::limb_kind::limb;
    const json_value* c = l.find("centreline");
    const json_value* d = l.find("diameter_px");
    if (c == nullptr || d == nullptr || !c->is_array() || !d->is_array() || c->items.size() != d->items.size() ||
        c->items.size() < 2)
      return path.string() + ": a limb needs centreline and diameter_px of the same length (>= 2)";
    for (std::size_t i = 0; i < c->items.size(); ++i) {
      const json_value& p = c->items[i];
      if (!p.is_array() || p.items.size() != 2 || !p.items[0].is_number() || !p.items[1].is_number() ||
          !d->items[i].is_number())
        return path.string() + ": bad centreline point";
      limb.centreline.emplace_back(static_cast<float>(p.items[0].number), static_cast<float>(p.items[1].number));
      limb.diameter_px.push_back(static_cast<float>(d->items[i].number));
    }
    limb.arc_px.assign(limb.centreline.size(), 0.0f);
    for (std::size_t i = 1; i < limb.centreline.size(); ++i)
      limb.arc_px[i] = limb.arc_px[i - 1] + (limb.centreline[i] - limb.centreline[i - 1]).norm();
    truth.limbs.push_back(std::move(limb));
  }
  return {};
}

}  // namespace perch::tool
