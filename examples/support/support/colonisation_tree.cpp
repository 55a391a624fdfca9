// SPDX-License-Identifier: BSL-1.0
// colonisation_tree.hpp's space-colonisation generator, compiled once into perch_support.
#include "support/colonisation_tree.hpp"

namespace perch::support {

namespace detail::sca {

inline constexpr double ln2 = 0.69314718055994530942;

/// Natural logarithm from a fixed series (frexp is exact), x > 0; |relative error| < 1e-15.
double fixed_log(double x) noexcept {
  int e = 0;
  double m = std::frexp(x, &e);  // [0.5, 1)
  if (m < 0.70710678118654752) {
    m *= 2.0;
    --e;
  }
  const double u = (m - 1.0) / (m + 1.0);  // |u| < 0.172
  const double u2 = u * u;
  double term = u, sum = 0.0;
  for (int k = 0; k < 20; ++k) {
    sum += term / static_cast<double>(2 * k + 1);
    term *= u2;
  }
  return 2.0 * sum + static_cast<double>(e) * ln2;
}

/// e^x from a fixed series after reduction by ln 2 (ldexp is exact).
double fixed_exp(double x) noexcept {
  const double k = std::floor(x / ln2 + 0.5);
  const double r = x - k * ln2;  // |r| ≤ 0.35
  double term = 1.0, sum = 0.0;
  for (int i = 1; i < 24; ++i) {
    sum += term;
    term *= r / static_cast<double>(i);
  }
  return std::ldexp(sum, static_cast<int>(k));
}

/// x^y for x > 0 (0 otherwise), platform-independent bits.
double fixed_pow(double x, double y) noexcept {
  return x > 0.0 ? fixed_exp(y * fixed_log(x)) : 0.0;
}

using vec3 = Eigen::Vector3d;

/// cos and sin of an angle in degrees.
Eigen::Vector2d cos_sin_deg(double degrees) {
  double s = 0.0, c = 0.0;
  sin_cos(degrees * deg, s, c);
  return {c, s};
}

/// An ellipsoid of the irregular crown.
struct blob {
  vec3 centre{0.0, 0.0, 0.0};
  vec3 half{1.0, 1.0, 1.0};
};

/// Where and how one tree grows: its crown envelope (image px, y down, z towards the viewer)
/// and its growth parameters, all drawn before growth.
struct crown_plan {
  crown_form form = crown_form::decurrent;
  int tree = 0;
  double trunk_x = 0.0, root_y = 0.0, d0 = 1.0;  ///< trunk base (below the bottom row), px
  double top_y = 0.0, base_y = 0.0;              ///< crown top and bottom
  double cx = 0.0;                               ///< crown axis
  double half_width = 1.0;                       ///< widest half-width
  double depth = 0.5;                            ///< z half-extent / x half-extent
  double centre_share = 0.7;  ///< decurrent: ellipsoid centre, share of the crown height
  double lean = 0.0;          ///< trunk lean, rad from vertical
  double leader_top_y = 0.0;  ///< the trunk is pre-grown up to here
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0;  ///< where points may lie (the frame, or beyond)
  std::vector<blob> blobs;                    ///< irregular crown
  int points = 0;                             ///< attraction points; 0: from `spacing`
  double spacing = 0.6;  ///< mean point spacing in influence radii (growth needs it < 1)
  double step = 8.0, influence = 96.0, kill = 20.0;
  double tropism = 0.0;  ///< weight of an upward pull added to each growth direction
  double exponent = 2.2;
  double d_min = 1.2;                        ///< minimum diameter, px
  double max_chase = cos_sin_deg(75.0).x();  ///< a tip ignores points further off its course
  double inertia = 0.8;  ///< weight of a tip's own direction in its next step (straighter limbs)
  Eigen::Vector2d max_turn = cos_sin_deg(20.0);     ///< a tip's largest turn per step
  Eigen::Vector2d max_branch = cos_sin_deg(100.0);  ///< a new shoot's largest branching angle
};

/// Whether `p` lies in the plan's crown envelope.
bool in_crown(const crown_plan& c, const vec3& p) {
  if (p.y() < c.top_y || p.y() > c.base_y || p.x() < c.x_lo || p.x() > c.x_hi || p.y() < c.y_lo)
    return false;
  const double h = c.base_y - c.top_y;
  const double dx = p.x() - c.cx;
  const double a = c.half_width, zc = c.depth * c.half_width;
  switch (c.form) {
    case crown_form::decurrent: {
      const double b = c.centre_share * h;
      const double dy = p.y() - (c.top_y + b);
      return (dx * dx) / (a * a) + (dy * dy) / (b * b) + (p.z() * p.z()) / (zc * zc) <= 1.0;
    }
    case crown_form::excurrent: {
      const double r = a * (p.y() - c.top_y) / h;  // the cone widens downwards
      if (r <= 0.0) return false;
      return (dx * dx) / (r * r) + (p.z() * p.z()) / (c.depth * c.depth * r * r) <= 1.0;
    }
    case crown_form::columnar: {
      const double b = 0.5 * h;
      const double dy = p.y() - (c.top_y + b);
      return (dx * dx) / (a * a) + (dy * dy) / (b * b) + (p.z() * p.z()) / (zc * zc) <= 1.0;
    }
    case crown_form::irregular:
      for (const blob& e : c.blobs) {
        const vec3 q = (p - e.centre).cwiseQuotient(e.half);
        if (q.squaredNorm() <= 1.0) return true;
      }
      return false;
  }
  return false;
}

/// The bounding box of the envelope (for rejection sampling).
void crown_box(const crown_plan& c, vec3& lo, vec3& hi) {
  const double a = c.half_width;
  lo = {std::max(c.cx - a, c.x_lo), std::max(c.top_y, c.y_lo), -c.depth * a};
  hi = {std::min(c.cx + a, c.x_hi), c.base_y, c.depth * a};
  if (c.form == crown_form::irregular) {
    for (const blob& e : c.blobs) {
      lo = lo.cwiseMin(e.centre - e.half);
      hi = hi.cwiseMax(e.centre + e.half);
    }
    lo = lo.cwiseMax(vec3(c.x_lo, std::max(c.top_y, c.y_lo), lo.z()));
    hi = hi.cwiseMin(vec3(c.x_hi, c.base_y, hi.z()));
  }
}

/// Draws a uniform random value in [lo, hi) unless `given` is positive.
double pick(tree_random& rng, double given, double lo, double hi) {
  const double drawn = rng.uniform(lo, hi);  // drawn either way: the stream stays aligned
  return given > 0.0 ? given : drawn;
}

/// The crown and growth parameters of one tree: `size` scales the trunk and the tree height,
/// the trunk base lies at [base_lo, base_hi) · width.
crown_plan make_plan(const colonisation_options& o, tree_random& rng, double size, double base_lo,
                     double base_hi, int tree) {
  crown_plan c;
  c.form = o.form;
  c.tree = tree;
  const double W = o.width, H = o.height;
  const double over = std::clamp(static_cast<double>(o.overflow), 0.0, 1.0);
  c.d0 = static_cast<double>(o.trunk_diameter_mm) / static_cast<double>(o.mm_per_px) * size;
  c.trunk_x = W * rng.uniform(base_lo, base_hi);
  c.root_y = H - 1.0 + 0.5 * c.d0;  // the base cap lies below the image: the trunk is grounded
  c.top_y = H - (H - 1.0) * size * rng.uniform(0.9, 0.97) - over * 0.3 * H;
  const double tree_h = c.root_y - c.top_y;
  const double margin = 0.02 * W;
  c.x_lo = margin - over * W;
  c.x_hi = W - 1.0 - margin + over * W;
  c.y_lo = c.top_y;
  c.lean = rng.uniform(-4.0, 4.0) * deg;
  const double shift = rng.uniform(-0.05, 0.05) * W;
  double crown_share = 0.5, width_share = 1.0;
  switch (o.form) {
    case crown_form::decurrent:
      crown_share = rng.uniform(0.5, 0.62);
      width_share = rng.uniform(0.8, 1.1);
      c.depth = 0.5;
      c.centre_share = rng.uniform(0.6, 0.85);
      c.tropism = 0.08;
      c.cx = c.trunk_x + shift;
      break;
    case crown_form::excurrent:
      crown_share = rng.uniform(0.68, 0.8);
      width_share = rng.uniform(0.33, 0.48);
      c.depth = 0.6;
      c.tropism = 0.0;
      c.lean *= 0.4;
      c.cx = c.trunk_x;
      break;
    case crown_form::columnar:
      crown_share = rng.uniform(0.55, 0.7);
      width_share = rng.uniform(0.2, 0.3);
      c.depth = 0.8;
      c.tropism = 0.15;
      c.cx = c.trunk_x + 0.2 * shift;
      break;
    case crown_form::irregular:
      crown_share = rng.uniform(0.5, 0.66);
      width_share = rng.uniform(0.6, 0.9);
      c.depth = 0.5;
      c.tropism = 0.05;
      c.lean = rng.uniform(-10.0, 10.0) * deg;
      c.cx = c.trunk_x + 2.0 * shift;
      break;
  }
  c.base_y = c.top_y + tree_h * crown_share;
  const double crown_h = c.base_y - c.top_y;
  const double room = std::min(c.cx - c.x_lo, c.x_hi - c.cx);
  c.half_width = std::max(std::min(crown_h * width_share * (1.0 + over), room), 0.1 * crown_h);
  if (o.form == crown_form::irregular) {
    // A chain of overlapping ellipsoids, the first on the trunk's top, each next one leaning
    // off a random earlier one (up or sideways), so the crown is one lopsided mass.
    const int n = rng.integer(3, 5);
    for (int k = 0; k < n; ++k) {
      blob e;
      const double r = crown_h * rng.uniform(0.24, 0.38);
      e.half = {r * rng.uniform(0.9, 1.5), r * rng.uniform(0.6, 0.9), r * 0.7};
      const int from = rng.integer(0, std::max(k - 1, 0));
      double sn = 0.0, cs = 0.0;
      sin_cos(rng.uniform(-80.0, 80.0) * deg, sn, cs);
      if (k == 0) {
        e.centre = {c.trunk_x + 0.3 * shift, c.base_y - 0.8 * e.half.y(), 0.0};
      } else {
        const blob& b = c.blobs[static_cast<std::size_t>(from)];
        const double reach = 0.6 * (b.half.x() + e.half.x());
        e.centre = {b.centre.x() + reach * sn, b.centre.y() - 0.6 * (b.half.y() + e.half.y()) * cs,
                    0.0};
      }
      c.blobs.push_back(e);
    }
  }
  c.leader_top_y =
      o.form == crown_form::excurrent ? c.top_y + crown_h * rng.uniform(0.08, 0.15) : c.base_y;
  const double step_n = rng.uniform(55.0, 80.0);
  c.step = o.step_px > 0.0f ? static_cast<double>(o.step_px) : crown_h / step_n;
  c.step = std::max(c.step, 1.0);
  double i_lo = 10.0, i_hi = 16.0, k_lo = 2.5, k_hi = 3.5, n_lo = 0.55, n_hi = 0.68;
  if (o.form == crown_form::excurrent) {
    i_lo = 5.0, i_hi = 8.0, k_lo = 1.5, k_hi = 2.5, n_lo = 0.38, n_hi = 0.48;
  } else if (o.form == crown_form::columnar) {
    i_lo = 8.0, i_hi = 12.0, n_lo = 0.4, n_hi = 0.5;
  } else if (o.form == crown_form::irregular) {
    i_lo = 8.0, i_hi = 14.0, n_lo = 0.42, n_hi = 0.55;
  }
  c.influence = c.step * pick(rng, static_cast<double>(o.influence_radius), i_lo, i_hi);
  c.kill = c.step * pick(rng, static_cast<double>(o.kill_distance), k_lo, k_hi);
  // A narrow crown needs a shorter reach, or a handful of points fills it and the tree is bare.
  double narrow = c.half_width;
  for (const blob& e : c.blobs) narrow = std::min(narrow, e.half.y());
  if (!(o.influence_radius > 0.0f))
    c.influence = std::min(c.influence, std::max(0.6 * narrow, 4.0 * c.step));
  c.kill = std::min(c.kill, 0.5 * c.influence);
  c.spacing = rng.uniform(n_lo, n_hi);
  c.points =
      o.attraction_points > 0
          ? std::clamp(static_cast<int>(o.attraction_points * (tree == 0 ? 1.0 : size)), 1, 20000)
          : 0;
  c.exponent = std::clamp(pick(rng, static_cast<double>(o.pipe_exponent), 2.0, 2.5), 1.5, 3.0);
  c.d_min =
      std::max(static_cast<double>(o.min_tip_diameter_mm) / static_cast<double>(o.mm_per_px), 1.2);
  return c;
}

/// The node tree grown by space colonisation; parents come before children.
struct node_tree {
  std::vector<vec3> pos;
  std::vector<int> parent;
  std::vector<std::vector<int>> kids;
  int add(const vec3& p, int parent_index) {
    pos.push_back(p);
    parent.push_back(parent_index);
    kids.emplace_back();
    const int index = static_cast<int>(pos.size()) - 1;
    if (parent_index >= 0) kids[static_cast<std::size_t>(parent_index)].push_back(index);
    return index;
  }
};

/// Uniform attraction points in the crown envelope (rejection sampling in its box).
std::vector<vec3> scatter_points(const crown_plan& c, tree_random& rng) {
  vec3 lo, hi;
  crown_box(c, lo, hi);
  int wanted = c.points;
  if (wanted <= 0) {  // from the envelope's volume (Monte Carlo) and the spacing
    int inside = 0;
    for (int k = 0; k < 4000; ++k)
      inside += in_crown(c, vec3(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()),
                                 rng.uniform(lo.z(), hi.z())))
                    ? 1
                    : 0;
    const vec3 box = hi - lo;
    const double volume = box.x() * box.y() * box.z() * inside / 4000.0;
    const double cell = c.spacing * c.influence;
    wanted = static_cast<int>(std::clamp(volume / (cell * cell * cell), 100.0, 6000.0));
  }
  std::vector<vec3> points;
  points.reserve(static_cast<std::size_t>(wanted));
  const long long tries = 200LL * wanted;
  for (long long t = 0; t < tries && static_cast<int>(points.size()) < wanted; ++t) {
    const vec3 p(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()),
                 rng.uniform(lo.z(), hi.z()));
    if (in_crown(c, p)) points.push_back(p);
  }
  return points;
}

