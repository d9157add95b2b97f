/***************************************************************************
  matchingwindows.h - the pixels a match reads
  -------------------------------------------------------------------------
  An image too large to prepare whole for matching is matched in windows
  of it (MatchImage's window constructor). These say which pixels one
  match reads: around a point, or along an epipolar curve with its band.
  measurementWindows() (workstation) and the 3-D step of road extraction
  build on them.
 ***************************************************************************/
#ifndef GEOSTATION_MATCHING_MATCHINGWINDOWS_H
#define GEOSTATION_MATCHING_MATCHINGWINDOWS_H

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "matching/areamatcher.h"

namespace geostation
{

  /**
   * The pixels matching reads around `pixelInImage` (image pixels): a
   * reference point's window, or matchAroundPosition()'s search within
   * `radiusPx` of an approximate position; the largest window of `area`
   * stretched by up to AreaMatchOptions::maxAffineScale, and a few pixels
   * of least squares' movement. Clipped to the image (empty outside it).
   */
  cv::Rect matchingWindowAround( const Eigen::Vector2d &pixelInImage, double radiusPx, const AreaMatchOptions &area, const cv::Size &imageSize );

  /**
   * The pixels matchAlongEpipolarBand() reads along `curve` (image pixels,
   * ordered along it), band and windows included; over maxPixels, only the
   * part of the curve around its vertex nearest to `centre` (default: its
   * middle vertex) that fits, and `cut` (if given) is set. Empty for an
   * empty curve or one outside the image.
   */
  cv::Rect matchingWindowAlong( const std::vector<Eigen::Vector2d> &curve, const AreaMatchOptions &area, const cv::Size &imageSize, long long maxPixels,
                                const std::optional<Eigen::Vector2d> &centre = std::nullopt, bool *cut = nullptr );

} // namespace geostation

#endif // GEOSTATION_MATCHING_MATCHINGWINDOWS_H
