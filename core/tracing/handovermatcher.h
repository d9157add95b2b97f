/***************************************************************************
  handovermatcher.h - the dynamic link refined by correlation (thesis §6.5.3)
  -------------------------------------------------------------------------
  A point of the traced line, seen at a known pixel of the previous
  station's image, is projected into the next station's image through the
  road surface. With independent GNSS/INS errors at the two stations the
  projection can be off by tens of pixels - more than the distance to a
  parallel edge (the edge line's paint beside the kerb). refineHandover()
  resamples the previous image into the next image's geometry around the
  prediction (each pixel of the window through the road surface into the
  previous image) and finds that patch in the next image by normalised
  cross-correlation, shifted across and along the line: the line's
  surroundings (kerb top, verge, paint) tell the right edge from its
  neighbours where the edge's own profile cannot.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_HANDOVERMATCHER_H
#define GEOSTATION_TRACING_HANDOVERMATCHER_H

#include <opencv2/core.hpp>

#include "geometry/projection.h"
#include "tracing/stereolinematcher.h"

namespace geostation
{

  struct HandoverOptions
  {
    int halfAcrossPx = 24;     //!< window half-size across the line (next image pixels)
    int halfAlongPx = 8;       //!< along the line
    double searchAcrossPx = 24.0; //!< shifts searched across the line, either way (the least, see maxSearchAcrossPx)
    double maxSearchAcrossPx = 60.0; //!< the most, where the poses' sigmas call for it
    double searchAlongPx = 3.0;   //!< and along it
    double minScore = 0.6;     //!< normalised cross-correlation
    double minContrast = 4.0;  //!< grey-value standard deviation of the resampled patch
  };

  struct HandoverMatch
  {
    bool found = false; //!< the window matched (score and contrast enough); the rest is valid only then
    Eigen::Vector2d pixelInNext = Eigen::Vector2d::Zero();
    double score = 0.0;
    Eigen::Vector2d shiftPx = Eigen::Vector2d::Zero(); //!< across, along the line: from where the two poses put the point
  };

  /**
   * Where the line's point seen at `pixelInPrevious` is in the next image
   * (the line running along `directionInNext` there); see the file comment.
   * `surface` maps a pixel of either image onto the road surface as the next
   * station sees it: the window around the point's projection into the next
   * image is mapped through it into the previous image and sampled there.
   * Not ok when the window leaves either image, is featureless, or
   * correlates below minScore.
   */
  HandoverMatch refineHandover( const cv::Mat &previousGrey, const OrientedImage &previous, const Eigen::Vector2d &pixelInPrevious, const cv::Mat &nextGrey,
                                const OrientedImage &next, const GroundOfPixel &surface, const Eigen::Vector2d &directionInNext,
                                const HandoverOptions &options = HandoverOptions() );

} // namespace geostation

#endif // GEOSTATION_TRACING_HANDOVERMATCHER_H