/// The trunk before colonisation: a gently wandering column of nodes D apart from the root up
/// to the plan's leader top, then on up until some attraction point is within the influence
/// radius (the classic start of the algorithm), at most to the crown top.
void grow_trunk(const crown_plan& c, const std::vector<vec3>& points, tree_random& rng,
                node_tree& t) {
  vec3 p(c.trunk_x, c.root_y, 0.0);
  int last = t.add(p, -1);
  double heading = c.lean;
  auto reached = [&](const vec3& q) {
    for (const vec3& a : points)
      if ((a - q).squaredNorm() <= c.influence * c.influence) return true;
    return false;
  };
  for (int n = 0; n < 100000; ++n) {
    if (p.y() <= c.top_y) break;
    if (p.y() <= c.leader_top_y && reached(p)) break;
    heading =
        std::clamp(heading + rng.uniform(-1.5, 1.5) * deg, c.lean - 6.0 * deg, c.lean + 6.0 * deg);
    double s = 0.0, co = 0.0;
    sin_cos(heading, s, co);
    p += c.step * vec3(s, -co, 0.0);
    last = t.add(p, last);
  }
}

/// `dir` turned back towards `in` if the angle between them exceeds the one whose cosine and
/// sine are `limit` (both unit vectors). Shoots do not turn back on themselves: without this a
/// tip whose points lie behind it curls into a hook (a leader at the crown's top, say).
vec3 limit_turn(const vec3& dir, const vec3& in, const Eigen::Vector2d& limit) {
  const double c = dir.dot(in);
  if (c >= limit.x()) return dir;
  vec3 side = dir - c * in;
  if (!(side.norm() > 1e-9))
    side = std::abs(in.x()) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
  side = (side - side.dot(in) * in).normalized();
  return (limit.x() * in + limit.y() * side).normalized();
}

