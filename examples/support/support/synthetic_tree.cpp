// SPDX-License-Identifier: BSL-1.0
// synthetic_tree.hpp's drawing, tree generator and truth, compiled once into perch_support.
#include "support/synthetic_tree.hpp"

namespace perch::support {

void draw_capsule(image_view<std::uint8_t> img, Eigen::Vector2f a, Eigen::Vector2f b,
                  float radius_a, float radius_b, std::uint8_t value) {
  if (img.empty() || !(radius_a >= 0.0f) || !(radius_b >= 0.0f)) return;
  if (!a.allFinite() || !b.allFinite()) return;
  const float r_max = std::max(radius_a, radius_b);
  const float fx0 = std::floor(std::min(a.x(), b.x()) - r_max);
  const float fx1 = std::ceil(std::max(a.x(), b.x()) + r_max);
  const float fy0 = std::floor(std::min(a.y(), b.y()) - r_max);
  const float fy1 = std::ceil(std::max(a.y(), b.y()) + r_max);
  const float w = static_cast<float>(img.width() - 1);
  const float h = static_cast<float>(img.height() - 1);
  if (fx1 < 0.0f || fy1 < 0.0f || fx0 > w || fy0 > h) return;
  const int x0 = static_cast<int>(std::max(fx0, 0.0f));
  const int x1 = static_cast<int>(std::min(fx1, w));
  const int y0 = static_cast<int>(std::max(fy0, 0.0f));
  const int y1 = static_cast<int>(std::min(fy1, h));
  const Eigen::Vector2f ab = b - a;
  const float len2 = ab.squaredNorm();
  const float inv_len2 = len2 > 0.0f ? 1.0f / len2 : 0.0f;
  const float dr = radius_b - radius_a;
  for (int y = y0; y <= y1; ++y) {
    const auto row = img.row(y);
    const float py = static_cast<float>(y) - a.y();
    for (int x = x0; x <= x1; ++x) {
      const float px = static_cast<float>(x) - a.x();
      float t = (px * ab.x() + py * ab.y()) * inv_len2;
      t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
      const float dx = px - t * ab.x();
      const float dy = py - t * ab.y();
      const float r = radius_a + t * dr;
      if (dx * dx + dy * dy <= r * r) row[static_cast<std::size_t>(x)] = value;
    }
  }
}

void draw_polyline(image_view<std::uint8_t> img, const std::vector<Eigen::Vector2f>& points,
                   const std::vector<float>& radii, std::uint8_t value) {
  if (points.empty() || points.size() != radii.size()) return;
  if (points.size() == 1) {
    draw_disc(img, points[0], radii[0], value);
    return;
  }
  for (std::size_t i = 0; i + 1 < points.size(); ++i)
    draw_capsule(img, points[i], points[i + 1], radii[i], radii[i + 1], value);
}

std::vector<Eigen::Vector2f> arc_points(Eigen::Vector2f centre, float arc_radius, float start_rad,
                                        float end_rad, float max_step_px) {
  const double sweep = static_cast<double>(end_rad) - static_cast<double>(start_rad);
  const double length = std::abs(sweep) * static_cast<double>(std::abs(arc_radius));
  const double step = max_step_px > 0.25f ? static_cast<double>(max_step_px) : 0.25;
  const int n = std::clamp(static_cast<int>(std::ceil(length / step)), 1, 1 << 20);
  std::vector<Eigen::Vector2f> points;
  points.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) {
    double s = 0.0, c = 0.0;
    detail::sin_cos(static_cast<double>(start_rad) + sweep * i / n, s, c);
    points.emplace_back(
        static_cast<float>(static_cast<double>(centre.x()) + static_cast<double>(arc_radius) * c),
        static_cast<float>(static_cast<double>(centre.y()) + static_cast<double>(arc_radius) * s));
  }
  return points;
}

void draw_arc(image_view<std::uint8_t> img, Eigen::Vector2f centre, float arc_radius,
              float start_rad, float end_rad, float stroke_radius, std::uint8_t value) {
  const auto points =
      arc_points(centre, arc_radius, start_rad, end_rad, std::max(1.0f, 0.5f * stroke_radius));
  draw_polyline(img, points, std::vector<float>(points.size(), stroke_radius), value);
}

limb_location locate(const std::vector<limb_truth>& limbs, Eigen::Vector2f p,
                     limb_set which) noexcept {
  limb_location best;
  float best_depth = std::numeric_limits<float>::infinity();
  for (std::size_t li = 0; li < limbs.size(); ++li) {
    const limb_truth& limb = limbs[li];
    if (which == limb_set::without_twigs && limb.kind == limb_kind::twig) continue;
    const auto& c = limb.centreline;
    if (c.size() < 2 || limb.diameter_px.size() != c.size() || limb.arc_px.size() != c.size())
      continue;
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
      const Eigen::Vector2f ab = c[i + 1] - c[i];
      const float len2 = ab.squaredNorm();
      float t = len2 > 0.0f ? (p - c[i]).dot(ab) / len2 : 0.0f;
      t = std::clamp(t, 0.0f, 1.0f);
      const Eigen::Vector2f q = c[i] + t * ab;
      const float dist = (p - q).norm();
      const float diameter =
          limb.diameter_px[i] + t * (limb.diameter_px[i + 1] - limb.diameter_px[i]);
      const float depth = dist - 0.5f * diameter;
      if (depth < best_depth) {
        best_depth = depth;
        best.limb = static_cast<int>(li);
        best.arc_px = limb.arc_px[i] + t * (limb.arc_px[i + 1] - limb.arc_px[i]);
        best.distance_px = dist;
        best.diameter_px = diameter;
        best.closest = q;
      }
    }
  }
  if (best.limb >= 0) {
    const limb_truth& limb = limbs[static_cast<std::size_t>(best.limb)];
    best.slope_deg = truth_slope_deg_at(limb, best.arc_px);
    best.curvature_per_px = truth_curvature_at(limb, best.arc_px);
  }
  return best;
}

namespace detail {

/// A limb waiting to be grown.
struct limb_seed {
  int parent = -1;
  double parent_arc = 0.0;
  Eigen::Vector2d base{0.0, 0.0};
  double heading = 0.0;   ///< rad from vertical-up, + towards +x
  double diameter = 0.0;  ///< px at the base
  double length = 0.0;    ///< px
  int level = 0;
  limb_kind kind = limb_kind::limb;
  bool decoy = false;  ///< `perch_supply::none`: a side limb that never forks
  int tree = 0;
};

/// Where and how big `grow_tree` grows a tree (the defaults grow the first tree).
struct tree_plan {
  double base_x_lo = 0.4, base_x_hi = 0.6;  ///< trunk base, fraction of the width
  double size = 1.0;                        ///< trunk diameter and height factor
  std::uint32_t seed_mix = 0;               ///< xor-ed into the seed
  int tree = 0;
};

/// `perch_supply::none`: structural limbs stay within this of vertical.
inline constexpr double steep_heading_max = 30.0 * (pi / 180.0);

/// The centreline of a circular arc of `length` from `base` with initial `heading` and
/// curvature `kappa`, as points at most `step` apart, with arc lengths.
void sample_arc(const limb_seed& seed, double kappa, double step, limb_truth& limb) {
  const int n = std::clamp(static_cast<int>(std::ceil(seed.length / step)), 1, 4096);
  limb.centreline.clear();
  limb.arc_px.clear();
  limb.centreline.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) {
    const double s = seed.length * i / n;
    // Exact arc: p(s) = base + chord(s)·(sin, -cos)(heading + κs/2), chord = 2 sin(κs/2)/κ.
    double chord = s;
    if (std::abs(kappa * s) > 1e-9) {
      double hs = 0.0, hc = 0.0;
      sin_cos(0.5 * kappa * s, hs, hc);
      chord = 2.0 * hs / kappa;
    }
    double ms = 0.0, mc = 0.0;
    sin_cos(seed.heading + 0.5 * kappa * s, ms, mc);
    limb.centreline.emplace_back(static_cast<float>(seed.base.x() + chord * ms),
                                 static_cast<float>(seed.base.y() - chord * mc));
  }
  limb.arc_px.assign(limb.centreline.size(), 0.0f);
  double acc = 0.0;
  for (std::size_t i = 1; i < limb.centreline.size(); ++i) {
    acc += static_cast<double>((limb.centreline[i] - limb.centreline[i - 1]).norm());
    limb.arc_px[i] = static_cast<float>(acc);
  }
}

