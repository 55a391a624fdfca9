// SPDX-License-Identifier: BSL-1.0
// sympodial_tree.hpp's generator of the third tree family, compiled once into perch_support.
#include "support/sympodial_tree.hpp"

namespace perch::support {

namespace detail::sympodial {

using vec3 = Eigen::Vector3d;

/// The cross product u × v (Eigen/Core only).
vec3 cross(const vec3& u, const vec3& v) {
  return {u.y() * v.z() - u.z() * v.y(), u.z() * v.x() - u.x() * v.z(), u.x() * v.y() - u.y() * v.x()};
}

/// Rotation of v about the unit axis k by angle a (Rodrigues' formula).
vec3 rotate(const vec3& v, const vec3& k, double a) {
  double s = 0.0, c = 0.0;
  sin_cos(a, s, c);
  return v * c + cross(k, v) * s + k * (k.dot(v) * (1.0 - c));
}

/// Two unit vectors perpendicular to the unit heading d: e1 in the image plane (z = 0), e2 =
/// d × e1. Rotating d about e2 turns it in the image plane, about e1 out of it.
void frame_of(const vec3& d, vec3& e1, vec3& e2) {
  e1 = vec3(-d.y(), d.x(), 0.0);
  const double n = e1.norm();
  e1 = n > 1e-9 ? vec3(e1 / n) : vec3(1.0, 0.0, 0.0);
  e2 = cross(d, e1);
  const double m = e2.norm();
  e2 = m > 1e-9 ? vec3(e2 / m) : vec3(0.0, 0.0, 1.0);
}

/// What an axis is.
enum class role : std::uint8_t { trunk, limb, stub, twig };

/// An axis waiting to be grown.
struct axis_seed {
  int parent = -1;             ///< axis index
  std::size_t parent_vertex = 0;
  vec3 base{0.0, 0.0, 0.0};
  vec3 heading{0.0, -1.0, 0.0};  ///< unit; y down (image), z towards the viewer
  double length = 0.0;           ///< px of 3-D arc
  int order = 0;
  role what = role::limb;
  bool monopodial = false;  ///< runs on as a leader carrying side limbs
  double roll = 0.0;        ///< azimuth of its fork plane / first side limb about its heading
  int tree = 0;
  double fixed_diameter = 0.0;  ///< stubs and twigs: px at the base (no pipe)
};

/// A grown axis.
struct axis {
  axis_seed seed;
  std::vector<vec3> points;
  std::vector<double> area;  ///< pipe-model area per vertex (relative units)
  std::vector<std::size_t> children;
  bool forked = false;  ///< ends in a fork (no own tip)
};

/// Per-tree growth parameters (from the options and the stream).
struct plan {
  tree_architecture arch = tree_architecture::sympodial;
  double H = 960.0, W = 1280.0;
  double crown_h = 960.0;
  double depth = 0.6;
  double droop = 0.0, bending = 0.0;
  int kinks = 0;
  int max_order = 3;
  double min_length = 20.0;
  double step = 2.0;
  int tree = 0;
};

/// Grows one axis: the turtle walks `seed.length` in steps ≤ `p.step`, turning by the axis's
/// own bending waves, kinks and tropism (P&L 1990 §2.2: the heading turns towards the tropism
/// vector T by e·|H × T| per step).
axis grow_axis(const axis_seed& seed, const plan& p, tree_random& rng) {
  axis a;
  a.seed = seed;
  const int n = std::clamp(static_cast<int>(std::ceil(seed.length / p.step)), 1, 20000);
  const double ds = seed.length / n;
  // Tropism: drooping (towards +y, down) or steep (towards -y), strength over the length.
  double e = 0.0;
  const double u_t = rng.uniform();
  if (seed.what == role::limb) {
    if (p.arch == tree_architecture::fastigiate)
      e = -rng.uniform(0.8, 2.0);
    else if (u_t < p.droop)
      e = rng.uniform(0.4, 1.6);  // drooping: weight of the limb and its leaves
    else if (u_t < p.droop + 0.25)
      e = -rng.uniform(0.5, 1.5);  // steep: reaching for the light
    else
      e = rng.uniform(-0.4, 0.3);
  } else if (seed.what == role::trunk) {
    e = -rng.uniform(0.0, 0.6);
  }
  const double e_per_px = e / std::max(seed.length, 1.0);
  // Bending: two sinusoidal turning rates (in-plane and out of it), amplitude ≤ 25° of heading.
  struct wave {
    double amp, omega, phase;
  };
  wave waves[2] = {};
  for (wave& w : waves) {
    const double amplitude = p.bending * rng.uniform(5.0, 25.0) * deg;
    const double periods = rng.uniform(0.4, 1.6);
    w.omega = 2.0 * pi * periods / std::max(seed.length, 0.15 * p.H);
    w.amp = amplitude * w.omega;  // the turning rate whose integral has that amplitude
    w.phase = rng.uniform(0.0, 2.0 * pi);
  }
  // Kinks at 20–80 % of the length.
  std::vector<std::pair<int, double>> kinks;
  const int k_count = seed.what == role::limb ? rng.integer(0, p.kinks) : 0;
  for (int k = 0; k < k_count; ++k)
    kinks.emplace_back(static_cast<int>(n * rng.uniform(0.2, 0.8)),
                       rng.sign() * rng.uniform(20.0, 60.0) * deg);
  vec3 d = seed.heading.normalized();
  vec3 at = seed.base;
  a.points.push_back(at);
  const vec3 up(0.0, -1.0, 0.0);
  for (int i = 1; i <= n; ++i) {
    const double s = ds * (i - 0.5);
    vec3 e1, e2;
    frame_of(d, e1, e2);
    double s0 = 0.0, c0 = 0.0, s1 = 0.0, c1 = 0.0;
    sin_cos(waves[0].omega * s + waves[0].phase, s0, c0);
    sin_cos(waves[1].omega * s + waves[1].phase, s1, c1);
    d = rotate(d, e2, waves[0].amp * c0 * ds);
    d = rotate(d, e1, p.depth * waves[1].amp * c1 * ds);
    for (const auto& k : kinks)
      if (k.first == i) {
        frame_of(d, e1, e2);
        d = rotate(d, e2, k.second);
      }
    // Tropism: e > 0 turns the heading down (towards +y), e < 0 up.
    const vec3 t = e_per_px > 0.0 ? vec3(-up) : up;
    const vec3 axis_t = cross(d, t);
    const double sin_dt = axis_t.norm();
    if (sin_dt > 1e-9) d = rotate(d, axis_t / sin_dt, std::abs(e_per_px) * ds * sin_dt);
    d.normalize();
    at += ds * d;
    a.points.push_back(at);
  }
  return a;
}

/// The direction of a daughter at angle `theta` from heading d, its plane turned by `roll`
/// about d (0: the image plane), out-of-plane turns scaled by `depth`.
vec3 branch(const vec3& d, double theta, double roll, double depth) {
  vec3 e1, e2;
  frame_of(d, e1, e2);
  double s = 0.0, c = 0.0;
  sin_cos(roll, s, c);
  vec3 k = c * e2 + depth * s * e1;
  k.normalize();
  return rotate(d, k, theta).normalized();
}

/// Arc length along a 3-D polyline up to vertex v.
double arc3(const std::vector<vec3>& pts, std::size_t v) {
  double acc = 0.0;
  for (std::size_t i = 1; i <= v && i < pts.size(); ++i) acc += (pts[i] - pts[i - 1]).norm();
  return acc;
}

/// Grows a whole tree's axes breadth-first (parents first) into `axes`.
void grow(const plan& p, const axis_seed& trunk, tree_random& rng, std::vector<axis>& axes,
          std::size_t max_axes) {
  std::vector<axis_seed> queue{trunk};
  constexpr double golden = 137.5 * deg;  // Fibonacci divergence (P&L 1990 ch. 4)
  for (std::size_t qi = 0; qi < queue.size() && axes.size() < max_axes; ++qi) {
    const axis_seed seed = queue[qi];
    axis a = grow_axis(seed, p, rng);
    const auto index = axes.size();
    if (seed.parent >= 0) axes[static_cast<std::size_t>(seed.parent)].children.push_back(index);
    const std::size_t last = a.points.size() - 1;
    const vec3 tip = a.points[last];
    const vec3 tip_heading = (a.points[last] - a.points[last - 1]).normalized();
    auto heading_at = [&](std::size_t v) {
      const std::size_t v0 = v == 0 ? 0 : v - 1, v1 = std::min(v + 1, last);
      return vec3((a.points[v1] - a.points[v0]).normalized());
    };
    auto inside = [&](const vec3& q) {
      return q.x() >= 0.0 && q.y() >= 0.0 && q.x() <= p.W - 1.0 && q.y() <= p.H - 1.0;
    };
    const bool living = seed.what == role::trunk || seed.what == role::limb;
    const int next = seed.order + 1;
    if (living && next <= p.max_order) {
      // Side limbs along a leader (monopodial axes), or a few side shoots on a sympodial one.
      const bool leader = seed.monopodial;
      const int sides = leader ? rng.integer(3, 6) : rng.integer(0, 1);
      double roll = seed.roll;
      const double first = seed.what == role::trunk ? rng.uniform(0.25, 0.45) : 0.2;
      for (int k = 0; k < sides; ++k) {
        const double u = leader ? first + (0.95 - first) * (k + rng.uniform(0.2, 0.8)) / sides
                                : rng.uniform(0.3, 0.85);
        const auto v = std::min(last - 1, static_cast<std::size_t>(u * static_cast<double>(last)));
        if (v == 0 || !inside(a.points[v])) continue;
        roll += golden;
        const double theta = p.arch == tree_architecture::fastigiate ? rng.uniform(10.0, 25.0) * deg
                                                                     : rng.uniform(20.0, 80.0) * deg;
        axis_seed side;
        side.parent = static_cast<int>(index);
        side.parent_vertex = v;
        side.base = a.points[v];
        side.heading = branch(heading_at(v), rng.sign() * theta, roll, p.depth);
        const double above = seed.length * (1.0 - u);
        side.length = leader ? std::max(above * rng.uniform(0.5, 1.1), 0.25 * seed.length * rng.uniform(0.6, 1.0))
                             : seed.length * rng.uniform(0.35, 0.6);
        side.order = next;
        side.what = role::limb;
        side.monopodial = p.arch == tree_architecture::monopodial && rng.uniform() < 0.5;
        side.roll = rng.uniform(0.0, 2.0 * pi);
        side.tree = seed.tree;
        if (side.length >= p.min_length) queue.push_back(side);
      }
      // The sympodial fork at the tip (Honda 1971): two daughters, θ1 and θ2 either side.
      if (!leader && inside(tip)) {
        const bool steep = p.arch == tree_architecture::fastigiate;
        const double t1 = steep ? rng.uniform(8.0, 20.0) : rng.uniform(15.0, 40.0);
        const double t2 = steep ? rng.uniform(8.0, 20.0) : rng.uniform(20.0, 50.0);
        const double r1 = rng.uniform(0.65, 0.9);
        const double r2 = rng.uniform() < 0.6 ? r1 * rng.uniform(0.9, 1.0) : r1 * rng.uniform(0.6, 0.9);
        const double roll_f = seed.roll + (rng.uniform() < 0.5 ? 0.0 : 0.5 * pi) + rng.uniform(-0.4, 0.4);
        const double sign = rng.sign();
        const double thetas[2] = {sign * t1 * deg, -sign * t2 * deg};
        const double ratios[2] = {r1, r2};
        for (int c = 0; c < 2; ++c) {
          axis_seed child;
          child.parent = static_cast<int>(index);
          child.parent_vertex = last;
          child.base = tip;
          child.heading = branch(tip_heading, thetas[c], roll_f, p.depth);
          child.length = seed.length * ratios[c];
          child.order = next;
          child.what = role::limb;
          child.monopodial = p.arch == tree_architecture::monopodial;
          child.roll = roll_f + 0.5 * pi;
          child.tree = seed.tree;
          if (child.length >= p.min_length) {
            queue.push_back(child);
            a.forked = true;
          }
        }
      }
    }
    axes.push_back(std::move(a));
  }
}

/// A smooth bump, 1 at 0 and 0 beyond |u| ≥ 1 (the biweight kernel).
double biweight(double u) noexcept {
  const double q = 1.0 - u * u;
  return q > 0.0 ? q * q : 0.0;
}

/// The pipe model (Shinozaki et al. 1964): per vertex, the area of leaves beyond it.
void pipe_areas(std::vector<axis>& axes, double tip_area, double leaf_density) {
  for (std::size_t ai = axes.size(); ai-- > 0;) {
    axis& a = axes[ai];
    a.area.assign(a.points.size(), 0.0);
    if (a.seed.what == role::stub || a.seed.what == role::twig) continue;
    const double rho = a.seed.order >= 1 ? leaf_density : 0.0;
    double acc = a.forked ? 0.0 : tip_area;
    for (std::size_t v = a.points.size(); v-- > 0;) {
      for (const std::size_t c : a.children) {
        const axis& ch = axes[c];
        if (ch.seed.parent_vertex == v && !ch.area.empty()) acc += ch.area[0];
      }
      a.area[v] = acc;
      if (v > 0) acc += rho * (a.points[v] - a.points[v - 1]).norm();
    }
  }
}

/// Coverage of the union of capsules, 16 sub-pixel samples per pixel (bit i: sample (i%4,
/// i/4) at offsets −3/8, −1/8, 1/8, 3/8 from the pixel centre).
class coverage {
 public:
  coverage(int w, int h) : w_(w), h_(h), bits_(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0) {}
  [[nodiscard]] int width() const noexcept { return w_; }
  [[nodiscard]] int height() const noexcept { return h_; }
  [[nodiscard]] std::uint16_t at(int x, int y) const noexcept {
    return bits_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(x)];
  }
  /// The tapered capsule a–b, radii ra, rb.
  void capsule(Eigen::Vector2f a, Eigen::Vector2f b, float ra, float rb) {
    if (!(ra > 0.0f) && !(rb > 0.0f)) return;
    ra = std::max(ra, 0.0f);
    rb = std::max(rb, 0.0f);
    const float r = std::max(ra, rb) + 1.0f;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min(a.x(), b.x()) - r)));
    const int x1 = std::min(w_ - 1, static_cast<int>(std::ceil(std::max(a.x(), b.x()) + r)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min(a.y(), b.y()) - r)));
    const int y1 = std::min(h_ - 1, static_cast<int>(std::ceil(std::max(a.y(), b.y()) + r)));
    if (x0 > x1 || y0 > y1) return;
    const Eigen::Vector2f ab = b - a;
    const float len2 = ab.squaredNorm();
    const float inv = len2 > 0.0f ? 1.0f / len2 : 0.0f;
    const float dr = rb - ra;
    // The signed distance is Lipschitz with constant ≤ 1 + |dr|/len: beyond this margin a
    // pixel's 16 samples all agree with its centre.
    const float lip = 1.0f + (len2 > 0.0f ? std::abs(dr) / std::sqrt(len2) : 0.0f);
    const float margin = 0.54f * lip;  // the farthest sample is 0.53 px from the centre
    auto sd = [&](float px, float py) {
      float t = (px * ab.x() + py * ab.y()) * inv;
      t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
      const float dx = px - t * ab.x(), dy = py - t * ab.y();
      return std::sqrt(dx * dx + dy * dy) - (ra + t * dr);
    };
    constexpr float off[4] = {-0.375f, -0.125f, 0.125f, 0.375f};
    for (int y = y0; y <= y1; ++y) {
      std::uint16_t* row = &bits_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w_)];
      const float py = static_cast<float>(y) - a.y();
      for (int x = x0; x <= x1; ++x) {
        std::uint16_t& cell = row[x];
        if (cell == 0xFFFFu) continue;
        const float px = static_cast<float>(x) - a.x();
        const float c = sd(px, py);
        if (c >= margin) continue;
        if (c <= -margin) {
          cell = 0xFFFFu;
          continue;
        }
        std::uint16_t m = 0;
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i)
            if (sd(px + off[i], py + off[j]) <= 0.0f) m = static_cast<std::uint16_t>(m | (1u << (j * 4 + i)));
        cell = static_cast<std::uint16_t>(cell | m);
      }
    }
  }
  void polyline(const std::vector<Eigen::Vector2f>& pts, const std::vector<float>& diameters) {
    if (pts.size() == 1) capsule(pts[0], pts[0], 0.5f * diameters[0], 0.5f * diameters[0]);
    for (std::size_t i = 0; i + 1 < pts.size(); ++i)
      capsule(pts[i], pts[i + 1], 0.5f * diameters[i], 0.5f * diameters[i + 1]);
  }
  /// Whether any sample lies within `gap` px of the capsule a–b (or it leaves the image).
  [[nodiscard]] bool occupied_near(Eigen::Vector2f a, Eigen::Vector2f b, float ra, float rb, float gap) const {
    const float r = std::max(ra, rb) + gap + 1.0f;
    const float fx0 = std::floor(std::min(a.x(), b.x()) - r), fx1 = std::ceil(std::max(a.x(), b.x()) + r);
    const float fy0 = std::floor(std::min(a.y(), b.y()) - r), fy1 = std::ceil(std::max(a.y(), b.y()) + r);
    if (fx0 < 0.0f || fy0 < 0.0f || fx1 > static_cast<float>(w_ - 1) || fy1 > static_cast<float>(h_ - 1))
      return true;
    const Eigen::Vector2f ab = b - a;
    const float len2 = ab.squaredNorm();
    for (int y = static_cast<int>(fy0); y <= static_cast<int>(fy1); ++y)
      for (int x = static_cast<int>(fx0); x <= static_cast<int>(fx1); ++x) {
        if (at(x, y) == 0) continue;
        const Eigen::Vector2f q(static_cast<float>(x) - a.x(), static_cast<float>(y) - a.y());
        const float t = len2 > 0.0f ? std::clamp(q.dot(ab) / len2, 0.0f, 1.0f) : 0.0f;
        if ((q - t * ab).norm() <= ra + t * (rb - ra) + gap) return true;
      }
    return false;
  }

 private:
  int w_, h_;
  std::vector<std::uint16_t> bits_;
};