/// Points whose nearest node went dormant take the nearest awake node instead (brute force:
/// rare). Without this a tip that will not turn to its points keeps them from every other node
/// and growth stalls.
void reassign(const std::vector<vec3>& points, const std::vector<std::uint8_t>& alive,
              const std::vector<std::uint8_t>& dormant, const node_tree& t,
              std::vector<int>& nearest, std::vector<double>& nearest_d2) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (alive[i] == 0 || nearest[i] < 0 || dormant[static_cast<std::size_t>(nearest[i])] == 0)
      continue;
    nearest[i] = -1;
    nearest_d2[i] = 1e300;
    for (std::size_t k = 0; k < t.pos.size(); ++k) {
      if (k < dormant.size() && dormant[k] != 0) continue;
      const double d2 = (points[i] - t.pos[k]).squaredNorm();
      if (d2 < nearest_d2[i]) {
        nearest_d2[i] = d2;
        nearest[i] = static_cast<int>(k);
      }
    }
  }
}

/// Runions et al. 2007, section 3: iterate association, growth and killing until no points
/// are left or no node grew. Each point keeps its nearest node; only the nodes added in the
/// last iteration can change it, so an iteration costs O(points × new nodes).
void colonise(const crown_plan& c, std::vector<vec3> points, node_tree& t) {
  const std::size_t np = points.size();
  std::vector<int> nearest(np, -1);
  std::vector<double> nearest_d2(np, 1e300);
  std::vector<std::uint8_t> alive(np, 1);
  std::vector<std::uint8_t> dormant;  // nodes that will not grow again: their points move on
  std::vector<vec3> pull;
  std::vector<int> count;
  std::size_t first_new = 0;
  const double di2 = c.influence * c.influence, dk2 = c.kill * c.kill;
  constexpr std::size_t max_nodes = 60000;
  for (int iteration = 0; iteration < 2000 && t.pos.size() < max_nodes; ++iteration) {
    const std::size_t n_nodes = t.pos.size();
    pull.assign(n_nodes, vec3::Zero());
    count.assign(n_nodes, 0);
    dormant.resize(n_nodes, 0);
    bool any_alive = false;
    for (std::size_t i = 0; i < np; ++i) {
      if (alive[i] == 0) continue;
      for (std::size_t k = first_new; k < n_nodes; ++k) {
        const double d2 = (points[i] - t.pos[k]).squaredNorm();
        if (d2 < nearest_d2[i]) {
          nearest_d2[i] = d2;
          nearest[i] = static_cast<int>(k);
        }
      }
      if (nearest_d2[i] <= dk2) {  // reached: the point is used up
        alive[i] = 0;
        continue;
      }
      any_alive = true;
      if (nearest_d2[i] > di2) continue;
      const auto k = static_cast<std::size_t>(nearest[i]);
      pull[k] += (points[i] - t.pos[k]) / std::sqrt(nearest_d2[i]);
      ++count[k];
    }
    if (!any_alive) break;
    first_new = n_nodes;
    bool slept = false;
    for (std::size_t k = 0; k < n_nodes; ++k) {
      if (count[k] == 0) continue;
      const double norm = pull[k].norm();
      if (!(norm > 1e-6 * static_cast<double>(count[k]))) continue;  // pulled both ways
      vec3 dir = pull[k] / norm + vec3(0.0, -c.tropism, 0.0);
      if (!(dir.norm() > 1e-9)) continue;
      dir.normalize();
      if (t.parent[k] >= 0) {
        const vec3 in = (t.pos[k] - t.pos[static_cast<std::size_t>(t.parent[k])]).normalized();
        // A tip runs on, and does not chase points behind it (it would orbit them: a curl).
        if (t.kids[k].empty() && dir.dot(in) < c.max_chase) {
          dormant[k] = 1;
          slept = true;
          continue;
        }
        if (t.kids[k].empty()) dir = (dir + c.inertia * in).normalized();
        dir = limit_turn(dir, in, t.kids[k].empty() ? c.max_turn : c.max_branch);
      }
      const vec3 q = t.pos[k] + c.step * dir;
      bool twin = false;  // the same shoot again: the points it aims at are already served
      for (int kid : t.kids[k])
        twin = twin || (t.pos[static_cast<std::size_t>(kid)] - q).norm() < 0.5 * c.step;
      if (!twin) {
        t.add(q, static_cast<int>(k));
      } else {
        dormant[k] = 1;
        slept = true;
      }
    }
    if (slept)
      reassign(points, alive, dormant, t, nearest, nearest_d2);
    else if (t.pos.size() == n_nodes)
      break;
  }
}

