// SPDX-License-Identifier: BSL-1.0
/// \file
/// A third family of synthetic trees, built with conventions of its own, so that what perch
/// would get wrong on a generator it has never seen shows up here. Same ground truth
/// (`limb_truth`, `synthetic_tree`, judged by `perch_truth`) as the other two families.
///
/// Architecture (how the limbs are laid out), written from the textbook descriptions:
///  - a 3-D turtle (P. Prusinkiewicz, A. Lindenmayer, "The Algorithmic Beauty of Plants",
///    Springer 1990, ch. 1.5 and 2.2: heading, rotations about the turtle's axes, tropism as a
///    rotation of the heading towards a vector, stochastic choice of productions), one axis at a
///    time, projected orthographically on the image plane (z dropped), so limbs cross in front of
///    one another and limbs pointing at the camera look short;
///  - branching after H. Honda, "Description of the form of trees by the parameters of the
///    tree-like body", J. Theor. Biol. 31 (1971): a fork's two daughters at angles θ1, θ2 from the
///    mother's heading, their lengths r1, r2 times hers (`sympodial`: r1 ≈ r2, codominant
///    forks, the mother ends at the fork);
///  - monopodial leaders (a leader runs on and carries side limbs at 20–80°, turned about it
///    by the Fibonacci divergence angle 137.5°, P&L 1990 ch. 4), a mixed form (a monopodial
///    trunk whose side limbs fork sympodially) and a fastigiate form (small angles, upward
///    tropism: steep limbs only; the population's no-perch members);
///  - per limb: drooping or steep tropism, low-frequency bending (two sinusoidal turning rates),
///    0–2 sharp kinks; dead broken stubs (short thick limbs ending abruptly, no leaves, no
///    children); clutter twigs (5–19 mm, so both near and well below the 20 mm twig limit).
///
/// Diameters by the pipe model (K. Shinozaki, K. Yoda, K. Hozumi, T. Kira, "A quantitative
/// analysis of plant form — the pipe model theory", Jap. J. Ecol. 14 (1964)): the cross-section
/// area at a point is proportional to the leaves it carries, here a unit per living tip plus a
/// density per px of leafy limb beyond the point; areas add where limbs join (so a limb's
/// diameter steps down past each child, instead of tapering linearly), scaled so the trunk base
/// is the trunk's diameter. Knots and burls: 0–4 smooth bumps of ±15 % on each limb. The
/// truth's `diameter_px` holds all of it: the drawn geometry.
///
/// Rasterisation (unlike the other families' hard-edged pixel-centre test): each limb is a
/// tapered capsule chain (the truth's), every pixel's coverage is sampled on a 4×4 grid of
/// sub-pixel points (the union of limbs ORs the sample bits), the coverage is softened by a
/// separable biweight kernel (0–1.5 px, a segmenter's soft edge), perturbed by value noise
/// (K. Perlin, "An image synthesizer", SIGGRAPH 1985: random values on a lattice, interpolated;
/// a rough, jagged outline), and thresholded at a per-tree level in [0.3, 0.7]. Then an optional
/// per-tree outline bias of ±1 px (4-neighbour dilation or erosion), then erasing defects.
///
/// Segmenter-like defects, each a knob: foliage clumps at twig ends and along some limbs (mask,
/// not truth: leaves give way to the claw), pinholes, leaves occluding a limb (a gap across it),
/// thin limbs broken into pieces, detached fragments (`limb_kind::fragment`), a second tree
/// partly in view at the side (`tree == 1`), crowns bigger than the frame.
///
/// Determinism: `detail::tree_random` (mt19937's specified output), `detail::sin_cos`, sqrt;
/// no libm transcendental decides a pixel. Host code: allocates, no exceptions. Not part of the
/// library. Every algorithm here is written for this file.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "support/synthetic_tree.hpp"

namespace perch::support {

/// How the limbs of a `make_sympodial_tree` tree are laid out.
enum class tree_architecture : std::uint8_t { sympodial, monopodial, mixed, fastigiate };

[[nodiscard]] constexpr const char* to_string(tree_architecture a) noexcept {
  switch (a) {
    case tree_architecture::sympodial: return "sympodial";
    case tree_architecture::monopodial: return "monopodial";
    case tree_architecture::mixed: return "mixed";
    case tree_architecture::fastigiate: return "fastigiate";
  }
  return "unknown";
}

/// Options of `make_sympodial_tree`. Lengths in px unless the name says mm.
struct sympodial_options {
  int width = 1280;                  ///< image width, px
  int height = 960;                  ///< image height, px
  std::uint32_t seed = 1;            ///< same options, same mask and truth
  float mm_per_px = 3.0f;            ///< scale (meant for 1.5–8)
  float trunk_diameter_mm = 200.0f;  ///< trunk diameter at its base (meant for 120–350)
  tree_architecture architecture = tree_architecture::sympodial;
  float crown = 1.0f;           ///< crown height / image height (> 1: limbs leave the frame)
  float depth = 0.6f;           ///< 0 … 1: how far out of the image plane limbs may turn
  float droop = 0.0f;           ///< 0 … 1: share of limbs that droop (the others may be steep)
  float bending = 0.0f;         ///< 0 … 1: low-frequency bending, amplitude up to 25°
  int kinks = 0;                ///< sharp kinks per limb: 0 … this (20–60°)
  int stubs = 0;                ///< dead broken stubs on the trunk and main limbs
  int twigs = 0;                ///< clutter twigs (5–19 mm, `limb_kind::twig`)
  float foliage = 0.0f;         ///< 0 … 1: share of tips (and some limbs) with leaf clumps
  float softness_px = 0.0f;     ///< biweight blur radius of the coverage, 0 … 1.5
  float threshold = 0.5f;       ///< coverage level a pixel must reach, 0.3 … 0.7
  float roughness = 0.0f;       ///< value-noise amplitude added to the coverage, 0 … 0.35
  int outline_bias_px = 0;      ///< -1, 0, +1: 4-neighbour erosion or dilation at the end
  bool bumps = true;            ///< knots and burls: ±15 % diameter bumps along the limbs
  int holes = 0;                ///< pinholes inside thick limbs
  int occlusions = 0;           ///< leaves in front of limbs: gaps across them
  int broken = 0;               ///< thin limbs (≤ 4 px) broken into pieces
  int fragments = 0;            ///< detached pieces (`limb_kind::fragment`)
  float second_tree = 0.0f;     ///< a second tree at the image side, partly out of view,
                                ///< its size relative to the first's; 0: none
};

/// Makes a tree of the third family (see the file comment). Limbs: the first tree (limbs[0] its
/// trunk, rising from below the bottom row; parents before children: main limbs, stubs,
/// twigs), the second tree if any (`tree == 1`), then the fragments (`limb_kind::fragment`,
/// parent -1). The mask (1 = tree) is NOT a redraw of the truth with the pixel-centre rule: it is
/// the sampled coverage, softened, roughened, thresholded, biased, then holed, occluded and
/// broken; foliage is in the mask only. Invalid options give an empty tree.
/// Cost: O(Σ capsule bounding boxes + pixels); ~0.1–0.5 s for a 2000×1500 tree.
[[nodiscard]] synthetic_tree make_sympodial_tree(const sympodial_options& o);

}  // namespace perch::support
