/***************************************************************************
  exteriororientation.cpp - projection centre and attitude of one image
 ***************************************************************************/
#include "geometry/exteriororientation.h"

#include <Eigen/Dense>

#include "geometry/rotation.h"

namespace geostation
{

  ExteriorOrientation ExteriorOrientation::fromCentreAndRotation( const Eigen::Vector3d &projectionCentre, const Eigen::Matrix3d &worldFromCamera )
  {
    ExteriorOrientation eo;
    eo.projectionCentre = projectionCentre;
    const Eigen::Vector3d opk = omegaPhiKappaDegFromRotation( worldFromCamera );
    eo.omegaDeg = opk.x();
    eo.phiDeg = opk.y();
    eo.kappaDeg = opk.z();
    return eo;
  }

  Eigen::Matrix3d ExteriorOrientation::worldFromCamera() const
  {
    return worldFromCameraRotationDeg( omegaDeg, phiDeg, kappaDeg );
  }

  Eigen::Vector3d ExteriorOrientation::cameraFromWorld( const Eigen::Vector3d &pointInWorld ) const
  {
    return worldFromCamera().transpose() * ( pointInWorld - projectionCentre );
  }

  Eigen::Vector3d ExteriorOrientation::worldDirectionFromCamera( const Eigen::Vector3d &directionInCamera ) const
  {
    return worldFromCamera() * directionInCamera;
  }

  Eigen::Vector3d ExteriorOrientation::viewingDirection() const
  {
    return worldFromCamera() * Eigen::Vector3d( 0.0, 0.0, -1.0 );
  }

} // namespace geostation