/// A limb's heading away from its arc: low-frequency sinusoids (`tree_options::bending`) and
/// kinks (`tree_options::kinks`). Zero everywhere when both are off.
struct heading_wander {
  struct wave {
    double amplitude, omega, phase;
  };
  std::vector<wave> waves;
  std::vector<std::pair<double, double>> kinks;  ///< (arc, heading jump), ascending arc
  [[nodiscard]] bool empty() const noexcept { return waves.empty() && kinks.empty(); }
  /// The heading offset at arc u (0 at the base: each wave starts at its phase's sine).
  [[nodiscard]] double at(double u) const noexcept {
    double h = 0.0;
    for (const wave& w : waves) {
      double s1 = 0.0, c1 = 0.0, s0 = 0.0, c0 = 0.0;
      sin_cos(w.omega * u + w.phase, s1, c1);
      sin_cos(w.phase, s0, c0);
      h += w.amplitude * (s1 - s0);
    }
    for (const auto& k : kinks)
      if (u >= k.first) h += k.second;
    return h;
  }
};

/// Draws the wander of a limb of `length` (a stream of its own, so the options off leave every
/// other draw, and the tree, as before).
heading_wander draw_wander(const tree_options& o, std::uint32_t stream, double length, bool trunk) {
  heading_wander w;
  const double bending = std::clamp(static_cast<double>(o.bending), 0.0, 1.0);
  const int kinks = trunk ? 0 : std::clamp(o.kinks, 0, 8);
  if (!(bending > 0.0) && kinks == 0) return w;
  tree_random rng(stream);
  if (bending > 0.0) {
    const int n = rng.integer(1, 3);
    for (int j = 0; j < n; ++j) {
      const double amplitude = bending * rng.uniform(4.0, 12.0) * deg * rng.sign();
      const double periods = rng.uniform(0.3, 1.5);
      const double phase = rng.uniform(0.0, 2.0 * pi);
      const double span = std::max({length, 0.2 * static_cast<double>(o.height), 1.0});
      w.waves.push_back({amplitude, 2.0 * pi * periods / span, phase});
    }
  }
  const int count = rng.integer(0, kinks);
  for (int k = 0; k < count; ++k)
    w.kinks.emplace_back(length * rng.uniform(0.2, 0.8),
                         rng.sign() * rng.uniform(20.0, 60.0) * deg);
  std::sort(w.kinks.begin(), w.kinks.end());
  return w;
}

/// The centreline of a limb whose heading is heading + κ·u + wander(u), clamped to ±`clamp`
/// (rad; ≥ π: none), integrated at the midpoint of steps at most `step` long, with a vertex at
/// every kink. Returns the heading at the tip.
double sample_wandering(const limb_seed& seed, double kappa, const heading_wander& w, double clamp,
                        double step, limb_truth& limb) {
  auto heading = [&](double u) {
    return std::clamp(seed.heading + kappa * u + w.at(u), -clamp, clamp);
  };
  std::vector<double> arcs;
  const int n = std::clamp(static_cast<int>(std::ceil(seed.length / step)), 1, 8192);
  for (int i = 0; i <= n; ++i) arcs.push_back(seed.length * i / n);
  for (const auto& k : w.kinks) arcs.push_back(k.first);
  std::sort(arcs.begin(), arcs.end());
  arcs.erase(std::unique(arcs.begin(), arcs.end(), [](double a, double b) { return b - a < 1e-6; }),
             arcs.end());
  limb.centreline.clear();
  limb.arc_px.clear();
  Eigen::Vector2d p = seed.base;
  limb.centreline.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  for (std::size_t i = 1; i < arcs.size(); ++i) {
    const double ds = arcs[i] - arcs[i - 1];
    double hs = 0.0, hc = 0.0;
    sin_cos(heading(0.5 * (arcs[i] + arcs[i - 1])), hs, hc);
    p += ds * Eigen::Vector2d(hs, -hc);
    limb.centreline.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  }
  limb.arc_px.assign(limb.centreline.size(), 0.0f);
  double acc = 0.0;
  for (std::size_t i = 1; i < limb.centreline.size(); ++i) {
    acc += static_cast<double>((limb.centreline[i] - limb.centreline[i - 1]).norm());
    limb.arc_px[i] = static_cast<float>(acc);
  }
  return heading(seed.length);
}