/// Removes side shoots of fewer than `keep` nodes at forks (a shoot stopped after a step or two
/// by a killed point would read as a stub on the outline); the deepest child always stays.
node_tree prune(const node_tree& t, int keep) {
  const std::size_t n = t.pos.size();
  std::vector<int> depth(n, 1);
  for (std::size_t i = n; i-- > 0;)
    for (int kid : t.kids[i])
      depth[i] = std::max(depth[i], depth[static_cast<std::size_t>(kid)] + 1);
  std::vector<std::uint8_t> gone(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (t.parent[i] >= 0 && gone[static_cast<std::size_t>(t.parent[i])] != 0) {
      gone[i] = 1;
      continue;
    }
    if (t.kids[i].size() < 2) continue;
    int deepest = t.kids[i][0];
    for (int kid : t.kids[i])
      if (depth[static_cast<std::size_t>(kid)] > depth[static_cast<std::size_t>(deepest)])
        deepest = kid;
    for (int kid : t.kids[i])
      if (kid != deepest && depth[static_cast<std::size_t>(kid)] < keep)
        gone[static_cast<std::size_t>(kid)] = 1;
  }
  node_tree out;
  std::vector<int> renamed(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (gone[i] != 0) continue;
    const int p = t.parent[i];
    renamed[i] = out.add(t.pos[i], p >= 0 ? renamed[static_cast<std::size_t>(p)] : -1);
  }
  return out;
}

/// Pipe model from the tips: each tip carries 1, a node the sum of its children (q = d^a), and
/// d = d0 · (q / q_root)^(1/a), at least `d_min`. Returns q per node in `q`.
std::vector<double> pipe_diameters(const crown_plan& c, const node_tree& t,
                                   std::vector<double>& q) {
  const std::size_t n = t.pos.size();
  q.assign(n, 0.0);
  for (std::size_t i = n; i-- > 0;) {
    if (t.kids[i].empty()) q[i] = 1.0;
    for (int kid : t.kids[i]) q[i] += q[static_cast<std::size_t>(kid)];
  }
  std::vector<double> d(n, c.d0);
  for (std::size_t i = 0; i < n; ++i)
    d[i] = std::max(c.d0 * fixed_pow(q[i] / q[0], 1.0 / c.exponent), c.d_min);
  return d;
}

