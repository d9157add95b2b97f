/***************************************************************************
  rotation.cpp - omega-phi-kappa rotations
 ***************************************************************************/
#include "geometry/rotation.h"

#include <algorithm>

namespace geostation
{

  Eigen::Matrix3d worldFromCameraRotationDeg( double omegaDeg, double phiDeg, double kappaDeg )
  {
    double r[9];
    worldFromCameraRotation( degToRad( omegaDeg ), degToRad( phiDeg ), degToRad( kappaDeg ), r );
    Eigen::Matrix3d R;
    R << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
    return R;
  }

  Eigen::Vector3d omegaPhiKappaDegFromRotation( const Eigen::Matrix3d &R )
  {
    // R(0,2) = sin(phi); R(1,2) = -sin(omega) cos(phi); R(2,2) = cos(omega) cos(phi);
    // R(0,1) = -cos(phi) sin(kappa); R(0,0) = cos(phi) cos(kappa).
    const double sinPhi = std::clamp( R( 0, 2 ), -1.0, 1.0 );
    const double phi = std::asin( sinPhi );
    double omega = 0.0;
    double kappa = 0.0;
    if ( std::abs( sinPhi ) < 1.0 - 1e-12 )
    {
      omega = std::atan2( -R( 1, 2 ), R( 2, 2 ) );
      kappa = std::atan2( -R( 0, 1 ), R( 0, 0 ) );
    }
    else
    {
      // Gimbal lock: with omega = 0, R(1,0) = sin(kappa), R(1,1) = cos(kappa).
      kappa = std::atan2( R( 1, 0 ), R( 1, 1 ) );
    }
    return { radToDeg( omega ), radToDeg( phi ), radToDeg( kappa ) };
  }

} // namespace geostation