/// Grows the branching structure (no noise) into `limbs` (appended: indices continue).
void grow_tree(const tree_options& o, std::vector<limb_truth>& limbs, const tree_plan& plan = {}) {
  tree_random rng(o.seed ^ plan.seed_mix);
  const bool none = o.perches == perch_supply::none;
  const double W = o.width, H = o.height;
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  const double d0 = static_cast<double>(o.trunk_diameter_mm) * px_per_mm * plan.size;
  const double d_min = static_cast<double>(o.min_diameter_mm) * px_per_mm;
  const int max_children = std::max(2, o.branches_per_node);
  const int levels = std::clamp(o.levels, 0, 12);
  const int side_max = std::clamp(o.side_limbs, 0, 8);
  constexpr std::size_t max_limbs = 4000;

  std::vector<limb_seed> queue;
  limb_seed trunk;
  trunk.base = {W * rng.uniform(plan.base_x_lo, plan.base_x_hi),
                H - 1.0 + 0.5 * d0};  // cap below the image
  trunk.heading = rng.uniform(-5.0, 5.0) * deg;
  trunk.diameter = d0;
  trunk.length = std::max(H * plan.size * rng.uniform(0.36, 0.46), 3.0 * d0) + 0.5 * d0;
  trunk.level = 0;
  trunk.kind = limb_kind::trunk;
  trunk.tree = plan.tree;
  queue.push_back(trunk);

  for (std::size_t qi = 0; qi < queue.size() && limbs.size() < max_limbs; ++qi) {
    limb_seed seed = queue[qi];
    if (none && !seed.decoy)
      seed.heading = std::clamp(seed.heading, -steep_heading_max, steep_heading_max);
    const int index = static_cast<int>(limbs.size());
    // Curvature: limbs leaning out bend back up towards the light; steep ones wander a little.
    double turn = 0.0;
    if (seed.kind == limb_kind::trunk)
      turn = rng.uniform(-6.0, 6.0) * deg;
    else if (std::abs(seed.heading) > 40.0 * deg)
      turn = -(seed.heading > 0.0 ? 1.0 : -1.0) * rng.uniform(4.0, 28.0) * deg;
    else
      turn = rng.uniform(-14.0, 14.0) * deg;
    if (none && !seed.decoy)  // the whole arc stays steep
      turn = std::clamp(seed.heading + turn, -steep_heading_max, steep_heading_max) - seed.heading;
    const double kappa = turn / seed.length;

    // Side limbs along the length (decided first: they take their share of the pipe).
    const int level_next = seed.level + 1;
    int sides = 0;
    if (level_next <= levels && side_max > 0 && !seed.decoy)
      sides = seed.kind == limb_kind::trunk ? side_max : rng.integer(0, side_max);
    const double taper = rng.uniform(0.86, 0.95);
    const double d_tip_free = taper * seed.diameter;
    struct side_plan {
      double s, d;
    };
    std::vector<side_plan> plans;
    double side_area = 0.0;
    double side_sign = rng.sign();
    for (int k = 0; k < sides; ++k) {
      const double s = seed.length * rng.uniform(0.3, 0.8);
      const double d_here = seed.diameter + (d_tip_free - seed.diameter) * s / seed.length;
      double d = d_here * rng.uniform(0.36, 0.55);
      if (none) {  // decoys: thick (> 130 mm) on a thick enough trunk, else thin (< 20 mm)
        const double thick = rng.uniform(135.0, 150.0) * px_per_mm;
        const double thin = rng.uniform(12.0, 18.0) * px_per_mm;
        d = seed.kind == limb_kind::trunk && std::min(thick, 0.95 * d_here) >= 132.0 * px_per_mm
                ? std::min(thick, 0.95 * d_here)
                : std::min(thin, 0.8 * d_here);
      }
      if (d < d_min) continue;
      plans.push_back({s, d});
      side_area += d * d;
    }
    double d_tip =
        std::sqrt(std::max(d_tip_free * d_tip_free - side_area, 0.36 * d_tip_free * d_tip_free));
    if (seed.decoy && seed.diameter >= 132.0 * px_per_mm) d_tip = seed.diameter;  // stays thick

    limb_truth limb;
    limb.parent = seed.parent;
    limb.parent_arc_px = static_cast<float>(seed.parent_arc);
    limb.level = seed.level;
    limb.kind = seed.kind;
    limb.base_heading_rad = static_cast<float>(seed.heading);
    limb.curvature_per_px = static_cast<float>(kappa);
    limb.exact_arc = true;
    limb.tree = seed.tree;
    double step = std::max(1.5, std::min(0.375 * d_tip, std::max(32.0, 0.1 * d_tip)));
    if (std::abs(kappa) > 0.0) step = std::min(step, 1.5 * deg / std::abs(kappa));
    const heading_wander wander = draw_wander(
        o, o.seed ^ plan.seed_mix ^ 0x68e31da4u ^ (static_cast<std::uint32_t>(index) * 0x9e3779b1u),
        seed.length, seed.kind == limb_kind::trunk);
    double tip_heading = seed.heading + kappa * seed.length;
    if (wander.empty()) {
      sample_arc(seed, kappa, step, limb);
    } else {
      // `none`: structural limbs stay steep all along, however they wander.
      const double clamp = none && !seed.decoy ? steep_heading_max : 4.0 * pi;
      tip_heading = sample_wandering(seed, kappa, wander, clamp, std::min(step, 2.0), limb);
      limb.exact_arc = false;
      limb.curvature_per_px = static_cast<float>((tip_heading - seed.heading) / seed.length);
    }
    limb.diameter_px.resize(limb.centreline.size());
    for (std::size_t i = 0; i < limb.centreline.size(); ++i) {
      const double u =
          static_cast<double>(limb.arc_px[i]) / static_cast<double>(limb.arc_px.back());
      limb.diameter_px[i] = static_cast<float>(seed.diameter + (d_tip - seed.diameter) * u);
    }
    const float length = length_px(limb);
    const Eigen::Vector2f tip = limb.centreline.back();
    limbs.push_back(std::move(limb));
    const limb_truth& grown = limbs.back();

    auto inside_image = [&](Eigen::Vector2f p) {
      return p.x() >= 0.0f && p.y() >= 0.0f && p.x() <= static_cast<float>(W - 1) &&
             p.y() <= static_cast<float>(H - 1);
    };
    auto clamp_heading = [](double h) { return std::clamp(h, -105.0 * deg, 105.0 * deg); };

    // Side limbs: near-horizontal for the trunk, diverging for limbs.
    for (const side_plan& side_at : plans) {
      const auto s = static_cast<float>(side_at.s * static_cast<double>(length) / seed.length);
      const Eigen::Vector2f at = truth_point_at(grown, s);
      if (!inside_image(at)) continue;
      const Eigen::Vector2f t = truth_tangent_at(grown, s);
      const double here = std::atan2(static_cast<double>(t.x()), -static_cast<double>(t.y()));
      limb_seed side;
      side.parent = index;
      side.parent_arc = static_cast<double>(s);
      side.base = {static_cast<double>(at.x()), static_cast<double>(at.y())};
      if (seed.kind == limb_kind::trunk) {
        side.heading = o.wide_side_angles ? here + side_sign * rng.uniform(20.0, 80.0) * deg
                                          : side_sign * rng.uniform(58.0, 84.0) * deg;
      } else {
        // Diverge by 35–70° from the parent. Near a horizontal parent the clamp can take most
        // of that away (a limb heading 95° turned +50° clamps to 105°: 10° of divergence), and
        // the child then hugs its parent for its whole length, fused with it in the mask: no
        // tree grows so, so such a limb leaves on the other side instead.
        const double lo = o.wide_side_angles ? 20.0 : 35.0, hi = o.wide_side_angles ? 80.0 : 70.0;
        const double divergence = rng.uniform(lo, hi) * deg;
        side.heading = clamp_heading(here + side_sign * divergence);
        if (std::abs(side.heading - here) < lo * deg) {
          side_sign = -side_sign;
          side.heading = clamp_heading(here + side_sign * divergence);
        }
      }
      if (none) side.heading = side_sign * rng.uniform(62.0, 88.0) * deg;  // near-horizontal
      side_sign = -side_sign;
      side.diameter = side_at.d;
      side.length = std::max(seed.length * rng.uniform(0.45, 0.75), 4.0 * side_at.d);
      side.level = level_next;
      side.kind = limb_kind::limb;
      side.decoy = none;
      side.tree = seed.tree;
      queue.push_back(side);
    }

    // The fork at the tip: a leader close to the parent's direction and diverging others.
    if (level_next > levels || !inside_image(tip) || seed.decoy) continue;
    const int children = rng.integer(2, max_children);
    std::vector<double> share(static_cast<std::size_t>(children));
    double total = 0.0;
    for (int k = 0; k < children; ++k) {
      share[static_cast<std::size_t>(k)] = k == 0 ? rng.uniform(1.3, 1.8) : rng.uniform(0.5, 1.0);
      total += share[static_cast<std::size_t>(k)];
    }
    const double lean = rng.sign();
    for (int k = 0; k < children; ++k) {
      const double d = d_tip * std::sqrt(share[static_cast<std::size_t>(k)] / total);
      double heading = tip_heading;
      if (k == 0)
        heading += (children == 2 ? lean * rng.uniform(5.0, 22.0) : rng.uniform(-12.0, 12.0)) * deg;
      else if (children == 2)
        heading -= lean * rng.uniform(30.0, 62.0) * deg;
      else
        heading += (k % 2 == 1 ? lean : -lean) * rng.uniform(28.0, 62.0) * deg;
      const double child_length = std::max(seed.length * rng.uniform(0.58, 0.78), 4.0 * d);
      if (d < d_min) continue;
      limb_seed child;
      child.parent = index;
      child.parent_arc = static_cast<double>(length);
      child.base = {static_cast<double>(tip.x()), static_cast<double>(tip.y())};
      child.heading = clamp_heading(heading);
      child.diameter = d;
      child.length = child_length;
      child.level = level_next;
      child.kind = limb_kind::limb;
      child.tree = seed.tree;
      queue.push_back(child);
    }
  }
}

