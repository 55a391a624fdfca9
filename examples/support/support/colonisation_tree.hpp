// SPDX-License-Identifier: BSL-1.0
/// \file
/// A second family of synthetic trees, grown by space colonisation, with the same ground truth
/// (`limb_truth`, `synthetic_tree`) as `make_tree` in synthetic_tree.hpp.
///
/// `make_tree` builds a tree top-down from rules (forks, side limbs, circular arcs); these trees
/// are grown bottom-up by competition for space, after A. Runions, B. Lane, P. Prusinkiewicz,
/// "Modeling trees with a space colonization algorithm", Eurographics Workshop on Natural
/// Phenomena 2007. Attraction points are scattered in a 3-D crown envelope; each iteration every
/// point finds its nearest tree node, points within the kill distance of a node are removed, and
/// every node that is the nearest node of some points within the influence radius grows one new
/// node a step D along the normalised mean of the unit vectors to those points (plus a little
/// tropism). Growth stops when no point is left or nothing grew. The crown is grown in 3-D and
/// seen from the side (orthographic, z dropped), so limbs cross and touch in the image as they
/// do in photographs. Limbs therefore wander, fork unevenly and are not arcs: the truth carries
/// `curvature_per_px = 0` and the tangent comes from the polyline.
///
/// Diameters follow the pipe model from the tips (d_parent^a = Σ d_child^a, a ≈ 2–2.5), scaled
/// so the trunk base is `trunk_diameter_mm / mm_per_px` px, with a minimum tip diameter. The
/// node tree becomes limbs by following the thickest child at every node (the other children
/// start limbs of their own whose first point is the fork node, on the parent's centreline).
/// The growth steps zig-zag, so each limb's nodes are smoothed (Laplacian, ends fixed) and
/// resampled to ≤ 2 px; the nodes stay vertices, so a child's base is exactly a parent vertex.
///
/// Determinism: the random stream is `detail::tree_random` (mt19937's specified output), sines
/// and cosines come from `detail::sin_cos`, powers from fixed series in colonisation_tree.cpp
/// (not libm), so the same options give the same mask bytes on every IEEE-754 platform (FMA
/// contraction aside, as in synthetic_tree.hpp). Host code: allocates, no exceptions. Not part
/// of the library.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "support/synthetic_tree.hpp"

namespace perch::support {

/// The crown's shape, i.e. the envelope the attraction points fill.
///  - `decurrent`: broad, spreading, rounded crown (a cut ellipsoid, widest low down) on a clear
///    trunk; several large limbs, long near-horizontal ones at the sides (oak, maple).
///  - `excurrent`: conifer-like cone; the trunk runs on as a central leader almost to the top
///    and carries many shorter side limbs (spruce, fir).
///  - `columnar`: a tall narrow ellipsoid, steep limbs (Lombardy poplar).
///  - `irregular`: a union of 3–5 random ellipsoids off the trunk's axis, a leaning trunk.
enum class crown_form : std::uint8_t { decurrent, excurrent, columnar, irregular };

/// Options of `make_colonisation_tree`. Lengths in px unless the name says mm. Growth
/// parameters left at 0 are drawn per tree from the form's range (given in brackets), so seeds
/// vary them; set them to pin a value.
struct colonisation_options {
  int width = 1920;                  ///< image width, px (≥ 1)
  int height = 1080;                 ///< image height, px (≥ 1)
  std::uint32_t seed = 1;            ///< same options, same mask and truth
  float mm_per_px = 2.0f;            ///< scale (meant for 1.5–8)
  float trunk_diameter_mm = 180.0f;  ///< trunk diameter at its base (meant for 150–300)
  crown_form form = crown_form::decurrent;
  int attraction_points = 0;         ///< 0: from the crown's volume, so the mean spacing is
                                     ///< [0.55, 0.68] influence radii (excurrent [0.38, 0.48],
                                     ///< columnar [0.4, 0.5], irregular [0.42, 0.55])
  float step_px = 0.0f;              ///< growth step D; 0: crown height / [55, 80]
  float influence_radius = 0.0f;     ///< in steps D; 0: decurrent [10, 16], excurrent [5, 8],
                                     ///< columnar [8, 12], irregular [8, 14]
  float kill_distance = 0.0f;        ///< in steps D; 0: [2.5, 3.5] (excurrent [1.5, 2.5])
  float pipe_exponent = 0.0f;        ///< a of d^a = Σ d_child^a; 0: [2, 2.5]
  float min_tip_diameter_mm = 6.0f;  ///< tips are at least this (and ≥ 1.2 px) thick
  float overflow = 0.0f;     ///< limbs leaving the frame: the crown grows this share bigger and
                             ///< may leave the sides and top (0: it stays inside, ≤ 1)
  float noise = 0.0f;        ///< outline roughness, px: bumps and spurs this big (0: none)
  int holes = 0;             ///< pinholes: small discs erased inside thick limbs
  int twigs = 0;             ///< thin clutter twigs (1.5–3.5 px, `limb_kind::twig`) on the limbs
  int fragments = 0;         ///< detached pieces (`limb_kind::fragment`, parent -1): short
                             ///< segments or blobs ≥ 3 px from everything else in the mask
  float second_tree = 0.0f;  ///< a second, smaller tree (`tree == 1`) beside the first, its
                             ///< size relative to the first's in (0, 1]; 0: none
};

/// Makes a space-colonisation tree (see the file comment). Order of the limbs: the first tree
/// (limbs[0] its trunk, rising from below the bottom row; breadth-first, parents before
/// children), the second tree (`tree == 1`, its trunk's parent -1), twigs, then fragments
/// (`limb_kind::fragment`, parent -1, `tree` 0: they belong to no tree, tell them by kind).
/// Limbs under 2.5 px everywhere are `twig`s. Mask: 1 = tree; the union of the limbs' tapered
/// capsules, then outline noise and pinholes, then the fragments. Without noise and holes the
/// mask is exactly a redraw of the limbs (the tests check it). Invalid options (size < 1, scale
/// or trunk diameter not positive and finite) give an empty tree. Cost: O(attraction points ×
/// nodes) for growth plus the drawing; tens of ms for the defaults, at any image size.
[[nodiscard]] synthetic_tree make_colonisation_tree(const colonisation_options& options);

}  // namespace perch::support
