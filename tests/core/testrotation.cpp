// Omega-phi-kappa: R = Rx(omega) Ry(phi) Rz(kappa), camera -> object (docs/conventions.md §3).
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "geometry/exteriororientation.h"
#include "geometry/rotation.h"

using namespace geostation;

namespace
{
  Eigen::Vector3d axisOf( double omega, double phi, double kappa )
  {
    ExteriorOrientation eo;
    eo.omegaDeg = omega;
    eo.phiDeg = phi;
    eo.kappaDeg = kappa;
    return eo.viewingDirection();
  }
} // namespace

TEST( Rotation, MatchesTheConventionProduct )
{
  std::mt19937 rng( 7 );
  std::uniform_real_distribution<double> angle( -180.0, 180.0 );
  for ( int i = 0; i < 100; ++i )
  {
    const double w = angle( rng ), p = angle( rng ) / 2, k = angle( rng );
    const Eigen::Matrix3d expected = ( Eigen::AngleAxisd( degToRad( w ), Eigen::Vector3d::UnitX() ) *
                                       Eigen::AngleAxisd( degToRad( p ), Eigen::Vector3d::UnitY() ) *
                                       Eigen::AngleAxisd( degToRad( k ), Eigen::Vector3d::UnitZ() ) ).toRotationMatrix();
    const Eigen::Matrix3d R = worldFromCameraRotationDeg( w, p, k );
    EXPECT_LT( ( R - expected ).norm(), 1e-14 );
    EXPECT_NEAR( R.determinant(), 1.0, 1e-14 );
    EXPECT_LT( ( R * R.transpose() - Eigen::Matrix3d::Identity() ).norm(), 1e-14 );
  }
}

TEST( Rotation, ElementaryMatricesAsWritten )
{
  // Rx(w) = [[1,0,0],[0,cos,-sin],[0,sin,cos]] etc., checked at 30 degrees.
  const double c = std::cos( degToRad( 30 ) ), s = std::sin( degToRad( 30 ) );
  Eigen::Matrix3d rx, ry, rz;
  rx << 1, 0, 0, 0, c, -s, 0, s, c;
  ry << c, 0, s, 0, 1, 0, -s, 0, c;
  rz << c, -s, 0, s, c, 0, 0, 0, 1;
  EXPECT_LT( ( worldFromCameraRotationDeg( 30, 0, 0 ) - rx ).norm(), 1e-15 );
  EXPECT_LT( ( worldFromCameraRotationDeg( 0, 30, 0 ) - ry ).norm(), 1e-15 );
  EXPECT_LT( ( worldFromCameraRotationDeg( 0, 0, 30 ) - rz ).norm(), 1e-15 );
}

TEST( Rotation, ZeroAnglesLookStraightDownNorthUp )
{
  EXPECT_LT( ( axisOf( 0, 0, 0 ) - Eigen::Vector3d( 0, 0, -1 ) ).norm(), 1e-15 );
  const Eigen::Matrix3d R = worldFromCameraRotationDeg( 0, 0, 0 );
  EXPECT_LT( ( R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX() ).norm(), 1e-15 ); // image right = east
  EXPECT_LT( ( R * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitY() ).norm(), 1e-15 ); // image up = north
}

TEST( Rotation, Omega90LooksTowardPlusY )
{
  EXPECT_LT( ( axisOf( 90, 0, 0 ) - Eigen::Vector3d( 0, 1, 0 ) ).norm(), 1e-15 );
  // and image up is then +Z (the sky)
  EXPECT_LT( ( worldFromCameraRotationDeg( 90, 0, 0 ) * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ() ).norm(), 1e-15 );
}

TEST( Rotation, Phi90LooksTowardMinusXAndKappa90TurnsImageRightNorth )
{
  EXPECT_LT( ( axisOf( 0, 90, 0 ) - Eigen::Vector3d( -1, 0, 0 ) ).norm(), 1e-15 );
  const Eigen::Matrix3d R = worldFromCameraRotationDeg( 0, 0, 90 );
  EXPECT_LT( ( R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY() ).norm(), 1e-15 );
}

TEST( Rotation, AnglesRoundTrip )
{
  std::mt19937 rng( 11 );
  std::uniform_real_distribution<double> angle( -179.9, 179.9 );
  std::uniform_real_distribution<double> tilt( -89.9, 89.9 );
  for ( int i = 0; i < 1000; ++i )
  {
    const Eigen::Vector3d opk( angle( rng ), tilt( rng ), angle( rng ) );
    const Eigen::Vector3d back = omegaPhiKappaDegFromRotation( worldFromCameraRotationDeg( opk.x(), opk.y(), opk.z() ) );
    EXPECT_LT( ( back - opk ).norm(), 1e-9 ) << opk.transpose();
  }
}

TEST( Rotation, GimbalLockKeepsTheRotation )
{
  const Eigen::Matrix3d R = worldFromCameraRotationDeg( 25, 90, 40 );
  const Eigen::Vector3d opk = omegaPhiKappaDegFromRotation( R );
  EXPECT_NEAR( opk.y(), 90.0, 1e-6 );
  EXPECT_LT( ( worldFromCameraRotationDeg( opk.x(), opk.y(), opk.z() ) - R ).norm(), 1e-6 );
}

TEST( Rotation, ExteriorOrientationFromCentreAndRotation )
{
  // a camera 30 m up looking north-east and 20 degrees down, rolled 5 degrees
  const Eigen::Matrix3d worldFromCamera = worldFromCameraRotationDeg( 70.0, -5.0, -45.0 );
  const Eigen::Vector3d centre( 500100.25, 5400200.5, 330.0 );
  const ExteriorOrientation eo = ExteriorOrientation::fromCentreAndRotation( centre, worldFromCamera );
  EXPECT_EQ( eo.projectionCentre, centre );
  EXPECT_NEAR( eo.omegaDeg, 70.0, 1e-9 );
  EXPECT_NEAR( eo.phiDeg, -5.0, 1e-9 );
  EXPECT_NEAR( eo.kappaDeg, -45.0, 1e-9 );
  EXPECT_LT( ( eo.worldFromCamera() - worldFromCamera ).norm(), 1e-12 );
  EXPECT_FALSE( eo.sigma.has_value() );
  // a point 10 m ahead along the viewing axis is on the camera's -z axis
  const Eigen::Vector3d ahead = eo.cameraFromWorld( centre + 10.0 * eo.viewingDirection() );
  EXPECT_LT( ( ahead - Eigen::Vector3d( 0.0, 0.0, -10.0 ) ).norm(), 1e-9 );
}