/// Adds `o.crossings` limbs that leave a random limb P and cross another limb Q of the same
/// tree (aimed at a point of Q's centreline, then running on past Q), so the mask gets loops.
/// A crossing limb is a limb of P (parent P, level + 1), 0.4–0.6 of P's diameter there
/// (`perch_supply::none`: a thin decoy of 12–18 mm), nearly straight (a turn of ±8°), leaving P
/// and crossing Q at 30° or more. Pairs are drawn until one fits (at most 40 draws per crossing).
void add_crossings(const tree_options& o, std::vector<limb_truth>& limbs) {
  if (o.crossings <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x27d4eb2fu);
  const std::size_t structural = limbs.size();
  const double W = o.width, H = o.height;
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  const double d_min = static_cast<double>(o.min_diameter_mm) * px_per_mm;
  auto inside_image = [&](Eigen::Vector2f p) {
    return p.x() >= 0.0f && p.y() >= 0.0f && p.x() <= static_cast<float>(W - 1) &&
           p.y() <= static_cast<float>(H - 1);
  };
  const int wanted = std::min(o.crossings, 64);
  for (int k = 0, draws = 0; k < wanted && draws < 40 * wanted; ++draws) {
    const auto p_index = static_cast<std::size_t>(rng.integer(0, static_cast<int>(structural) - 1));
    const auto q_index = static_cast<std::size_t>(rng.integer(0, static_cast<int>(structural) - 1));
    const double u_p = rng.uniform(0.2, 0.8);
    const double u_q = rng.uniform(0.2, 0.8);
    const double turn = rng.uniform(-8.0, 8.0) * deg;
    const double share = rng.uniform(0.4, 0.6);
    const double thin = rng.uniform(12.0, 18.0) * px_per_mm;
    const double overshoot = rng.uniform(0.3, 0.8);
    if (p_index == q_index) continue;
    const limb_truth& P = limbs[p_index];
    const limb_truth& Q = limbs[q_index];
    if (P.kind == limb_kind::twig || Q.kind == limb_kind::twig || P.tree != Q.tree) continue;
    if (static_cast<int>(q_index) == P.parent || Q.parent == static_cast<int>(p_index)) continue;
    const auto s_p = static_cast<float>(u_p * static_cast<double>(length_px(P)));
    const auto s_q = static_cast<float>(u_q * static_cast<double>(length_px(Q)));
    const Eigen::Vector2f a = truth_point_at(P, s_p);
    const Eigen::Vector2f b = truth_point_at(Q, s_q);
    if (!inside_image(a) || !inside_image(b)) continue;
    const double r_p = 0.5 * static_cast<double>(truth_diameter_at(P, s_p));
    const double r_q = 0.5 * static_cast<double>(truth_diameter_at(Q, s_q));
    const Eigen::Vector2f ab = b - a;
    const double dist = static_cast<double>(ab.norm());
    if (dist < std::max(2.0 * (r_p + r_q), 0.08 * H) || dist > 0.4 * H) continue;
    const Eigen::Vector2f dir = ab / ab.norm();
    const double cross = std::abs(static_cast<double>(
        dir.x() * truth_tangent_at(Q, s_q).y() - dir.y() * truth_tangent_at(Q, s_q).x()));
    if (cross < 0.5) continue;  // crosses Q at 30° or more
    const Eigen::Vector2f tp = truth_tangent_at(P, s_p);
    if (std::abs(static_cast<double>(dir.x() * tp.y() - dir.y() * tp.x())) < 0.5)
      continue;  // and leaves P at 30° or more (not running along it)
    double d = share * 2.0 * r_p;
    if (o.perches == perch_supply::none) d = std::min(thin, 1.6 * r_p);
    if (d < d_min) continue;
    limb_seed seed;
    seed.parent = static_cast<int>(p_index);
    seed.parent_arc = static_cast<double>(s_p);
    seed.base = {static_cast<double>(a.x()), static_cast<double>(a.y())};
    seed.length = dist * (1.0 + overshoot) + r_q;
    const double kappa = turn / seed.length;
    // The chord to arc length `dist` points along heading + κ·dist/2: aim it at b.
    seed.heading = std::atan2(static_cast<double>(dir.x()), -static_cast<double>(dir.y())) -
                   0.5 * kappa * dist;
    seed.diameter = d;
    seed.level = P.level + 1;
    seed.kind = limb_kind::limb;
    seed.tree = P.tree;
    limb_truth limb;
    limb.parent = seed.parent;
    limb.parent_arc_px = s_p;
    limb.level = seed.level;
    limb.kind = limb_kind::limb;
    limb.base_heading_rad = static_cast<float>(seed.heading);
    limb.curvature_per_px = static_cast<float>(kappa);
    limb.exact_arc = true;
    limb.tree = seed.tree;
    double step = std::max(1.5, std::min(0.375 * d, 32.0));
    if (std::abs(kappa) > 0.0) step = std::min(step, 1.5 * deg / std::abs(kappa));
    sample_arc(seed, kappa, step, limb);
    const double d_tip = 0.85 * d;
    limb.diameter_px.resize(limb.centreline.size());
    for (std::size_t i = 0; i < limb.centreline.size(); ++i) {
      const double u =
          static_cast<double>(limb.arc_px[i]) / static_cast<double>(limb.arc_px.back());
      limb.diameter_px[i] = static_cast<float>(d + (d_tip - d) * u);
    }
    limbs.push_back(std::move(limb));
    ++k;
  }
}

/// Adds a second, smaller tree (`o.second_tree` × the first's trunk diameter and height) on the
/// side of the image away from the first trunk.
void add_second_tree(const tree_options& o, std::vector<limb_truth>& limbs) {
  if (!(o.second_tree > 0.0f) || limbs.empty()) return;
  tree_plan plan;
  plan.size = std::min(static_cast<double>(o.second_tree), 1.0);
  const double first_x = static_cast<double>(limbs[0].centreline[0].x()) / o.width;
  if (first_x < 0.5) {
    plan.base_x_lo = 0.8;
    plan.base_x_hi = 0.92;
  } else {
    plan.base_x_lo = 0.08;
    plan.base_x_hi = 0.2;
  }
  plan.seed_mix = 0x5bd1e995u;
  plan.tree = 1;
  tree_options second = o;
  second.levels = std::max(0, o.levels - 1);
  grow_tree(second, limbs, plan);
}

/// Adds `count` thin twigs leaving random limbs (drawn and recorded as `limb_kind::twig`).
void add_twigs(const tree_options& o, std::vector<limb_truth>& limbs) {
  if (o.twigs <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x9e3779b9u);
  const std::size_t structural = limbs.size();
  const double H = o.height;
  for (int k = 0; k < o.twigs; ++k) {
    const auto li = static_cast<std::size_t>(rng.integer(0, static_cast<int>(structural) - 1));
    const limb_truth& parent = limbs[li];
    const auto s =
        static_cast<float>(rng.uniform(0.1, 0.95) * static_cast<double>(length_px(parent)));
    const Eigen::Vector2f at = truth_point_at(parent, s);
    const Eigen::Vector2f t = truth_tangent_at(parent, s);
    const double here = std::atan2(static_cast<double>(t.x()), -static_cast<double>(t.y()));
    limb_seed seed;
    seed.parent = static_cast<int>(li);
    seed.parent_arc = static_cast<double>(s);
    seed.base = {static_cast<double>(at.x()), static_cast<double>(at.y())};
    seed.heading =
        std::clamp(here + rng.sign() * rng.uniform(30.0, 80.0) * deg, -120.0 * deg, 120.0 * deg);
    seed.diameter = rng.uniform(1.5, 3.5);
    if (o.perches == perch_supply::none)  // twigs stay under 18 mm
      seed.diameter = std::min(seed.diameter, 18.0 / static_cast<double>(o.mm_per_px));
    seed.length =
        0.5 * static_cast<double>(truth_diameter_at(parent, s)) + H * rng.uniform(0.03, 0.1);
    seed.level = parent.level + 1;
    seed.kind = limb_kind::twig;
    const double kappa = rng.uniform(-20.0, 20.0) * deg / seed.length;
    limb_truth twig;
    twig.parent = seed.parent;
    twig.parent_arc_px = s;
    twig.level = seed.level;
    twig.kind = limb_kind::twig;
    twig.tree = parent.tree;
    twig.base_heading_rad = static_cast<float>(seed.heading);
    twig.curvature_per_px = static_cast<float>(kappa);
    twig.exact_arc = true;
    sample_arc(seed, kappa, std::min(4.0, 1.5 * deg / std::max(std::abs(kappa), 1e-9)), twig);
    const double d_tip = std::max(1.0, 0.6 * seed.diameter);
    twig.diameter_px.resize(twig.centreline.size());
    for (std::size_t i = 0; i < twig.centreline.size(); ++i) {
      const double u =
          static_cast<double>(twig.arc_px[i]) / static_cast<double>(twig.arc_px.back());
      twig.diameter_px[i] = static_cast<float>(seed.diameter + (d_tip - seed.diameter) * u);
    }
    limbs.push_back(std::move(twig));
  }
}

