/***************************************************************************
  innerorientation.h - inner orientation of a scanned photo from fiducials
  -------------------------------------------------------------------------
  The affine transformation from image pixels to photo coordinates (mm,
  camera system, x right, y up) estimated by least squares from three or
  more fiducial marks, with Stokes' (1988) decomposition into two
  scale factors A >= B along directions alpha_A, alpha_B = alpha_A + 90 deg,
  followed by a rotation beta (Stokes 1988, §4):

      [x' - x'0]       [u - u0]
      [y' - y'0] = a * [v - v0] + eps,     (u, v) = (col, -row)

  Using v = -row makes the affine a proper one (positive determinant) for an
  ordinary scan, so beta is the scan's rotation and A, B its scales (mm/px).
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_INNERORIENTATION_H
#define GEOSTATION_ADJUSTMENT_INNERORIENTATION_H

#include <string>
#include <vector>

#include <Eigen/Core>

#include "camera/camera.h"

namespace geostation
{

  //! A fiducial measured in the image (pixels).
  struct FiducialMeasurement
  {
    std::string id;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
  };

  //! The paper's decomposition of the 2 x 2 part of the affine.
  struct AffineDecomposition
  {
    double scaleA = 0.0;       //!< largest scale factor (mm per pixel)
    double scaleB = 0.0;       //!< smallest scale factor
    double alphaADeg = 0.0;    //!< direction of A
    double alphaBDeg = 0.0;    //!< alpha_A + 90
    double affinityPct = 0.0;  //!< 100 (A / B - 1)
    double betaDeg = 0.0;      //!< rotation between image and camera system
  };

  //! Decomposes a (see the header comment); a must have a positive determinant.
  AffineDecomposition decomposeAffine( const Eigen::Matrix2d &a );

  struct FiducialResidual
  {
    std::string id;
    Eigen::Vector2d residualMm = Eigen::Vector2d::Zero(); //!< transformed - calibrated
  };

  struct InnerOrientationSummary
  {
    enum class Status
    {
      Ok,
      TooFewFiducials,
      Degenerate, //!< fiducials (nearly) on a line, or a mirrored scan
    };
    Status status = Status::Ok;
    std::string message;

    //! photo mm = photoFromPixel * (col, row, 1)^T
    Eigen::Matrix<double, 2, 3> photoFromPixel = Eigen::Matrix<double, 2, 3>::Zero();
    Eigen::Matrix2d a = Eigen::Matrix2d::Zero(); //!< on (u, v) = (col, -row)
    Eigen::Vector2d fiducialCentreMm = Eigen::Vector2d::Zero(); //!< (x'0, y'0)
    Eigen::Vector2d fiducialCentrePx = Eigen::Vector2d::Zero(); //!< (col, row) of (u0, v0)
    AffineDecomposition decomposition;
    double sigma0Mm = 0.0; //!< a posteriori, from the residuals (0 with three fiducials)
    int redundancy = 0;
    std::vector<FiducialResidual> residuals;
    double rmsResidualMm = 0.0;

    bool ok() const { return status == Status::Ok; }

    //! Photo coordinates (mm) of a pixel.
    Eigen::Vector2d photoMmFromPixel( const Eigen::Vector2d &pixelInImage ) const { return photoFromPixel.leftCols<2>() * pixelInImage + photoFromPixel.col( 2 ); }
  };

  /**
   * Estimates the inner orientation from the measured fiducials that the
   * camera defines. Measurements of unknown fiducials throw
   * std::invalid_argument; too few fiducials or degenerate ones are reported.
   */
  InnerOrientationSummary innerOrientation( const std::vector<Fiducial> &calibrated, const std::vector<FiducialMeasurement> &measured );

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_INNERORIENTATION_H
