// SPDX-License-Identifier: BSL-1.0
// sequence.hpp's approach sequences, compiled once into perch_support.
#include "support/sequence.hpp"

namespace perch::support {

approach_sequence::approach_sequence(const synthetic_tree& world, const sequence_options& options)
    : options_(options), world_(world) {
  world_.mask = image<std::uint8_t>();
  width_ = world.mask.width();
  height_ = world.mask.height();
  extend_trunk();
  plan_camera();
  plan_dropouts();
}

image<std::uint16_t> approach_sequence::depth_mm(const sequence_frame& frame) const {
  const float z = std::min(distance_mm(frame), 65535.0f);
  const auto value = static_cast<std::uint16_t>(std::lround(z));
  image<std::uint16_t> out(width_, height_, 0);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      if (frame.tree.mask(x, y) != 0) out(x, y) = value;
  return out;
}

sequence_frame approach_sequence::frame(int f) const {
  sequence_frame out;
  const auto& p = poses_[static_cast<std::size_t>(f)];
  const camera_motion to_frame = p.motion();
  out.from_world = to_frame;
  out.scale = p.scale;
  out.roll_deg = p.roll_deg;
  out.motion = f == 0 ? camera_motion::identity()
                      : to_frame.after(detail::sequences::inverse_similarity(
                            poses_[static_cast<std::size_t>(f - 1)].motion()));
  out.tree = transformed(to_frame, p.scale);
  out.tree.mask = image<std::uint8_t>(width_, height_, 0);
  for (const limb_truth& limb : out.tree.limbs) {
    std::vector<float> radii(limb.diameter_px.size());
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.5f * limb.diameter_px[i];
    draw_polyline(out.tree.mask, limb.centreline, radii);
  }
  out.mask = out.tree.mask;
  add_noise(f, out);
  return out;
}

void approach_sequence::extend_trunk() {
  if (world_.limbs.empty() || world_.limbs[0].centreline.size() < 2) return;
  const limb_truth& trunk = world_.limbs[0];
  limb_truth ground;
  const Eigen::Vector2f base = trunk.centreline.front();
  const Eigen::Vector2f foot = base + Eigen::Vector2f(0, 3.0f * static_cast<float>(height_));
  ground.centreline = {foot, base};
  ground.diameter_px = {trunk.diameter_px.front(), trunk.diameter_px.front()};
  ground.arc_px = {0.0f, (base - foot).norm()};
  ground.kind = limb_kind::trunk;
  ground.parent = -1;
  ground.tree = trunk.tree;
  world_.limbs.push_back(ground);
}

void approach_sequence::plan_camera() {
  detail::tree_random rng(options_.seed * 2654435761u + 17u);
  const float w = static_cast<float>(width_), h = static_cast<float>(height_);
  const Eigen::Vector2f centre(0.5f * (w - 1), 0.5f * (h - 1));
  const float side = static_cast<float>(rng.sign());
  const float rise = static_cast<float>(rng.uniform(-0.05, 0.05));
  const float roll_amplitude = options_.max_roll_deg * static_cast<float>(rng.uniform(0.5, 1.0));
  const float roll_phase = static_cast<float>(rng.uniform(0.0, 2.0 * detail::pi));
  const float roll_cycles = static_cast<float>(rng.uniform(0.3, 1.0));
  const int n = std::max(options_.frames, 1);
  poses_.resize(static_cast<std::size_t>(n));
  for (int f = 0; f < n; ++f) {
    const float u = n > 1 ? static_cast<float>(f) / static_cast<float>(n - 1) : 1.0f;
    detail::sequences::pose& p = poses_[static_cast<std::size_t>(f)];
    const float distance = options_.start_distance + (1.0f - options_.start_distance) * u;
    p.scale = 1.0f / distance;
    p.centre = centre;
    p.aim = centre + Eigen::Vector2f(side * options_.drift * w * (u - 0.5f), rise * h * u);
    double sn = 0, cs = 1;
    detail::sin_cos(2.0 * detail::pi * static_cast<double>(roll_cycles * u) +
                        static_cast<double>(roll_phase),
                    sn, cs);
    p.roll_deg = roll_amplitude * static_cast<float>(sn) +
                 options_.jitter_deg * static_cast<float>(rng.uniform(-1.0, 1.0));
    p.shake = options_.jitter_px * Eigen::Vector2f(static_cast<float>(rng.uniform(-1.0, 1.0)),
                                                   static_cast<float>(rng.uniform(-1.0, 1.0)));
  }
}

void approach_sequence::plan_dropouts() {
  detail::tree_random rng(options_.seed * 40503u + 5u);
  std::vector<int> droppable;
  for (std::size_t i = 1; i < world_.limbs.size(); ++i)
    if (world_.limbs[i].kind == limb_kind::limb) droppable.push_back(static_cast<int>(i));
  for (int f = 0; f < options_.frames; ++f) {
    const bool starts = rng.uniform() < static_cast<double>(options_.dropout_chance);
    const int frames = rng.integer(1, 3);
    const int pick = rng.integer(0, std::max(0, static_cast<int>(droppable.size()) - 1));
    const auto where = static_cast<float>(rng.uniform(0.2, 0.8));
    if (starts && !droppable.empty())
      dropouts_.push_back({f, frames, droppable[static_cast<std::size_t>(pick)], where});
  }
}

synthetic_tree approach_sequence::transformed(const camera_motion& m, float s) const {
  synthetic_tree t;
  t.mm_per_px = world_.mm_per_px / s;
  t.limbs = world_.limbs;
  for (limb_truth& limb : t.limbs) {
    for (Eigen::Vector2f& p : limb.centreline) p = m.apply(p);
    for (float& d : limb.diameter_px) d *= s;
    for (float& a : limb.arc_px) a *= s;
    limb.parent_arc_px *= s;
    limb.curvature_per_px /= s;
    limb.exact_arc = false;  // tangents from the moved polyline
  }
  return t;
}

void approach_sequence::add_noise(int f, sequence_frame& out) const {
  detail::tree_random rng(options_.seed * 97u + static_cast<std::uint32_t>(f) * 7919u + 3u);
  out.heavy = rng.uniform() < static_cast<double>(options_.heavy_chance);
  const int heavy = out.heavy ? 1 : 0;
  tree_options noise;
  noise.seed = options_.seed * 1000003u + static_cast<std::uint32_t>(f);
  noise.noise = options_.outline_noise_px * static_cast<float>(1 + 2 * heavy);
  detail::add_outline_noise(noise, out.tree.limbs, out.mask);
  add_pinholes(rng, options_.pinholes * (1 + 4 * heavy), out);
  for (const detail::sequences::dropout& d : dropouts_)
    if (f >= d.first_frame && f < d.first_frame + d.frames) {
      cut(out.tree.limbs[static_cast<std::size_t>(d.limb)], d.arc_fraction, out.mask);
      ++out.dropouts;
    }
  if (out.heavy)
    for (int k = 0; k < 2; ++k) {
      const int li = rng.integer(1, static_cast<int>(out.tree.limbs.size()) - 1);
      cut(out.tree.limbs[static_cast<std::size_t>(li)], static_cast<float>(rng.uniform(0.2, 0.8)),
          out.mask);
    }
}

void approach_sequence::add_pinholes(detail::tree_random& rng, int count, sequence_frame& out) {
  const auto& limbs = out.tree.limbs;
  if (limbs.size() < 2) return;
  for (int k = 0; k < count; ++k) {
    const limb_truth& limb = limbs[static_cast<std::size_t>(
        rng.integer(0, static_cast<int>(limbs.size()) - 2))];  // not the ground extension
    const auto s = static_cast<float>(rng.uniform() * static_cast<double>(length_px(limb)));
    const float r = 0.5f * truth_diameter_at(limb, s);
    const Eigen::Vector2f t = truth_tangent_at(limb, s);
    const Eigen::Vector2f n(-t.y(), t.x());
    const auto offset = static_cast<float>(rng.uniform(-0.6, 0.6)) * r;
    draw_disc(out.mask, truth_point_at(limb, s) + offset * n,
              static_cast<float>(rng.uniform(0.6, 1.3)), 0);
  }
}

void approach_sequence::cut(const limb_truth& limb, float fraction, image<std::uint8_t>& mask) {
  const float s = fraction * length_px(limb);
  const float d = truth_diameter_at(limb, s);
  const Eigen::Vector2f t = truth_tangent_at(limb, s);
  const Eigen::Vector2f c = truth_point_at(limb, s);
  const Eigen::Vector2f from = c - 0.75f * d * t, to = c + 0.75f * d * t;
  draw_capsule(mask, from, to, 0.5f * d + 2.0f, std::uint8_t{0});
}

approach_sequence evaluation_sequence(int i, sequence_options options, tree_family family) {
  int member = 0;
  for (int seen = 0;; ++member)
    if (wishes_perch(member) && seen++ == i) break;
  const population_member m = population_tree(family, member);
  options.seed = static_cast<std::uint32_t>(i) + 1u;
  return approach_sequence(m.tree, options);
}

}  // namespace perch::support