float surface_distance(const limb_truth& limb, Eigen::Vector2f p) noexcept {
  float best = std::numeric_limits<float>::infinity();
  for (std::size_t k = 0; k + 1 < limb.centreline.size(); ++k) {
    const Eigen::Vector2f q0 = limb.centreline[k];
    const Eigen::Vector2f d = limb.centreline[k + 1] - q0;
    const float len2 = d.squaredNorm();
    const float t = len2 > 0.0f ? std::clamp((p - q0).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
    const float r =
        0.5f * (limb.diameter_px[k] + t * (limb.diameter_px[k + 1] - limb.diameter_px[k]));
    best = std::min(best, (p - (q0 + t * d)).norm() - r);
  }
  return best;
}

/// Adds `o.fragments` detached pieces of mask (`limb_kind::fragment`) near the crown: a point
/// drawn in the box of the first tree's limbs above the trunk (the trunk's top third when it
/// has none), then a short thick stub (25–90 mm, 1–4 diameters long), a thin stick (2–6 px,
/// 3–8 % of the height) or a blob (a stub 0.3 diameters long, 30–80 px), straight, at any
/// heading. It is kept only when its surface stays at least 4 px + 2 × (3.2 × noise + 1.5)
/// (room for both sides' outline spurs and bumps) from every limb, twig and earlier fragment,
/// so it is its own 8-connected component of the mask whatever the noise. At most 40 draws per
/// fragment; `tree` is that of the nearest limb.
void add_fragments(const tree_options& o, std::vector<limb_truth>& limbs) {
  if (o.fragments <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x165667b1u);
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  float x0 = std::numeric_limits<float>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (const limb_truth& L : limbs) {
    if (L.kind == limb_kind::trunk || L.kind == limb_kind::twig || L.tree != 0) continue;
    for (const Eigen::Vector2f& p : L.centreline) {
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
  }
  if (!(x1 >= x0)) {  // a bare trunk: its top third
    const limb_truth& T = limbs[0];
    const Eigen::Vector2f a = truth_point_at(T, 0.67f * length_px(T)), b = T.centreline.back();
    x0 = std::min(a.x(), b.x()) - 0.5f * T.diameter_px.back() - 20.0f;
    x1 = std::max(a.x(), b.x()) + 0.5f * T.diameter_px.back() + 20.0f;
    y0 = std::min(a.y(), b.y());
    y1 = std::max(a.y(), b.y());
  }
  x0 = std::max(x0, 0.0f);
  y0 = std::max(y0, 0.0f);
  x1 = std::min(x1, static_cast<float>(o.width - 1));
  y1 = std::min(y1, static_cast<float>(o.height - 1));
  if (!(x1 >= x0 && y1 >= y0)) return;
  const float gap = 4.0f + 2.0f * (3.2f * std::max(o.noise, 0.0f) + 1.5f);
  const int wanted = std::min(o.fragments, 64);
  for (int k = 0, draws = 0; k < wanted && draws < 40 * wanted; ++draws) {
    const double cx = rng.uniform(static_cast<double>(x0), static_cast<double>(x1));
    const double cy = rng.uniform(static_cast<double>(y0), static_cast<double>(y1));
    const double shape = rng.uniform();
    const double heading = rng.uniform(-pi, pi);
    double d = 0.0, length = 0.0;
    if (shape < 0.45) {  // a stub
      d = rng.uniform(25.0, 90.0) * px_per_mm;
      length = d * rng.uniform(1.0, 4.0);
    } else if (shape < 0.8) {  // a stick
      d = rng.uniform(2.0, 6.0);
      length = static_cast<double>(o.height) * rng.uniform(0.03, 0.08);
    } else {  // a blob
      d = rng.uniform(30.0, 80.0);
      length = 0.3 * d;
    }
    double hs = 0.0, hc = 0.0;
    sin_cos(heading, hs, hc);
    limb_seed seed;
    seed.base = {cx - 0.5 * length * hs, cy + 0.5 * length * hc};
    seed.heading = heading;
    seed.length = std::max(length, 1.0);
    limb_truth f;
    f.parent = -1;
    f.kind = limb_kind::fragment;
    f.base_heading_rad = static_cast<float>(heading);
    f.exact_arc = true;
    sample_arc(seed, 0.0, std::max(1.0, std::min(0.375 * d, 16.0)), f);
    f.diameter_px.resize(f.centreline.size());
    for (std::size_t i = 0; i < f.centreline.size(); ++i)
      f.diameter_px[i] = static_cast<float>(d * (1.0 - 0.15 * static_cast<double>(f.arc_px[i]) /
                                                           static_cast<double>(f.arc_px.back())));
    // Detached: every point of its surface (its centreline every px, minus its radius) clears
    // every other piece by the gap.
    bool clear = true;
    float nearest = std::numeric_limits<float>::infinity();
    const float len = length_px(f);
    const int n = std::max(1, static_cast<int>(std::ceil(len)));
    for (std::size_t li = 0; li < limbs.size() && clear; ++li) {
      for (int i = 0; i <= n && clear; ++i) {
        const float s = len * static_cast<float>(i) / static_cast<float>(n);
        const float dist =
            surface_distance(limbs[li], truth_point_at(f, s)) - 0.5f * truth_diameter_at(f, s);
        clear = dist >= gap;
        if (dist < nearest && limbs[li].kind != limb_kind::fragment) {
          nearest = dist;
          f.tree = limbs[li].tree;
        }
      }
    }
    if (!clear) continue;
    limbs.push_back(std::move(f));
    ++k;
  }
}

void add_outline_noise(const tree_options& o, const std::vector<limb_truth>& limbs,
                       image_view<std::uint8_t> mask) {
  if (!(o.noise > 0.0f) || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x85ebca6bu);
  const double a = static_cast<double>(o.noise);
  double outline = 0.0;
  std::vector<double> cumulative;
  for (const limb_truth& limb : limbs) {
    outline += limb.kind == limb_kind::twig ? 0.0 : 2.0 * static_cast<double>(length_px(limb));
    cumulative.push_back(outline);
  }
  const int count = static_cast<int>(outline / (6.0 * a + 10.0));
  for (int k = 0; k < count; ++k) {
    const double pick = rng.uniform() * outline;
    const auto li = static_cast<std::size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    if (li >= limbs.size()) continue;
    const limb_truth& limb = limbs[li];
    const auto s = static_cast<float>(rng.uniform() * static_cast<double>(length_px(limb)));
    const Eigen::Vector2f c = truth_point_at(limb, s);
    const Eigen::Vector2f t = truth_tangent_at(limb, s);
    const float side = static_cast<float>(rng.sign());
    const Eigen::Vector2f n(-t.y() * side, t.x() * side);
    const float r = 0.5f * truth_diameter_at(limb, s);
    const Eigen::Vector2f surface = c + r * n;
    const double kind = rng.uniform();
    if (kind < 0.75) {
      const auto rho = static_cast<float>(a * rng.uniform(0.5, 1.0));
      draw_disc(mask, surface + n * (rho * static_cast<float>(rng.uniform(0.0, 0.6))), rho);
    } else {
      const auto len = static_cast<float>(a * rng.uniform(1.5, 3.0));
      const Eigen::Vector2f dir = (n + t * static_cast<float>(rng.uniform(-0.6, 0.6))).normalized();
      draw_capsule(mask, surface - dir, surface + len * dir,
                   static_cast<float>(rng.uniform(0.8, 1.3)), 0.6f);
    }
  }
}

/// Occlusion holes: discs erased well inside thick limbs (the limb stays connected around them).
void add_holes(const tree_options& o, const std::vector<limb_truth>& limbs,
               image_view<std::uint8_t> mask) {
  if (o.holes <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0xc2b2ae35u);
  std::vector<std::size_t> thick;
  for (std::size_t i = 0; i < limbs.size(); ++i)
    if (limbs[i].kind != limb_kind::twig && limbs[i].diameter_px.back() >= 16.0f)
      thick.push_back(i);
  if (thick.empty()) return;
  for (int k = 0; k < o.holes; ++k) {
    const limb_truth& limb =
        limbs[thick[static_cast<std::size_t>(rng.integer(0, static_cast<int>(thick.size()) - 1))]];
    const auto s =
        static_cast<float>(rng.uniform(0.15, 0.85) * static_cast<double>(length_px(limb)));
    const float r = 0.5f * truth_diameter_at(limb, s);
    const Eigen::Vector2f t = truth_tangent_at(limb, s);
    const Eigen::Vector2f n(-t.y(), t.x());
    const auto rho = static_cast<float>(rng.uniform(0.12, 0.25)) * r;
    const auto offset = static_cast<float>(rng.uniform(-0.3, 0.3)) * r;
    draw_disc(mask, truth_point_at(limb, s) + offset * n, rho, 0);
  }
}

}  // namespace detail

void shift_outline(image<std::uint8_t>& mask, int px) {
  if (px == 0 || mask.width() <= 0 || mask.height() <= 0) return;
  const int w = mask.width(), h = mask.height(), r = std::abs(px);
  const std::uint8_t grown = px > 0 ? 255 : 0;  // the value a pixel takes near the other kind
  image<std::uint8_t> out = mask;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if ((mask(x, y) != 0) == (px > 0)) continue;  // already what the shift makes
      bool near = false;
      for (int dy = -r; dy <= r && !near; ++dy)
        for (int dx = -r; dx <= r && !near; ++dx) {
          const int u = x + dx, v = y + dy;
          if (dx * dx + dy * dy > r * r || u < 0 || v < 0 || u >= w || v >= h) continue;
          near = (mask(u, v) != 0) == (px > 0);
        }
      if (near) out(x, y) = grown;
    }
  mask = std::move(out);
}

