/***************************************************************************
  edgeprimitives.h - edge and feature primitives (thesis §6.1-6.4, Förstner)
  -------------------------------------------------------------------------
  The building blocks of road tracing and point measurement:
    gradientMagnitude()   Sobel (eq. 4.10) or the four-direction extended
                          Sobel (eqs. 4.12-4.14) gradient magnitude
    lineFilterEdges()     Xin's (1995) 1 x 7 line filter: a step between the
                          two pixels either side and the centre, so isolated
                          bit errors are not edges (§6.1)
    binarise()            edge pixels above a global threshold
    skeletonise()         thinning to one-pixel lines with a 256-entry
                          lookup table on the 8-neighbour code (Kreifelts'
                          template method, §6.2; neighbour i has bit i, in
                          the order of Xin's (1995) Figure 6.5)
    forstnerPoints()      Förstner's interest operator: weight w and
                          roundness q of the gradient structure tensor,
                          local maxima, located to sub-pixel precision as the
                          point closest to all gradient lines of the window
    centreOfGravity()     grey-weighted centroid of a mark above its background
    douglasPeucker()      polyline simplification to a tolerance
  Images are 8-bit grey (CV_8U); pixel positions follow docs/conventions.md §1.
 ***************************************************************************/
#ifndef GEOSTATION_IMAGEPROC_EDGEPRIMITIVES_H
#define GEOSTATION_IMAGEPROC_EDGEPRIMITIVES_H

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  enum class GradientFilter
  {
    Sobel,         //!< max(|Gx|, |Gy|), eq. 4.10-4.11
    ExtendedSobel, //!< max of |Gx|, |Gy|, |Gxy|, |Gyx|, eqs. 4.12-4.14
  };

  //! Gradient magnitude (CV_32F) of an 8-bit grey image. Throws std::invalid_argument for other types.
  cv::Mat gradientMagnitude( const cv::Mat &grey, GradientFilter filter );

  /**
   * Edge candidates of the 1 x 7 line filter along rows: the centre differs
   * from both pixels on one side by more than `threshold` one way and from
   * both on the other side the other way (CV_8U, 255 = candidate).
   */
  cv::Mat lineFilterEdges( const cv::Mat &grey, double threshold );

  //! 255 where `value` > threshold, else 0 (CV_8U).
  cv::Mat binarise( const cv::Mat &value, double threshold );

  //! The 8-neighbour code of a pixel of a binary image (bit i for neighbour i, Figure 6.5 order; outside = 0).
  int neighbourCode( const cv::Mat &binary, int col, int row );

  /**
   * The two deletion tables of the thinning (first and second sub-iteration):
   * entry c is 1 when a foreground pixel with neighbour code c is not a
   * skeleton pixel: isolated (a bit error), or a simple border pixel that is
   * not the end of a line, removed from the north-west side first and the
   * south-east side second so lines thin from both sides to their middle.
   */
  const std::array<std::array<uint8_t, 256>, 2> &skeletonTables();

  //! Thins a binary image (CV_8U, nonzero = foreground) to one-pixel lines; returns the iterations used.
  int skeletonise( cv::Mat &binary, int maxIterations = 50 );

  struct InterestPoint
  {
    Eigen::Vector2d pixelInImage; //!< sub-pixel location
    double weight = 0.0;          //!< w = det N / trace N
    double roundness = 0.0;       //!< q = 4 det N / trace^2 N, 0..1
  };

  struct ForstnerOptions
  {
    int window = 5;               //!< odd window for the structure tensor
    double minRoundness = 0.5;    //!< q threshold (0.5-0.75 usual)
    double weightFactor = 1.0;    //!< w threshold: this times the mean weight
    int suppressionRadius = 3;    //!< non-maximum suppression, pixels
  };

  std::vector<InterestPoint> forstnerPoints( const cv::Mat &grey, const ForstnerOptions &options = ForstnerOptions(),
      const std::optional<cv::Rect> &area = std::nullopt );

  /**
   * The grey-weighted centroid of a bright (or dark) mark in a window
   * centred near `approximate`: weights are the excess over the window's
   * median. Nothing when the window leaves the image or shows no mark.
   */
  std::optional<Eigen::Vector2d> centreOfGravity( const cv::Mat &grey, const Eigen::Vector2d &approximate, int halfSize, bool brightMark = true );

  //! Douglas-Peucker: the vertices kept so no dropped vertex is further than `tolerance` from the simplified line.
  std::vector<Eigen::Vector2d> douglasPeucker( const std::vector<Eigen::Vector2d> &polyline, double tolerance );

} // namespace geostation

#endif // GEOSTATION_IMAGEPROC_EDGEPRIMITIVES_H