/// Laplacian smoothing of a polyline, both ends fixed: removes the growth steps' zig-zag.
void smooth(std::vector<Eigen::Vector2d>& p, int passes) {
  if (p.size() < 3) return;
  std::vector<Eigen::Vector2d> next = p;
  for (int pass = 0; pass < passes; ++pass) {
    for (std::size_t i = 1; i + 1 < p.size(); ++i)
      next[i] = 0.5 * p[i] + 0.25 * (p[i - 1] + p[i + 1]);
    p.swap(next);
    next = p;
  }
}

/// A limb in node form before resampling.
struct node_limb {
  std::vector<int> nodes;         ///< base (the fork node, on the parent) → tip
  int parent = -1;                ///< limb index
  std::size_t parent_vertex = 0;  ///< index into the parent's `nodes`
  int level = 0;
};

/// Splits the node tree into limbs: the trunk from the root, then at each node the thickest
/// child (largest q; the lower index on ties) continues the limb and the others start new
/// limbs. Breadth-first, so parents come before children.
std::vector<node_limb> split_limbs(const node_tree& t, const std::vector<double>& q) {
  std::vector<node_limb> limbs;
  if (t.pos.empty()) return limbs;
  node_limb trunk;
  trunk.nodes.push_back(0);
  limbs.push_back(trunk);
  for (std::size_t li = 0; li < limbs.size(); ++li) {
    std::size_t at = static_cast<std::size_t>(limbs[li].nodes.back());
    while (!t.kids[at].empty()) {
      int best = t.kids[at][0];
      for (int kid : t.kids[at])
        if (q[static_cast<std::size_t>(kid)] > q[static_cast<std::size_t>(best)]) best = kid;
      for (int kid : t.kids[at]) {
        if (kid == best) continue;
        node_limb side;
        side.nodes = {static_cast<int>(at), kid};
        side.parent = static_cast<int>(li);
        side.parent_vertex = limbs[li].nodes.size() - 1;
        side.level = limbs[li].level + 1;
        limbs.push_back(side);  // may reallocate: index limbs[li] afresh below
      }
      limbs[li].nodes.push_back(best);
      at = static_cast<std::size_t>(best);
    }
  }
  return limbs;
}

/// Whether p lies in the image (pixel centres 0 … size − 1).
bool in_frame(int width, int height, Eigen::Vector2f p) {
  return p.x() >= 0.0f && p.y() >= 0.0f && p.x() <= static_cast<float>(width - 1) &&
         p.y() <= static_cast<float>(height - 1);
}

/// Heading (rad from vertical-up, + towards +x) of the direction (dx, dy).
float heading_of(double dx, double dy) { return static_cast<float>(std::atan2(dx, -dy)); }

/// Direction at the base of a polyline: towards the first vertex at least `reach` px away.
float base_heading(const std::vector<Eigen::Vector2f>& c, const std::vector<float>& arc,
                   float reach) {
  std::size_t j = 1;
  while (j + 1 < c.size() && arc[j] < reach) ++j;
  const Eigen::Vector2f d = c[j] - c[0];
  return heading_of(static_cast<double>(d.x()), static_cast<double>(d.y()));
}

/// Thin limbs (under this diameter everywhere, px) are twigs.
inline constexpr float twig_diameter_px = 2.5f;

/// Turns the node limbs of one tree into truth limbs appended to `out` (parent indices count
/// the limbs already there). Limbs whose base falls outside the image are dropped with their
/// descendants, so every drawn limb joins its tree inside the frame.
void emit_limbs(const crown_plan& c, const node_tree& t, const std::vector<double>& d,
                const std::vector<node_limb>& limbs, const colonisation_options& o,
                std::vector<limb_truth>& out) {
  std::vector<std::vector<Eigen::Vector2d>> smoothed(limbs.size());
  std::vector<std::vector<std::size_t>> vertex_of(limbs.size());  // node position → vertex
  std::vector<int> index_of(limbs.size(), -1);
  for (std::size_t li = 0; li < limbs.size(); ++li) {
    const node_limb& l = limbs[li];
    const auto pi = static_cast<std::size_t>(std::max(l.parent, 0));
    if (l.parent >= 0 && index_of[pi] < 0) continue;  // its parent was dropped
    std::vector<Eigen::Vector2d> p;
    for (int nd : l.nodes) {
      const vec3& v = t.pos[static_cast<std::size_t>(nd)];
      p.emplace_back(v.x(), v.y());
    }
    if (l.parent >= 0) p[0] = smoothed[pi][l.parent_vertex];  // on the parent's axis
    smooth(p, 8);
    smoothed[li] = p;
    limb_truth limb;
    limb.parent = l.parent >= 0 ? index_of[pi] : -1;
    limb.level = l.level;
    limb.tree = c.tree;
    limb.kind = l.parent < 0 ? limb_kind::trunk : limb_kind::limb;
    if (l.parent >= 0) {
      const std::size_t v = vertex_of[pi][l.parent_vertex];
      limb.parent_arc_px = out[static_cast<std::size_t>(index_of[pi])].arc_px[v];
    }
    // Resample every segment to ≤ 2 px; the nodes stay vertices (so children's bases do).
    double acc = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::size_t nd = static_cast<std::size_t>(l.nodes[i]);
      const double di = i == 0 && l.parent >= 0 ? d[static_cast<std::size_t>(l.nodes[1])] : d[nd];
      if (i > 0) {
        const Eigen::Vector2d a = p[i - 1], b = p[i];
        const double len = (b - a).norm();
        const double d_a = static_cast<double>(limb.diameter_px.back());
        const int pieces = std::max(1, static_cast<int>(std::ceil(len / 2.0)));
        for (int k = 1; k < pieces; ++k) {
          const double u = static_cast<double>(k) / pieces;
          const Eigen::Vector2d m = a + u * (b - a);
          limb.centreline.emplace_back(static_cast<float>(m.x()), static_cast<float>(m.y()));
          limb.diameter_px.push_back(static_cast<float>(d_a + u * (di - d_a)));
          limb.arc_px.push_back(static_cast<float>(acc + u * len));
        }
        acc += len;
      }
      vertex_of[li].push_back(limb.centreline.size());
      limb.centreline.emplace_back(static_cast<float>(p[i].x()), static_cast<float>(p[i].y()));
      limb.diameter_px.push_back(static_cast<float>(di));
      limb.arc_px.push_back(static_cast<float>(acc));
    }
    if (l.parent >= 0 && !in_frame(o.width, o.height, limb.centreline[0])) continue;
    limb.base_heading_rad =
        base_heading(limb.centreline, limb.arc_px, std::max(4.0f, limb.diameter_px[0]));
    limb.curvature_per_px = 0.0f;
    if (limb.kind == limb_kind::limb &&
        *std::max_element(limb.diameter_px.begin(), limb.diameter_px.end()) < twig_diameter_px)
      limb.kind = limb_kind::twig;
    index_of[li] = static_cast<int>(out.size());
    out.push_back(std::move(limb));
  }
}