void bias_radii(synthetic_tree& tree, float px) {
  if (px == 0.0f || !std::isfinite(px) || tree.mask.width() <= 0 || tree.mask.height() <= 0) return;
  auto draw_all = [&](image_view<std::uint8_t> into, float extra) {
    std::vector<float> radii;
    for (const limb_truth& limb : tree.limbs) {
      if (limb.centreline.empty() || limb.diameter_px.size() != limb.centreline.size()) continue;
      radii.resize(limb.diameter_px.size());
      for (std::size_t i = 0; i < radii.size(); ++i)
        radii[i] = 0.5f * limb.diameter_px[i] + extra;  // < 0: that piece is not drawn
      draw_polyline(into, limb.centreline, radii);
    }
  };
  if (px > 0.0f) {
    draw_all(tree.mask.view(), px);
    return;
  }
  image<std::uint8_t> drawn(tree.mask.width(), tree.mask.height(), 0);
  image<std::uint8_t> kept(tree.mask.width(), tree.mask.height(), 0);
  draw_all(drawn.view(), 0.0f);
  draw_all(kept.view(), px);
  for (int y = 0; y < tree.mask.height(); ++y)
    for (int x = 0; x < tree.mask.width(); ++x)
      if (drawn(x, y) != 0 && kept(x, y) == 0) tree.mask(x, y) = 0;
}

void cut_gaps(synthetic_tree& tree, int count, std::uint32_t seed) {
  std::vector<std::size_t> cut;  // limbs a gap may cross
  for (std::size_t i = 0; i < tree.limbs.size(); ++i) {
    const limb_truth& L = tree.limbs[i];
    if ((L.kind == limb_kind::trunk || L.kind == limb_kind::limb) && L.centreline.size() >= 2 &&
        L.diameter_px.size() == L.centreline.size() && L.diameter_px.front() >= 6.0f)
      cut.push_back(i);
  }
  if (count <= 0 || cut.empty()) return;
  detail::tree_random rng(seed ^ 0x9e3779b9u);
  for (int k = 0; k < count; ++k) {
    const limb_truth& L = tree.limbs[cut[static_cast<std::size_t>(rng.integer(0, static_cast<int>(cut.size()) - 1))]];
    const float length = length_px(L);
    const float gap = static_cast<float>(rng.integer(1, 8));
    float s = static_cast<float>(rng.uniform(0.2, 0.8)) * length;
    const bool at_base = k % 2 == 1 && L.parent >= 0;
    if (at_base) {  // where the child's whole width has left the parent's outline
      const limb_truth& P = tree.limbs[static_cast<std::size_t>(L.parent)];
      for (s = 0; s < length && detail::surface_distance(P, truth_point_at(L, s)) <
                                    0.5f * truth_diameter_at(L, s);
           s += 0.5f) {
      }
    }
    if (s + gap > length || truth_diameter_at(L, s) < 4.0f) continue;
    const Eigen::Vector2f c = truth_point_at(L, s + 0.5f * gap), t = truth_tangent_at(L, s);
    const float half_width = 0.5f * truth_diameter_at(L, s) + 4.0f;
    const float reach = std::hypot(0.5f * gap, half_width);
    const int x0 = std::max(0, static_cast<int>(std::floor(c.x() - reach)));
    const int x1 = std::min(tree.mask.width() - 1, static_cast<int>(std::ceil(c.x() + reach)));
    const int y0 = std::max(0, static_cast<int>(std::floor(c.y() - reach)));
    const int y1 = std::min(tree.mask.height() - 1, static_cast<int>(std::ceil(c.y() + reach)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2f d = Eigen::Vector2f(static_cast<float>(x), static_cast<float>(y)) - c;
        if (tree.mask(x, y) == 0 || std::abs(d.dot(t)) > 0.5f * gap ||
            std::abs(d.x() * t.y() - d.y() * t.x()) > half_width)
          continue;
        bool other = false;
        for (std::size_t j = 0; j < tree.limbs.size() && !other; ++j)
          other = &tree.limbs[j] != &L && !tree.limbs[j].centreline.empty() &&
                  detail::surface_distance(tree.limbs[j], c + d) <= 0.5f;
        if (!other) tree.mask(x, y) = 0;
      }
  }
}

synthetic_tree make_tree(const tree_options& options) {
  synthetic_tree tree;
  tree.mm_per_px = options.mm_per_px;
  const bool valid =
      options.width >= 1 && options.height >= 1 &&
      static_cast<std::int64_t>(options.width) * options.height <= max_image_pixels &&
      std::isfinite(options.mm_per_px) && options.mm_per_px > 0.0f &&
      std::isfinite(options.trunk_diameter_mm) && options.trunk_diameter_mm > 0.0f &&
      std::isfinite(options.min_diameter_mm) && std::isfinite(options.noise) &&
      std::isfinite(options.second_tree);
  if (!valid) return tree;
  tree.mask = image<std::uint8_t>(options.width, options.height, 0);
  detail::grow_tree(options, tree.limbs);
  detail::add_second_tree(options, tree.limbs);
  detail::add_crossings(options, tree.limbs);
  detail::add_twigs(options, tree.limbs);
  detail::add_fragments(options, tree.limbs);
  for (const limb_truth& limb : tree.limbs) {
    std::vector<float> radii(limb.diameter_px.size());
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.5f * limb.diameter_px[i];
    draw_polyline(tree.mask, limb.centreline, radii);
  }
  detail::add_outline_noise(options, tree.limbs, tree.mask);
  detail::add_holes(options, tree.limbs, tree.mask);
  return tree;
}

tree_options benchmark_tree_options(int width, int height, tree_noise noise) {
  tree_options o;
  o.width = width;
  o.height = height;
  o.seed = 23;
  o.trunk_diameter_mm = 180.0f;
  o.mm_per_px = width > 0 ? 180.0f / (0.045f * static_cast<float>(width)) : 1.0f;
  if (noise == tree_noise::noisy) {
    o.noise = 1.0f + 0.0016f * static_cast<float>(width);
    o.twigs = 24;
    o.holes = 3;
  }
  return o;
}

perch_truth::perch_truth(const synthetic_tree& tree, const claw_spec& spec)
    : tree_(&tree), spec_(spec) {
  mmpp_ = tree.mm_per_px > 0.0f ? tree.mm_per_px : 1.0f;
  window_px_ = spec.drone_width_mm / mmpp_;
  claw_half_px_ = 0.5f * spec.claw_mm / mmpp_;
  clearance_px_ = spec.clearance_mm / mmpp_;
  thick_px_ = spec.twig_max_mm / mmpp_;
  build_support();
  build_obstacles();
  build_profiles();
  build_stretches();
}

window_truth perch_truth::window(int limb, float centre_arc_px) const {
  window_truth out;
  out.limb = limb;
  out.centre_arc_px = centre_arc_px;
  if (limb < 0 || static_cast<std::size_t>(limb) >= tree_->limbs.size()) return out;
  const auto li = static_cast<std::size_t>(limb);
  const limb_truth& L = tree_->limbs[li];
  if (L.centreline.size() < 2 || L.diameter_px.size() != L.centreline.size() ||
      L.arc_px.size() != L.centreline.size())
    return out;
  const float len = length_px(L);
  const float half = 0.5f * window_px_;
  const float s0 = centre_arc_px - half, s1 = centre_arc_px + half;
  const float c0 = std::clamp(s0, 0.0f, len), c1 = std::clamp(s1, 0.0f, len);
  // Measures (over the part of the window on the limb).
  double dsum = 0.0;
  int dn = 0;
  for (float u = -claw_half_px_; u <= claw_half_px_ + 1e-3f; u += 0.5f, ++dn)
    dsum += static_cast<double>(truth_diameter_at(L, centre_arc_px + u));
  out.claw_diameter_mm = static_cast<float>(dsum / std::max(dn, 1)) * mmpp_;
  out.slope_deg = max_slope_deg(L, c0, c1);
  const profile& pr = profiles_[li];
  out.clearance_mm = clearance_gap_px(li, c0);
  out.border_px = border_px(L, c0);
  out.bend_deg = bend_deg(L, c0);
  out.clearance_mm = std::min(out.clearance_mm, clearance_gap_px(li, c1));
  out.border_px = std::min(out.border_px, border_px(L, c1));
  out.bend_deg = std::max(out.bend_deg, bend_deg(L, c1));
  if (pr.step > 0.0f) {
    const auto last = static_cast<std::ptrdiff_t>(pr.gap.size()) - 1;
    const auto k0 =
        std::max<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(std::ceil(c0 / pr.step)));
    const auto k1 =
        std::min<std::ptrdiff_t>(last, static_cast<std::ptrdiff_t>(std::floor(c1 / pr.step)));
    for (std::ptrdiff_t k = k0; k <= k1; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      out.clearance_mm = std::min(out.clearance_mm, pr.gap[uk]);
      out.border_px = std::min(out.border_px, pr.border[uk]);
      out.bend_deg = std::max(out.bend_deg, pr.bend[uk]);
    }
  }
  out.clearance_mm *= mmpp_;  // px → mm (∞ stays ∞)
  out.curvature_per_mm = std::abs(L.curvature_per_px) / mmpp_;
  const float lever_mm =
      std::abs((truth_point_at(L, centre_arc_px) - L.centreline.front()).dot(horizon())) * mmpp_;
  const float r_m = 0.5f * out.claw_diameter_mm / 1000.0f;
  out.stress_mpa = r_m > 0.0f ? 4.0f * spec_.mass_kg * 9.80665f * (lever_mm / 1000.0f) /
                                    (static_cast<float>(detail::pi) * r_m * r_m * r_m) / 1.0e6f
                              : std::numeric_limits<float>::infinity();
  // Rules, in order.
  auto verdict = [&]() {
    if (is_twig_[li] != 0) return window_verdict::twig;
    if (s0 < 0.0f || s1 > len) return window_verdict::off_limb;
    if (supported_[li] == 0) return window_verdict::unsupported;
    if (!(out.border_px >= spec_.border_margin_px)) return window_verdict::outside_image;
    if (!(out.clearance_mm >= spec_.clearance_mm)) return window_verdict::clearance;
    if (!(out.claw_diameter_mm >= spec_.diameter_min_mm &&
          out.claw_diameter_mm <= spec_.diameter_max_mm))
      return window_verdict::diameter;
    const float d_px = out.claw_diameter_mm / mmpp_;
    if (!(d_px - spec_.resolution_px >= spec_.diameter_min_mm / mmpp_ &&
          d_px + spec_.resolution_px <= spec_.diameter_max_mm / mmpp_))
      return window_verdict::resolution;
    if (!(out.slope_deg <= spec_.max_slope_deg)) return window_verdict::slope;
    if (!(out.bend_deg <= spec_.max_bend_deg)) return window_verdict::bend;
    if (!(out.stress_mpa <= spec_.max_stress_mpa)) return window_verdict::bending;
    return window_verdict::feasible;
  };
  out.verdict = verdict();
  return out;
}

