/***************************************************************************
  directionalfollower.h - directional-matrix line following (thesis §6.3.1)
  -------------------------------------------------------------------------
  An area of interest around the current position is turned into a thin
  binary line image: a painted stripe by its top-hat (black-hat for dark
  stripes), an edge by its gradient across the line with the right
  polarity, binarised and thinned with the skeleton table (§6.2). The
  skeleton is then followed pixel by pixel with directional matrices:
  offsets ahead of the current pixel in a fixed search order, the farther
  ones first so that one-pixel gaps are bridged. When the matrix of the
  current direction finds nothing, its neighbours (15 degrees either side)
  are tried, then the large matrices (three sizes per 45 degrees) for a
  larger gap. The direction is recomputed every 20 pixels from the last
  direction counting point; those points are the vertices, each refined
  across the line to a fraction of a pixel. The area of interest moves
  with the line.

  Xin's (1995) 11 matrices cover -75..+75 degrees (up the image); the same
  construction is used every 15 degrees round the circle, so lines that
  run sideways or down the image are followed too.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_DIRECTIONALFOLLOWER_H
#define GEOSTATION_TRACING_DIRECTIONALFOLLOWER_H

#include <vector>

#include "tracing/linetrace.h"

namespace geostation
{

  struct DirectionalMatrix
  {
    double directionDeg = 0.0;              //!< from up the image, clockwise
    std::vector<Eigen::Vector2i> offsets;   //!< (dcol, drow) in search order
  };

  /**
   * The directional matrices, one every 15 degrees from 0 (up) clockwise:
   * the offsets within two pixels that lie within 60 degrees of the
   * direction, farther first, then nearer the direction first.
   */
  const std::vector<DirectionalMatrix> &directionalMatrices();

  /**
   * The large matrices for bridging gaps, three sizes (radius 5, 7, 9 px)
   * for each of the 8 directions every 45 degrees, index 3 * direction +
   * size: offsets from 3 px out within 35 degrees of the direction, nearer
   * to the current pixel and to the direction first.
   */
  const std::vector<DirectionalMatrix> &largeDirectionalMatrices();

  struct DirectionalOptions
  {
    FollowOptions follow;
    int areaPx = 64;          //!< side of the area of interest
    int adjacentMatrices = 2; //!< matrices tried either side of the current one
  };

  //! Follows the line from request.start; see the file comment.
  FollowResult followDirectional( const cv::Mat &grey, const FollowRequest &request, const DirectionalOptions &options = DirectionalOptions() );

  //! The thin binary line image (CV_8U, 255 = line) of an area of interest; exposed for tests and display.
  cv::Mat lineSkeleton( const cv::Mat &grey, const cv::Rect &area, const LineProfile &profile, const Eigen::Vector2d &direction, const FollowOptions &options );

} // namespace geostation

#endif // GEOSTATION_TRACING_DIRECTIONALFOLLOWER_H
