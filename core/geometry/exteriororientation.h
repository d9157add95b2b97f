/***************************************************************************
  exteriororientation.h - projection centre and attitude of one image
  -------------------------------------------------------------------------
  docs/conventions.md §3: projection centre X, Y, Z in the block CRS (metres) and
  omega, phi, kappa in degrees. A ground point P has camera coordinates
  p = R^T (P - X0) with R = worldFromCamera.
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_EXTERIORORIENTATION_H
#define GEOSTATION_GEOMETRY_EXTERIORORIENTATION_H

#include <optional>

#include <Eigen/Core>

namespace geostation
{

  //! A priori standard deviations of the six exterior values (m and degrees).
  struct ExteriorSigma
  {
    double x = 0.0, y = 0.0, z = 0.0;
    double omegaDeg = 0.0, phiDeg = 0.0, kappaDeg = 0.0;
  };

  struct ExteriorOrientation
  {
    Eigen::Vector3d projectionCentre = Eigen::Vector3d::Zero(); //!< X0 in the block CRS, metres
    double omegaDeg = 0.0;
    double phiDeg = 0.0;
    double kappaDeg = 0.0;
    std::optional<ExteriorSigma> sigma; //!< GNSS/INS quality, used as priors

    /**
     * The exterior orientation of a projection centre (block CRS, metres) and a rotation from the camera frame
     * (x right, y up, z back) to object space, expressed as omega, phi, kappa in degrees; no sigma.
     */
    static ExteriorOrientation fromCentreAndRotation( const Eigen::Vector3d &projectionCentre, const Eigen::Matrix3d &worldFromCamera );

    //! R = Rx(omega) Ry(phi) Rz(kappa): camera-frame vectors to object space.
    Eigen::Matrix3d worldFromCamera() const;

    //! p = R^T (P - X0): an object point in the camera frame.
    Eigen::Vector3d cameraFromWorld( const Eigen::Vector3d &pointInWorld ) const;

    //! A camera-frame direction expressed in object space.
    Eigen::Vector3d worldDirectionFromCamera( const Eigen::Vector3d &directionInCamera ) const;

    //! Unit vector of the viewing axis (camera -z) in object space.
    Eigen::Vector3d viewingDirection() const;
  };

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_EXTERIORORIENTATION_H