site_match perch_truth::nearest_site(Eigen::Vector2f p) const {
  site_match best;
  const float half = 0.5f * window_px_;
  for (const feasible_stretch& st : stretches_) {
    const limb_truth& L = tree_->limbs[static_cast<std::size_t>(st.limb)];
    const float lo = st.arc_begin_px + half, hi = st.arc_end_px - half;
    // Walk the centreline between lo and hi in steps ≤ 0.5 px, projecting on each piece.
    const int n = std::max(1, static_cast<int>(std::ceil((hi - lo) / 0.5f)));
    Eigen::Vector2f prev = truth_point_at(L, lo);
    float prev_s = lo;
    auto consider = [&](Eigen::Vector2f q0, Eigen::Vector2f q1, float a0, float a1) {
      const Eigen::Vector2f d = q1 - q0;
      const float len2 = d.squaredNorm();
      const float t = len2 > 0.0f ? std::clamp((p - q0).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
      const float dist = (p - (q0 + t * d)).norm();
      if (dist < best.distance_px) {
        best.distance_px = dist;
        best.limb = st.limb;
        best.arc_px = a0 + t * (a1 - a0);
      }
    };
    consider(prev, prev, lo, lo);
    for (int i = 1; i <= n; ++i) {
      const float s = lo + (hi - lo) * static_cast<float>(i) / static_cast<float>(n);
      const Eigen::Vector2f q = truth_point_at(L, s);
      consider(prev, q, prev_s, s);
      prev = q;
      prev_s = s;
    }
  }
  return best;
}

void perch_truth::build_support() {
  const auto& limbs = tree_->limbs;
  is_twig_.assign(limbs.size(), 0);
  supported_.assign(limbs.size(), 1);
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    const limb_truth& L = limbs[i];
    float d_max = 0.0f;
    for (const float d : L.diameter_px) d_max = std::max(d_max, d);
    is_twig_[i] = L.kind == limb_kind::twig || !(d_max >= thick_px_) ? 1 : 0;
    // Walk up the parents (at most limbs.size() steps: a malformed cycle ends the walk).
    int at = static_cast<int>(i);
    for (std::size_t steps = 0;
         at >= 0 && static_cast<std::size_t>(at) < limbs.size() && steps <= limbs.size();
         ++steps) {
      if (limbs[static_cast<std::size_t>(at)].kind == limb_kind::fragment) {
        supported_[i] = 0;
        break;
      }
      at = limbs[static_cast<std::size_t>(at)].parent;
    }
  }
}

bool perch_truth::hidden(std::size_t bi, const std::vector<box>& boxes) const {
  const auto& limbs = tree_->limbs;
  const limb_truth& B = limbs[bi];
  const float len = length_px(B);
  const int n = std::max(1, static_cast<int>(std::ceil(len)));
  for (std::size_t ci = 0; ci < limbs.size(); ++ci) {
    const limb_truth& C = limbs[ci];
    if (ci == bi || C.kind == limb_kind::twig || !well_formed(C)) continue;
    if (boxes[ci].x0 > boxes[bi].x0 + 0.5f || boxes[ci].y0 > boxes[bi].y0 + 0.5f ||
        boxes[ci].x1 < boxes[bi].x1 - 0.5f || boxes[ci].y1 < boxes[bi].y1 - 0.5f)
      continue;  // B's box is not inside C's: B cannot be inside C
    bool inside = true;
    for (int i = 0; i <= n && inside; ++i) {
      const float s = len * static_cast<float>(i) / static_cast<float>(n);
      const Eigen::Vector2f p = truth_point_at(B, s);
      const float rb = 0.5f * truth_diameter_at(B, s);
      bool in = false;
      for (std::size_t k = 0; k + 1 < C.centreline.size() && !in; ++k) {
        const Eigen::Vector2f q0 = C.centreline[k];
        const Eigen::Vector2f d = C.centreline[k + 1] - q0;
        const float len2 = d.squaredNorm();
        const float t = len2 > 0.0f ? std::clamp((p - q0).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
        const float rc =
            0.5f * (C.diameter_px[k] + t * (C.diameter_px[k + 1] - C.diameter_px[k]));
        in = (p - (q0 + t * d)).norm() + rb <= rc + 0.5f;
      }
      inside = in;
    }
    if (inside) return true;
  }
  return false;
}

void perch_truth::build_obstacles() {
  const auto& limbs = tree_->limbs;
  boxes_.assign(limbs.size(), box{});
  for (std::size_t i = 0; i < limbs.size(); ++i)
    if (well_formed(limbs[i]))
      for (std::size_t k = 0; k < limbs[i].centreline.size(); ++k)
        boxes_[i].add(limbs[i].centreline[k], 0.5f * limbs[i].diameter_px[k]);
  for (std::size_t bi = 0; bi < limbs.size(); ++bi) {
    const limb_truth& B = limbs[bi];
    if (B.kind == limb_kind::twig || !well_formed(B) || hidden(bi, boxes_)) continue;
    for (std::size_t k = 0; k + 1 < B.centreline.size(); ++k) {
      float t0 = 0.0f, t1 = 1.0f;
      const float d0 = B.diameter_px[k], d1 = B.diameter_px[k + 1];
      if (!(d0 >= thick_px_) && !(d1 >= thick_px_)) continue;
      if (!(d0 >= thick_px_)) t0 = (thick_px_ - d0) / (d1 - d0);
      if (!(d1 >= thick_px_)) t1 = (thick_px_ - d0) / (d1 - d0);
      const Eigen::Vector2f p0 = B.centreline[k], dp = B.centreline[k + 1] - p0;
      obstacle ob;
      ob.a = p0 + t0 * dp;
      ob.b = p0 + t1 * dp;
      ob.ra = 0.5f * (d0 + t0 * (d1 - d0));
      ob.rb = 0.5f * (d0 + t1 * (d1 - d0));
      ob.limb = bi;
      ob.bounds.add(ob.a, ob.ra);
      ob.bounds.add(ob.b, ob.rb);
      obstacles_.push_back(ob);
    }
  }
}

float perch_truth::clearance_gap_px(std::size_t li, float s) const {
  const profile& pr = profiles_[li];
  if (pr.near_run.empty() || !(pr.step > 0.0f)) return clearance_gap_px(li, s, pr.near);
  const auto k = static_cast<std::ptrdiff_t>(std::floor(s / pr.step + 0.5f)) / profile::run_points;
  const auto last = static_cast<std::ptrdiff_t>(pr.near_run.size()) - 1;
  return clearance_gap_px(li, s, pr.near_run[static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(k, 0, last))]);
}

