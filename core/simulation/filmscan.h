/***************************************************************************
  filmscan.h - the scanned-film variant of the oblique photo
  -------------------------------------------------------------------------
  A film camera with fiducial marks near the frame corners and edges, and a
  scan that is slightly rotated, scaled differently in x and y (affinity)
  and shifted against the camera's nominal pixel grid, as a real scanner
  leaves it. The truth block stores that scan as the image's inner
  orientation (photo mm = M (col, row, 1)); the noisy block leaves it out,
  to be measured from the rendered marks (geostation:inner_orientation).
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_FILMSCAN_H
#define GEOSTATION_SIMULATION_FILMSCAN_H

#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "camera/camera.h"
#include "geometry/projection.h"

namespace geostation
{

  constexpr double kFiducialDiameterPx = 24.0; //!< bright disc of a rendered mark
  constexpr double kFiducialSquareHalfPx = 1.5 * kFiducialDiameterPx; //!< half side of the dark square it sits on

  //! A fiducial's centre in the camera's nominal pixels (the camera has a pixel size).
  Eigen::Vector2d fiducialNominalPixel( const Camera &camera, const Fiducial &fiducial );

  //! Four corner and four edge fiducials, in photo mm (principal point origin).
  std::vector<Fiducial> filmFiducials( const Camera &camera );

  /**
   * A scan's photoFromPixel: the camera's nominal mapping rotated by
   * 0.1-0.4 degrees, with 0.05-0.15 % affinity and a shift of up to 0.2 mm.
   */
  Eigen::Matrix<double, 2, 3> simulatedScan( const Camera &camera, std::mt19937 &random );

  //! Draws the camera's fiducial marks (bright discs on dark squares of film border) into a rendered scan.
  void drawFiducialMarks( cv::Mat &linearRgb, const Camera &camera, const OrientedImage &scan );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_FILMSCAN_H