/// Value noise (Perlin 1985): uniform values on a lattice `cell` px apart, bilinearly
/// interpolated with a smoothstep, in [-1, 1].
class value_noise {
 public:
  value_noise(int w, int h, double cell, tree_random& rng)
      : cell_(std::max(cell, 1.0)),
        nx_(static_cast<int>(std::ceil(w / cell_)) + 2),
        ny_(static_cast<int>(std::ceil(h / cell_)) + 2) {
    values_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
    for (double& v : values_) v = rng.uniform(-1.0, 1.0);
  }
  [[nodiscard]] double at(int x, int y) const noexcept {
    const double fx = x / cell_, fy = y / cell_;
    const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
    double u = fx - ix, v = fy - iy;
    u = u * u * (3.0 - 2.0 * u);
    v = v * v * (3.0 - 2.0 * v);
    auto val = [&](int i, int j) {
      return values_[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(i)];
    };
    return (1 - v) * ((1 - u) * val(ix, iy) + u * val(ix + 1, iy)) +
           v * ((1 - u) * val(ix, iy + 1) + u * val(ix + 1, iy + 1));
  }

 private:
  double cell_;
  int nx_, ny_;
  std::vector<double> values_;
};

/// The limbs of one grown tree, appended to `out` (axis i → limb offset + i). Diameters are the
/// pipe areas scaled so the trunk base is `d0` px, with knots and burls.
void emit(const std::vector<axis>& axes, double d0, const sympodial_options& o, tree_random& rng,
          std::vector<limb_truth>& out) {
  const int offset = static_cast<int>(out.size());
  const double scale = axes[0].area[0] > 0.0 ? d0 * d0 / axes[0].area[0] : 1.0;
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  for (std::size_t ai = 0; ai < axes.size(); ++ai) {
    const axis& a = axes[ai];
    limb_truth L;
    L.parent = a.seed.parent >= 0 ? offset + a.seed.parent : -1;
    L.level = a.seed.order;
    L.tree = a.seed.tree;
    L.exact_arc = false;
    L.kind = a.seed.what == role::trunk ? limb_kind::trunk
             : a.seed.what == role::twig ? limb_kind::twig
                                         : limb_kind::limb;
    for (const vec3& q : a.points) L.centreline.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
    L.arc_px.assign(L.centreline.size(), 0.0f);
    double acc = 0.0;
    for (std::size_t i = 1; i < L.centreline.size(); ++i) {
      acc += static_cast<double>((L.centreline[i] - L.centreline[i - 1]).norm());
      L.arc_px[i] = static_cast<float>(acc);
    }
    // Diameters: the pipe, or fixed (stubs taper to 85 %, twigs to 60 %).
    const std::size_t n = a.points.size();
    std::vector<double> d(n);
    for (std::size_t v = 0; v < n; ++v) {
      const double u = n > 1 ? static_cast<double>(v) / static_cast<double>(n - 1) : 0.0;
      if (a.seed.what == role::stub)
        d[v] = a.seed.fixed_diameter * (1.0 - 0.15 * u);
      else if (a.seed.what == role::twig)
        d[v] = std::max(0.8, a.seed.fixed_diameter * (1.0 - 0.4 * u));
      else
        d[v] = std::sqrt(std::max(a.area[v], 0.0) * scale);
    }
    // A daughter is no thicker than its mother where it leaves her (areas add up exactly at a
    // fork, so this only trims rounding and stubs).
    if (L.parent >= 0) {
      const limb_truth& P = out[static_cast<std::size_t>(L.parent)];
      const double dp = static_cast<double>(P.diameter_px[a.seed.parent_vertex]);
      for (double& x : d) x = std::min(x, dp);
    }
    // Knots and burls: 0–4 bumps of ±15 % (a biweight of half-width 0.5–1.5 diameters).
    const int bumps = o.bumps && a.seed.what != role::twig ? rng.integer(0, 4) : 0;
    const double len = acc;
    for (int b = 0; b < bumps && len > 0.0; ++b) {
      const double at = rng.uniform(0.1, 0.95) * len;
      const double amp = rng.uniform(-0.15, 0.15);
      const double half = rng.uniform(0.5, 1.5) * std::max(d[0], 2.0);
      for (std::size_t v = 0; v < n; ++v)
        d[v] *= 1.0 + amp * biweight((static_cast<double>(L.arc_px[v]) - at) / half);
    }
    const double floor_px = std::max(0.8, 4.0 * px_per_mm);  // tips at least 4 mm (and 0.8 px)
    for (std::size_t v = 0; v < n; ++v) L.diameter_px.push_back(static_cast<float>(std::max(d[v], floor_px)));
    if (L.parent >= 0) L.parent_arc_px = out[static_cast<std::size_t>(L.parent)].arc_px[a.seed.parent_vertex];
    // Heading at the base and mean curvature: information only (the tangent is the polyline's).
    const std::size_t v1 = std::min<std::size_t>(n - 1, 4);
    const Eigen::Vector2f h0 = L.centreline[v1] - L.centreline[0];
    const Eigen::Vector2f h1 = L.centreline[n - 1] - L.centreline[n - 1 - v1];
    const double b0 = std::atan2(static_cast<double>(h0.x()), -static_cast<double>(h0.y()));
    const double b1 = std::atan2(static_cast<double>(h1.x()), -static_cast<double>(h1.y()));
    L.base_heading_rad = static_cast<float>(b0);
    L.curvature_per_px = len > 0.0 ? static_cast<float>((b1 - b0) / len) : 0.0f;
    out.push_back(std::move(L));
  }
}

}  // namespace detail::sympodial