/// Grows one tree (plan, points, trunk, colonisation, pruning, pipe model, limbs) into `out`.
void grow_colonised_tree(const crown_plan& c, tree_random& rng, const colonisation_options& o,
                         std::vector<limb_truth>& out) {
  const std::vector<vec3> points = scatter_points(c, rng);
  node_tree t;
  grow_trunk(c, points, rng, t);
  colonise(c, points, t);
  const node_tree pruned = prune(t, 4);
  std::vector<double> q;
  const std::vector<double> d = pipe_diameters(c, pruned, q);
  emit_limbs(c, pruned, d, split_limbs(pruned, q), o, out);
}

/// The unit tangent of a limb's polyline at arc position s (its segment's direction).
Eigen::Vector2f polyline_tangent(const limb_truth& limb, float s) {
  float u = 0.0f;
  std::size_t i = segment_at(limb, s, u);
  for (std::size_t k = 0; k + 1 < limb.centreline.size(); ++k) {
    const std::size_t j = std::min(i + k, limb.centreline.size() - 2);
    const Eigen::Vector2f dv = limb.centreline[j + 1] - limb.centreline[j];
    if (dv.norm() > 1e-4f) return dv / dv.norm();
    if (i + k >= limb.centreline.size() - 2) break;
  }
  double sn = 0.0, cs = 0.0;
  sin_cos(static_cast<double>(limb.base_heading_rad), sn, cs);
  return {static_cast<float>(sn), static_cast<float>(-cs)};
}

/// Thin clutter twigs leaving random limbs at 30–80° (drawn as `limb_kind::twig`).
void add_twigs(const colonisation_options& o, std::vector<limb_truth>& limbs) {
  if (o.twigs <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x9e3779b9u);
  std::vector<std::size_t> hosts;
  for (std::size_t i = 0; i < limbs.size(); ++i)
    if (limbs[i].kind != limb_kind::twig && limbs[i].kind != limb_kind::fragment &&
        limbs[i].diameter_px[0] >= 4.0f)
      hosts.push_back(i);
  if (hosts.empty()) return;
  const double H = o.height;
  const int wanted = std::min(o.twigs, 2000);
  for (int k = 0, draws = 0; k < wanted && draws < 20 * wanted; ++draws) {
    const std::size_t li =
        hosts[static_cast<std::size_t>(rng.integer(0, static_cast<int>(hosts.size()) - 1))];
    const limb_truth& host = limbs[li];
    const auto s =
        static_cast<float>(rng.uniform(0.1, 0.95) * static_cast<double>(length_px(host)));
    const double side = rng.sign() * rng.uniform(30.0, 80.0) * deg;
    const double diameter = rng.uniform(1.5, 3.5);
    const double length =
        0.5 * static_cast<double>(truth_diameter_at(host, s)) + H * rng.uniform(0.02, 0.07);
    const double bend = rng.uniform(-25.0, 25.0) * deg;
    const Eigen::Vector2f at = truth_point_at(host, s);
    if (!in_frame(o.width, o.height, at)) continue;
    const Eigen::Vector2f tan = polyline_tangent(host, s);
    const double heading =
        std::atan2(static_cast<double>(tan.x()), -static_cast<double>(tan.y())) + side;
    limb_truth twig;
    twig.parent = static_cast<int>(li);
    twig.parent_arc_px = s;
    twig.level = host.level + 1;
    twig.kind = limb_kind::twig;
    twig.tree = host.tree;
    twig.base_heading_rad = static_cast<float>(heading);
    const int n = std::max(2, static_cast<int>(std::ceil(length / 2.0)));
    Eigen::Vector2d p(static_cast<double>(at.x()), static_cast<double>(at.y()));
    double acc = 0.0;
    for (int i = 0; i <= n; ++i) {
      if (i > 0) {
        double sn = 0.0, cs = 0.0;
        sin_cos(heading + bend * (i - 0.5) / n, sn, cs);
        p += (length / n) * Eigen::Vector2d(sn, -cs);
        acc += length / n;
      }
      const double u = static_cast<double>(i) / n;
      twig.centreline.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
      twig.diameter_px.push_back(
          static_cast<float>(diameter + (std::max(1.0, 0.6 * diameter) - diameter) * u));
      twig.arc_px.push_back(static_cast<float>(acc));
    }
    twig.centreline[0] = at;
    limbs.push_back(std::move(twig));
    ++k;
  }
}