float perch_truth::clearance_gap_px(std::size_t li, float s,
                                    const std::vector<std::size_t>& candidates) const {
  const limb_truth& L = tree_->limbs[li];
  const Eigen::Vector2f p = truth_point_at(L, s);
  const float r = 0.5f * truth_diameter_at(L, s);
  const float reach = r + 2.0f * clearance_px_;
  float best = std::numeric_limits<float>::infinity();
  for (const std::size_t oi : candidates) {
    const obstacle& ob = obstacles_[oi];
    if (!ob.bounds.near(p, reach)) continue;
    const Eigen::Vector2f d = ob.b - ob.a;
    const float len2 = d.squaredNorm();
    const float t = len2 > 0.0f ? std::clamp((p - ob.a).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
    const float gap = (p - (ob.a + t * d)).norm() - (ob.ra + t * (ob.rb - ob.ra)) - r;
    best = std::min(best, gap);
  }
  return best;
}

float perch_truth::border_px(const limb_truth& L, float s) const {
  const Eigen::Vector2f q = truth_point_at(L, s);
  const auto W = static_cast<float>(tree_->mask.width() - 1);
  const auto H = static_cast<float>(tree_->mask.height() - 1);
  return std::min({q.x(), q.y(), W - q.x(), H - q.y()}) - 0.5f * truth_diameter_at(L, s);
}

Eigen::Vector2d perch_truth::chord_tangent(const limb_truth& L, float s) {
  const float len = length_px(L);
  const Eigen::Vector2f d =
      truth_point_at(L, std::min(s + 1.0f, len)) - truth_point_at(L, std::max(s - 1.0f, 0.0f));
  return {static_cast<double>(d.x()), static_cast<double>(d.y())};
}

float perch_truth::angle_deg(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  const double cross = u.x() * v.y() - u.y() * v.x();
  const double dot = u.dot(v);
  if (cross == 0.0 && dot == 0.0) return 0.0f;
  return static_cast<float>(std::atan2(std::abs(cross), dot) * (180.0 / detail::pi));
}

float perch_truth::bend_deg(const limb_truth& L, float s) const {
  const float half = 0.5f * window_px_;
  return angle_deg(chord_tangent(L, std::max(s - half, 0.0f)),
                   chord_tangent(L, std::min(s + half, length_px(L))));
}

float perch_truth::max_slope_deg(const limb_truth& L, float a, float b) const {
  const Eigen::Vector2f h = horizon();
  float t = 0.0f;
  std::size_t i = detail::segment_at(L, a, t);
  // At a vertex exactly at a, the segment before it counts too.
  if (i > 0 && L.arc_px[i] >= a) --i;
  float worst = 0.0f;
  for (; i + 1 < L.centreline.size() && L.arc_px[i] <= b; ++i) {
    const Eigen::Vector2f d = L.centreline[i + 1] - L.centreline[i];
    if (!(d.squaredNorm() > 0.0f)) continue;
    const double across = static_cast<double>(h.x() * d.y() - h.y() * d.x());
    const double along = static_cast<double>(h.x() * d.x() + h.y() * d.y());
    worst = std::max(worst, static_cast<float>(std::atan2(std::abs(across), std::abs(along)) *
                                               (180.0 / detail::pi)));
  }
  return worst;
}

Eigen::Vector2f perch_truth::horizon() const noexcept {
  if (spec_.roll_deg == 0.0f) return {1.0f, 0.0f};
  double sn = 0.0, cs = 1.0;
  detail::sin_cos(static_cast<double>(spec_.roll_deg) * (detail::pi / 180.0), sn, cs);
  return {static_cast<float>(cs), static_cast<float>(sn)};
}

void perch_truth::build_profiles() {
  const auto& limbs = tree_->limbs;
  profiles_.assign(limbs.size(), profile{});
  for (std::size_t li = 0; li < limbs.size(); ++li) {
    const limb_truth& L = limbs[li];
    if (!well_formed(L)) continue;
    profile& pr = profiles_[li];
    float r_max = 0.0f;
    for (const float d : L.diameter_px) r_max = std::max(r_max, 0.5f * d);
    const float reach = r_max + 2.0f * clearance_px_;
    for (std::size_t oi = 0; oi < obstacles_.size(); ++oi)
      if (obstacles_[oi].limb != li && obstacles_[oi].bounds.overlaps(boxes_[li], reach))
        pr.near.push_back(oi);
    const float len = length_px(L);
    const int n = std::max(1, static_cast<int>(std::ceil(len / 0.5f)));
    pr.step = len / static_cast<float>(n);
    pr.gap.resize(static_cast<std::size_t>(n) + 1);
    pr.border.resize(pr.gap.size());
    pr.bend.resize(pr.gap.size());
    // The points in runs, each run searching only the obstacles near its box (the same gaps
    // as searching `near`, far fewer tests on a long limb in a dense crown).
    for (int k0 = 0; k0 <= n; k0 += profile::run_points) {
      const int k1 = std::min(n, k0 + profile::run_points - 1);
      box run;
      float run_r = 0.0f;
      for (int k = k0; k <= k1; ++k) {
        const float s = std::min(pr.step * static_cast<float>(k), len);
        const float r = 0.5f * truth_diameter_at(L, s);
        run.add(truth_point_at(L, s), r);
        run_r = std::max(run_r, r);
      }
      std::vector<std::size_t>& local = pr.near_run.emplace_back();
      for (const std::size_t oi : pr.near)
        if (obstacles_[oi].bounds.overlaps(run, run_r + 1.0f + 2.0f * clearance_px_))
          local.push_back(oi);
      for (int k = k0; k <= k1; ++k) {
        const float s = std::min(pr.step * static_cast<float>(k), len);
        const auto uk = static_cast<std::size_t>(k);
        pr.gap[uk] = clearance_gap_px(li, s, local);
        pr.border[uk] = border_px(L, s);
        pr.bend[uk] = bend_deg(L, s);
      }
    }
  }
}

void perch_truth::build_stretches() {
  const float half = 0.5f * window_px_;
  const float step = spec_.step_px > 0.05f ? spec_.step_px : 0.05f;
  for (std::size_t li = 0; li < tree_->limbs.size(); ++li) {
    const limb_truth& L = tree_->limbs[li];
    if (is_twig_[li] != 0 || supported_[li] == 0 || !well_formed(L)) continue;
    const float len = length_px(L);
    if (len < window_px_) continue;
    const int n = static_cast<int>(std::floor((len - window_px_) / step));
    float run_first = -1.0f, run_last = -1.0f;
    auto close_run = [&]() {
      if (run_first >= 0.0f)
        stretches_.push_back({static_cast<int>(li), run_first - half, run_last + half});
      run_first = run_last = -1.0f;
    };
    for (int i = 0; i <= n; ++i) {
      const float c = half + static_cast<float>(i) * step;
      if (window(static_cast<int>(li), c).verdict == window_verdict::feasible) {
        if (run_first < 0.0f) run_first = c;
        run_last = c;
      } else {
        close_run();
      }
    }
    close_run();
  }
}

}  // namespace perch::support