synthetic_tree make_sympodial_tree(const sympodial_options& o) {
  using namespace detail::sympodial;
  using detail::tree_random;
  using detail::deg;
  using detail::pi;
  synthetic_tree tree;
  tree.mm_per_px = o.mm_per_px;
  const bool valid = o.width >= 16 && o.height >= 16 &&
                     static_cast<std::int64_t>(o.width) * o.height <= max_image_pixels &&
                     std::isfinite(o.mm_per_px) && o.mm_per_px > 0.0f && std::isfinite(o.trunk_diameter_mm) &&
                     o.trunk_diameter_mm > 0.0f && std::isfinite(o.crown) && o.crown > 0.0f &&
                     std::isfinite(o.softness_px) && std::isfinite(o.threshold) && std::isfinite(o.roughness);
  if (!valid) return tree;
  const int W = o.width, H = o.height;
  tree_random rng(o.seed);
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  const double d0 = static_cast<double>(o.trunk_diameter_mm) * px_per_mm;

  // --- Architecture: the first tree, then the second.
  auto grow_one = [&](double size, double base_x, int which, std::uint32_t mix) {
    tree_random r(o.seed ^ mix);
    plan p;
    p.arch = o.architecture;
    p.W = W;
    p.H = H;
    p.crown_h = static_cast<double>(o.crown) * H * size;
    p.depth = std::clamp(static_cast<double>(o.depth), 0.0, 1.0);
    p.droop = std::clamp(static_cast<double>(o.droop), 0.0, 1.0);
    p.bending = std::clamp(static_cast<double>(o.bending), 0.0, 1.0);
    p.kinks = std::clamp(o.kinks, 0, 4);
    p.max_order = o.architecture == tree_architecture::monopodial ? 2 : r.integer(2, 3);
    p.min_length = std::max(6.0, 0.05 * p.crown_h);
    p.tree = which;
    const double dt = d0 * size;
    axis_seed trunk;
    trunk.base = {base_x, H - 1.0 + 0.5 * dt, 0.0};
    trunk.heading = branch({0.0, -1.0, 0.0}, r.uniform(-8.0, 8.0) * deg, r.uniform(0.0, 2.0 * pi), 0.5);
    const bool leader = o.architecture != tree_architecture::sympodial &&
                        o.architecture != tree_architecture::fastigiate;
    trunk.length = leader ? p.crown_h * r.uniform(0.75, 0.95) : std::max(p.crown_h * r.uniform(0.28, 0.45), 3.0 * dt);
    trunk.what = role::trunk;
    trunk.monopodial = leader;
    trunk.roll = r.uniform(0.0, 2.0 * pi);
    trunk.tree = which;
    std::vector<axis> axes;
    grow(p, trunk, r, axes, 600);
    // A side axis of fixed base diameter (a stub or a twig) grown from vertex v (≥ 1) of axis
    // `host`, `theta` off its heading there, rolled by `roll`, with no pipe area of its own.
    auto attach = [&](std::size_t host, std::size_t v, double theta, double roll, double length,
                      role what, double diameter, const plan& ps) {
      const axis& h = axes[host];
      const std::size_t last = h.points.size() - 1;
      axis_seed s;
      s.parent = static_cast<int>(host);
      s.parent_vertex = v;
      s.base = h.points[v];
      const vec3 hd = (h.points[std::min(v + 1, last)] - h.points[v - 1]).normalized();
      s.heading = branch(hd, theta, roll, p.depth);
      s.length = length;
      s.order = h.seed.order + 1;
      s.what = what;
      s.fixed_diameter = diameter;
      s.tree = which;
      axis a = grow_axis(s, ps, r);
      a.area.assign(a.points.size(), 0.0);
      axes[host].children.push_back(axes.size());
      axes.push_back(std::move(a));
    };
    // Stubs: dead, broken, thick and short (1–3 diameters), on the trunk and main limbs.
    const std::size_t structural = axes.size();
    const double tip_area = 1.0, leaf_density = r.uniform(60.0, 200.0) / std::max(p.crown_h, 1.0);
    pipe_areas(axes, tip_area, leaf_density);
    const double scale = axes[0].area[0] > 0.0 ? dt * dt / axes[0].area[0] : 1.0;
    const int stubs = which == 0 ? std::clamp(o.stubs, 0, 40) : o.stubs / 2;
    for (int k = 0, tries = 0; k < stubs && tries < 20 * (stubs + 1); ++tries) {
      const auto hi = static_cast<int>(std::min<std::size_t>(structural, 12)) - 1;
      const auto host = static_cast<std::size_t>(r.integer(0, std::max(hi, 0)));
      const axis& h = axes[host];
      const std::size_t last = h.points.size() - 1;
      const auto v = static_cast<std::size_t>(r.uniform(0.15, 0.85) * static_cast<double>(last));
      const double dh = std::sqrt(std::max(h.area[v], 0.0) * scale);
      const double ds = dh * r.uniform(0.45, 0.9);
      const double theta = r.uniform(40.0, 95.0) * deg * r.sign();
      const double roll = r.uniform(-0.6, 0.6) + (r.uniform() < 0.5 ? 0.0 : pi);
      if (ds * static_cast<double>(o.mm_per_px) < 15.0 || v == 0) continue;
      plan ps = p;
      ps.bending = 0.0;
      attach(host, v, theta, roll, 0.5 * dh + ds * r.uniform(1.0, 3.0), role::stub, ds, ps);
      ++k;
    }
    // Clutter twigs (5–19 mm) on the outer limbs.
    const int twigs = which == 0 ? std::clamp(o.twigs, 0, 400) : o.twigs / 3;
    for (int k = 0; k < twigs; ++k) {
      const auto host = static_cast<std::size_t>(r.integer(0, static_cast<int>(structural) - 1));
      const axis& h = axes[host];
      const std::size_t last = h.points.size() - 1;
      const auto v = std::max<std::size_t>(1, static_cast<std::size_t>(r.uniform(0.2, 1.0) * static_cast<double>(last)));
      const double mm = r.uniform() < 0.5 ? r.uniform(14.0, 19.0) : r.uniform(5.0, 14.0);
      const double theta = r.uniform(30.0, 80.0) * deg * r.sign();
      const double roll = r.uniform(0.0, 2.0 * pi);
      const double length = r.uniform(0.02, 0.07) * H;
      if (v > last) continue;
      plan ps = p;
      ps.kinks = 0;
      attach(host, v, theta, roll, length, role::twig, std::max(1.0, mm * px_per_mm), ps);
    }
    // Parents first: stubs and twigs come after every structural axis (their hosts are lower).
    emit(axes, dt, o, r, tree.limbs);
  };
  const double first_x = W * rng.uniform(0.3, 0.7);
  grow_one(1.0, first_x, 0, 0u);
  if (o.second_tree > 0.0f) {
    const bool right = first_x < 0.5 * W;
    const double x = right ? W * rng.uniform(0.92, 1.08) : W * rng.uniform(-0.08, 0.08);
    grow_one(std::min(static_cast<double>(o.second_tree), 1.0), x, 1, 0x5bd1e995u);
  }

  // --- Coverage: every truth limb, then foliage, then detached fragments.
  coverage cov(W, H);
  for (const limb_truth& L : tree.limbs) cov.polyline(L.centreline, L.diameter_px);
  if (o.foliage > 0.0f) {
    tree_random r(o.seed ^ 0x3c6ef372u);
    const double clump = r.uniform(40.0, 140.0) * px_per_mm;
    for (const limb_truth& L : tree.limbs) {
      const bool tip = L.kind == limb_kind::twig ||
                       (L.kind == limb_kind::limb && L.diameter_px.back() * o.mm_per_px < 25.0f);
      const double u = r.uniform();
      if (!tip || u >= static_cast<double>(o.foliage)) continue;
      // A clump of 3–7 leaf discs round the tip; one in three limbs also along its outer half.
      const bool along = r.uniform() < 0.33 && L.kind == limb_kind::limb;
      const int discs = r.integer(3, 7) + (along ? 6 : 0);
      for (int k = 0; k < discs; ++k) {
        const float s = along && k >= 3 ? static_cast<float>(r.uniform(0.5, 1.0)) * length_px(L) : length_px(L);
        const Eigen::Vector2f c = truth_point_at(L, s);
        const double rad = std::max(1.5, 0.5 * clump * r.uniform(0.3, 0.8));
        const double ang = r.uniform(0.0, 2.0 * pi);
        const double dist = r.uniform(0.0, 0.8) * clump * 0.5;
        double sn = 0.0, cs = 0.0;
        detail::sin_cos(ang, sn, cs);
        const Eigen::Vector2f at = c + Eigen::Vector2f(static_cast<float>(dist * cs), static_cast<float>(dist * sn));
        cov.capsule(at, at, static_cast<float>(rad), static_cast<float>(rad));
      }
    }
  }
  if (o.fragments > 0) {
    tree_random r(o.seed ^ 0x27d4eb2fu);
    const float gap = 4.0f + 2.0f * std::clamp(o.softness_px, 0.0f, 1.5f) + (o.outline_bias_px > 0 ? 2.0f : 0.0f);
    const int wanted = std::min(o.fragments, 64);
    for (int k = 0, tries = 0; k < wanted && tries < 60 * wanted; ++tries) {
      const double shape = r.uniform();
      double d = 0.0, length = 0.0;
      if (shape < 0.4) {  // a broken-off stub
        d = r.uniform(25.0, 90.0) * px_per_mm;
        length = d * r.uniform(1.0, 3.5);
      } else if (shape < 0.75) {  // a stick
        d = r.uniform(1.5, 5.0);
        length = H * r.uniform(0.02, 0.07);
      } else {  // a clump of leaves, seen as one blob
        d = r.uniform(40.0, 150.0) * px_per_mm;
        length = 0.4 * d;
      }
      const double cx = r.uniform(0.05, 0.95) * W, cy = r.uniform(0.03, 0.8) * H;
      const double heading = r.uniform(-pi, pi);
      const double bend = r.uniform(-20.0, 20.0) * deg;
      double sn = 0.0, cs = 0.0;
      detail::sin_cos(heading, sn, cs);
      limb_truth f;
      f.kind = limb_kind::fragment;
      f.parent = -1;
      f.exact_arc = false;
      f.base_heading_rad = static_cast<float>(heading);
      const int n = std::max(2, static_cast<int>(std::ceil(length / 2.0)));
      Eigen::Vector2d q(cx - 0.5 * length * sn, cy + 0.5 * length * cs);
      double acc = 0.0;
      for (int i = 0; i <= n; ++i) {
        if (i > 0) {
          double s2 = 0.0, c2 = 0.0;
          detail::sin_cos(heading + bend * (i - 0.5) / n, s2, c2);
          q += (length / n) * Eigen::Vector2d(s2, -c2);
          acc += length / n;
        }
        f.centreline.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
        f.arc_px.push_back(static_cast<float>(acc));
        f.diameter_px.push_back(static_cast<float>(d * (1.0 - 0.2 * i / n)));
      }
      bool clear = true;
      for (std::size_t i = 0; i + 1 < f.centreline.size() && clear; ++i)
        clear = !cov.occupied_near(f.centreline[i], f.centreline[i + 1], 0.5f * f.diameter_px[i],
                                   0.5f * f.diameter_px[i + 1], gap);
      if (!clear) continue;
      float nearest = std::numeric_limits<float>::infinity();
      for (const limb_truth& L : tree.limbs) {
        if (L.kind == limb_kind::fragment) continue;
        const float dist = detail::surface_distance(L, f.centreline[f.centreline.size() / 2]);
        if (dist < nearest) {
          nearest = dist;
          f.tree = L.tree;
        }
      }
      cov.polyline(f.centreline, f.diameter_px);
      tree.limbs.push_back(std::move(f));
      ++k;
    }
  }

  // --- Coverage → soft → rough → threshold.
  std::vector<float> level(static_cast<std::size_t>(W) * static_cast<std::size_t>(H));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      level[static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x)] =
          static_cast<float>(std::popcount(cov.at(x, y))) / 16.0f;
  const double soft = std::clamp(static_cast<double>(o.softness_px), 0.0, 1.5);
  if (soft > 0.0) {
    // Separable biweight kernel of half-width soft + 0.5 px.
    const double hw = soft + 0.5;
    const int R = static_cast<int>(std::ceil(hw));
    std::vector<float> k(static_cast<std::size_t>(2 * R + 1));
    double sum = 0.0;
    for (int i = -R; i <= R; ++i) sum += detail::sympodial::biweight(i / hw);
    for (int i = -R; i <= R; ++i)
      k[static_cast<std::size_t>(i + R)] = static_cast<float>(detail::sympodial::biweight(i / hw) / sum);
    std::vector<float> tmp(level.size());
    for (int pass = 0; pass < 2; ++pass) {
      const std::vector<float>& src = pass == 0 ? level : tmp;
      std::vector<float>& dst = pass == 0 ? tmp : level;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          float acc = 0.0f;
          for (int i = -R; i <= R; ++i) {
            const int xx = pass == 0 ? std::clamp(x + i, 0, W - 1) : x;
            const int yy = pass == 0 ? y : std::clamp(y + i, 0, H - 1);
            acc += k[static_cast<std::size_t>(i + R)] *
                   src[static_cast<std::size_t>(yy) * static_cast<std::size_t>(W) + static_cast<std::size_t>(xx)];
          }
          dst[static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x)] = acc;
        }
    }
  }
  const float threshold = std::clamp(o.threshold, 0.05f, 0.95f);
  const double rough = std::clamp(static_cast<double>(o.roughness), 0.0, 0.5);
  tree.mask = image<std::uint8_t>(W, H, 0);
  {
    tree_random r(o.seed ^ 0x85ebca6bu);
    const value_noise fine(W, H, r.uniform(1.5, 3.0), r);
    const value_noise coarse(W, H, r.uniform(5.0, 12.0), r);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        float v = level[static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x)];
        if (rough > 0.0 && v > 0.0f && v < 1.0f)
          v += static_cast<float>(rough * (0.6 * fine.at(x, y) + 0.4 * coarse.at(x, y)));
        tree.mask(x, y) = v >= threshold ? 1 : 0;
      }
  }
  // --- Outline bias: 4-neighbour dilation (+1) or erosion (-1).
  if (o.outline_bias_px != 0) {
    const std::uint8_t to = o.outline_bias_px > 0 ? 1 : 0;
    image<std::uint8_t> out = tree.mask;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        if (tree.mask(x, y) == to) continue;
        const bool near = (x > 0 && tree.mask(x - 1, y) == to) || (x + 1 < W && tree.mask(x + 1, y) == to) ||
                          (y > 0 && tree.mask(x, y - 1) == to) || (y + 1 < H && tree.mask(x, y + 1) == to);
        if (near) out(x, y) = to;
      }
    tree.mask = std::move(out);
  }
  // --- Erasing defects.
  auto erase_ellipse = [&](Eigen::Vector2f c, Eigen::Vector2f along, float half_along, float half_across) {
    const float r = std::max(half_along, half_across) + 1.0f;
    const int x0 = std::max(0, static_cast<int>(std::floor(c.x() - r))), x1 = std::min(W - 1, static_cast<int>(std::ceil(c.x() + r)));
    const int y0 = std::max(0, static_cast<int>(std::floor(c.y() - r))), y1 = std::min(H - 1, static_cast<int>(std::ceil(c.y() + r)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2f q(static_cast<float>(x) - c.x(), static_cast<float>(y) - c.y());
        const float a = q.dot(along) / half_along;
        const float b = (q.x() * along.y() - q.y() * along.x()) / half_across;
        if (a * a + b * b <= 1.0f) tree.mask(x, y) = 0;
      }
  };
  std::vector<std::size_t> structural;
  for (std::size_t i = 0; i < tree.limbs.size(); ++i)
    if (tree.limbs[i].kind == limb_kind::trunk || tree.limbs[i].kind == limb_kind::limb) structural.push_back(i);
  tree_random r(o.seed ^ 0xc2b2ae35u);
  if (!structural.empty()) {
    auto pick_limb = [&](float min_d, float max_d) -> const limb_truth* {
      for (int tries = 0; tries < 40; ++tries) {
        const limb_truth& L =
            tree.limbs[structural[static_cast<std::size_t>(r.integer(0, static_cast<int>(structural.size()) - 1))]];
        const float dm = L.diameter_px[L.diameter_px.size() / 2];
        if (dm >= min_d && dm <= max_d && length_px(L) > 8.0f) return &L;
      }
      return nullptr;
    };
    auto tangent = [](const limb_truth& L, float s) {
      const Eigen::Vector2f t =
          truth_point_at(L, std::min(s + 1.0f, length_px(L))) - truth_point_at(L, std::max(s - 1.0f, 0.0f));
      return t.norm() > 0.0f ? Eigen::Vector2f(t / t.norm()) : Eigen::Vector2f(0.0f, -1.0f);
    };
    for (int k = 0; k < std::min(o.holes, 200); ++k)
      if (const limb_truth* L = pick_limb(10.0f, 1e9f)) {
        const float s = static_cast<float>(r.uniform(0.15, 0.85)) * length_px(*L);
        const float rad = 0.5f * truth_diameter_at(*L, s);
        const Eigen::Vector2f t = tangent(*L, s), n(-t.y(), t.x());
        const float rho = std::max(1.0f, static_cast<float>(r.uniform(0.08, 0.22)) * rad);
        const float off = static_cast<float>(r.uniform(-0.4, 0.4)) * rad;
        erase_ellipse(truth_point_at(*L, s) + off * n, t, rho * static_cast<float>(r.uniform(0.7, 1.6)), rho);
      }
    for (int k = 0; k < std::min(o.occlusions, 20); ++k)
      if (const limb_truth* L = pick_limb(4.0f, 1e9f)) {
        const float s = static_cast<float>(r.uniform(0.2, 0.8)) * length_px(*L);
        const float half_gap = static_cast<float>(r.uniform(0.75, 4.0));
        const Eigen::Vector2f t = tangent(*L, s);
        erase_ellipse(truth_point_at(*L, s), t, half_gap, 0.5f * truth_diameter_at(*L, s) + 3.0f);
      }
    for (int k = 0; k < std::min(o.broken, 20); ++k)
      if (const limb_truth* L = pick_limb(0.5f, 4.0f)) {
        const float period = static_cast<float>(r.uniform(6.0, 20.0));
        const float half_gap = static_cast<float>(r.uniform(0.5, 1.5));
        for (float s = period * static_cast<float>(r.uniform(0.3, 1.0)); s < length_px(*L); s += period)
          erase_ellipse(truth_point_at(*L, s), tangent(*L, s), half_gap, 0.5f * truth_diameter_at(*L, s) + 1.5f);
      }
  }
  return tree;
}

}  // namespace perch::support