/// Boundary noise: bumps (discs straddling the outline) and spurs (thin capsules sticking out),
/// about one per 6·noise + 10 px of outline.
void add_outline_noise(const colonisation_options& o, const std::vector<limb_truth>& limbs,
                       image_view<std::uint8_t> mask) {
  if (!(o.noise > 0.0f) || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x85ebca6bu);
  const double a = static_cast<double>(o.noise);
  double outline = 0.0;
  std::vector<double> cumulative;
  for (const limb_truth& limb : limbs) {
    if (limb.kind != limb_kind::twig && limb.kind != limb_kind::fragment)
      outline += 2.0 * static_cast<double>(length_px(limb));
    cumulative.push_back(outline);
  }
  const int count = std::min(static_cast<int>(outline / (6.0 * a + 10.0)), 200000);
  for (int k = 0; k < count; ++k) {
    const double pick_at = rng.uniform() * outline;
    const auto li = static_cast<std::size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), pick_at) - cumulative.begin());
    const double s_u = rng.uniform();
    const float side = static_cast<float>(rng.sign());
    const double kind = rng.uniform();
    const double size_u = rng.uniform(), offset_u = rng.uniform(0.0, 0.6);
    const double lean = rng.uniform(-0.6, 0.6), width = rng.uniform(0.8, 1.3);
    if (li >= limbs.size()) continue;
    const limb_truth& limb = limbs[li];
    const auto s = static_cast<float>(s_u * static_cast<double>(length_px(limb)));
    const Eigen::Vector2f c = truth_point_at(limb, s);
    const Eigen::Vector2f t = polyline_tangent(limb, s);
    const Eigen::Vector2f n(-t.y() * side, t.x() * side);
    const Eigen::Vector2f surface = c + 0.5f * truth_diameter_at(limb, s) * n;
    if (kind < 0.75) {
      const auto rho = static_cast<float>(a * (0.5 + 0.5 * size_u));
      draw_disc(mask, surface + n * (rho * static_cast<float>(offset_u)), rho);
    } else {
      const auto len = static_cast<float>(a * (1.5 + 1.5 * size_u));
      const Eigen::Vector2f dir = (n + t * static_cast<float>(lean)).normalized();
      draw_capsule(mask, surface - dir, surface + len * dir, static_cast<float>(width), 0.6f);
    }
  }
}

/// Pinholes: small discs (0.12–0.25 of the radius) erased inside limbs ≥ 12 px thick, off the
/// centreline by at most 0.3 of the radius, so the limb stays connected around them.
void add_holes(const colonisation_options& o, const std::vector<limb_truth>& limbs,
               image_view<std::uint8_t> mask) {
  if (o.holes <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0xc2b2ae35u);
  std::vector<std::size_t> thick;
  for (std::size_t i = 0; i < limbs.size(); ++i)
    if (limbs[i].kind != limb_kind::twig && limbs[i].kind != limb_kind::fragment &&
        limbs[i].diameter_px.back() >= 12.0f && length_px(limbs[i]) > 4.0f)
      thick.push_back(i);
  if (thick.empty()) return;
  for (int k = 0; k < std::min(o.holes, 10000); ++k) {
    const limb_truth& limb =
        limbs[thick[static_cast<std::size_t>(rng.integer(0, static_cast<int>(thick.size()) - 1))]];
    const auto s =
        static_cast<float>(rng.uniform(0.15, 0.85) * static_cast<double>(length_px(limb)));
    const float r = 0.5f * truth_diameter_at(limb, s);
    const Eigen::Vector2f t = polyline_tangent(limb, s);
    const Eigen::Vector2f n(-t.y(), t.x());
    const auto rho = std::max(static_cast<float>(rng.uniform(0.12, 0.25)) * r, 1.0f);
    const auto offset = static_cast<float>(rng.uniform(-0.3, 0.3)) * r;
    draw_disc(mask, truth_point_at(limb, s) + offset * n, rho, 0);
  }
}

/// Whether every pixel within `clearance` px of the tapered capsule a–b (radii ra, rb) is
/// inside the image and background in `mask`.
bool clear_around(image_view<const std::uint8_t> mask, Eigen::Vector2f a, Eigen::Vector2f b,
                  float ra, float rb, float clearance) {
  const float r = std::max(ra, rb) + clearance;
  const float x0 = std::floor(std::min(a.x(), b.x()) - r),
              x1 = std::ceil(std::max(a.x(), b.x()) + r);
  const float y0 = std::floor(std::min(a.y(), b.y()) - r),
              y1 = std::ceil(std::max(a.y(), b.y()) + r);
  if (x0 < 0.0f || y0 < 0.0f || x1 > static_cast<float>(mask.width() - 1) ||
      y1 > static_cast<float>(mask.height() - 1))
    return false;
  const Eigen::Vector2f ab = b - a;
  const float len2 = ab.squaredNorm();
  for (int y = static_cast<int>(y0); y <= static_cast<int>(y1); ++y)
    for (int x = static_cast<int>(x0); x <= static_cast<int>(x1); ++x) {
      const Eigen::Vector2f p(static_cast<float>(x), static_cast<float>(y));
      const float t = len2 > 0.0f ? std::clamp((p - a).dot(ab) / len2, 0.0f, 1.0f) : 0.0f;
      const float reach = ra + t * (rb - ra) + clearance;
      if ((p - (a + t * ab)).squaredNorm() <= reach * reach && mask(x, y) != 0) return false;
    }
  return true;
}

