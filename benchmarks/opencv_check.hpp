// SPDX-License-Identifier: BSL-1.0
// What the benchmarks' OpenCV comparisons check first: that cv::distanceTransform (DIST_L2,
// DIST_MASK_PRECISE) gives perch's exact distances on the same mask.
#pragma once

#if PERCH_HAVE_OPENCV
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>

#include "perch/core/image.hpp"
#include "perch/distance.hpp"

namespace perch::bench {

// Pixels of `mask` where the two distances differ by more than 1e-3, or -1 if perch failed.
// OpenCV treats outside the image as foreground, perch as background, so both are compared on
// the mask with a background frame (both then measure to the same pixels).
inline long opencv_edt_differ_px(const perch::image<std::uint8_t>& mask) {
  const int w = mask.width(), h = mask.height();
  perch::image<std::uint8_t> framed = mask;
  for (int x = 0; x < w; ++x) framed(x, 0) = framed(x, h - 1) = 0;
  for (int y = 0; y < h; ++y) framed(0, y) = framed(w - 1, y) = 0;
  const cv::Mat fm(h, w, CV_8U, framed.data());
  cv::Mat fd;
  cv::distanceTransform(fm, fd, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  perch::image<std::uint32_t> d2(w, h);
  perch::workspace ws;
  if (!perch::distance_transform_sq(framed.view(), d2.view(), ws)) return -1;
  long differ = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (std::abs(std::sqrt(static_cast<double>(d2(x, y))) -
                   static_cast<double>(fd.at<float>(y, x))) > 1e-3)
        ++differ;
  return differ;
}

}  // namespace perch::bench
#endif