/// Detached fragments (what a segmenter leaves of leaves, gaps, clutter): short straight
/// segments or round blobs, beside a limb or anywhere in the crown's box, at least 3 px from
/// every pixel already in the mask and fully inside the image. Drawn as they are placed, so
/// later fragments keep clear of earlier ones too. At most 60 tries each.
void add_fragments(const colonisation_options& o, std::vector<limb_truth>& limbs,
                   image_view<std::uint8_t> mask) {
  if (o.fragments <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x27d4eb2fu);
  const double H = o.height, W = o.width;
  const std::size_t structural = limbs.size();
  const double d0 = static_cast<double>(limbs[0].diameter_px[0]);
  constexpr float clearance = 3.0f;
  const int wanted = std::min(o.fragments, 1000);
  for (int k = 0, tries = 0; k < wanted && tries < 60 * wanted; ++tries) {
    const bool blob_kind = rng.uniform() < 0.4;
    const double diameter = blob_kind ? rng.uniform(4.0, std::max(5.0, 0.35 * d0 + 4.0))
                                      : rng.uniform(2.0, std::max(3.0, std::min(0.25 * d0, 14.0)));
    const double length =
        blob_kind ? diameter * rng.uniform(0.0, 0.8) : H * rng.uniform(0.01, 0.05);
    const double heading = rng.uniform(-90.0, 90.0) * deg;
    const bool beside = rng.uniform() < 0.5;
    const auto li = static_cast<std::size_t>(rng.integer(0, static_cast<int>(structural) - 1));
    const double s_u = rng.uniform(), side = rng.sign(), gap = rng.uniform(3.0, 12.0);
    Eigen::Vector2f centre(static_cast<float>(rng.uniform(0.05, 0.95) * W),
                           static_cast<float>(rng.uniform(0.03, 0.75) * H));
    if (beside) {
      const limb_truth& limb = limbs[li];
      const auto s = static_cast<float>(s_u * static_cast<double>(length_px(limb)));
      const Eigen::Vector2f t = polyline_tangent(limb, s);
      const Eigen::Vector2f n(-t.y(), t.x());
      const double off = 0.5 * static_cast<double>(truth_diameter_at(limb, s)) +
                         0.5 * std::max(diameter, length) + gap;
      centre = truth_point_at(limb, s) + static_cast<float>(side * off) * n;
    }
    double sn = 0.0, cs = 0.0;
    sin_cos(heading, sn, cs);
    const Eigen::Vector2f half(static_cast<float>(0.5 * length * sn),
                               static_cast<float>(-0.5 * length * cs));
    const Eigen::Vector2f a = centre - half, b = centre + half;
    const auto ra = static_cast<float>(0.5 * diameter);
    const float rb = blob_kind ? ra : std::max(0.6f * ra, 0.8f);
    if (!clear_around(image_view<const std::uint8_t>(mask), a, b, ra, rb, clearance)) continue;
    limb_truth f;
    f.kind = limb_kind::fragment;
    f.parent = -1;
    f.level = 0;
    f.tree = 0;
    f.centreline = {a, b};
    f.diameter_px = {2.0f * ra, 2.0f * rb};
    f.arc_px = {0.0f, (b - a).norm()};
    f.base_heading_rad =
        heading_of(static_cast<double>(b.x() - a.x()), static_cast<double>(b.y() - a.y()));
    draw_capsule(mask, a, b, ra, rb);
    limbs.push_back(std::move(f));
    ++k;
  }
}

}  // namespace detail::sca

synthetic_tree make_colonisation_tree(const colonisation_options& options) {
  using namespace detail::sca;
  using detail::tree_random;
  synthetic_tree tree;
  tree.mm_per_px = options.mm_per_px;
  const bool valid =
      options.width >= 1 && options.height >= 1 &&
      static_cast<std::int64_t>(options.width) * options.height <= max_image_pixels &&
      std::isfinite(options.mm_per_px) && options.mm_per_px > 0.0f &&
      std::isfinite(options.trunk_diameter_mm) && options.trunk_diameter_mm > 0.0f &&
      std::isfinite(options.min_tip_diameter_mm) && std::isfinite(options.noise) &&
      std::isfinite(options.second_tree) && std::isfinite(options.overflow) &&
      std::isfinite(options.step_px) && std::isfinite(options.influence_radius) &&
      std::isfinite(options.kill_distance) && std::isfinite(options.pipe_exponent);
  if (!valid) return tree;
  tree.mask = image<std::uint8_t>(options.width, options.height, 0);
  tree_random rng(options.seed);
  const crown_plan first = make_plan(options, rng, 1.0, 0.38, 0.62, 0);
  grow_colonised_tree(first, rng, options, tree.limbs);
  if (options.second_tree > 0.0f && !tree.limbs.empty()) {
    const double size = std::min(static_cast<double>(options.second_tree), 1.0);
    tree_random rng2(options.seed ^ 0x5bd1e995u);
    const bool right = static_cast<double>(tree.limbs[0].centreline[0].x()) < 0.5 * options.width;
    const crown_plan second =
        make_plan(options, rng2, size, right ? 0.8 : 0.1, right ? 0.9 : 0.2, 1);
    grow_colonised_tree(second, rng2, options, tree.limbs);
  }
  detail::sca::add_twigs(options, tree.limbs);
  for (const limb_truth& limb : tree.limbs) {
    std::vector<float> radii(limb.diameter_px.size());
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.5f * limb.diameter_px[i];
    draw_polyline(tree.mask, limb.centreline, radii);
  }
  detail::sca::add_outline_noise(options, tree.limbs, tree.mask);
  detail::sca::add_holes(options, tree.limbs, tree.mask);
  detail::sca::add_fragments(options, tree.limbs, tree.mask);
  return tree;
}

}  // namespace perch::support
