// Interior orientation: pixel convention, distortion models, OpenCV agreement,
// round trips, behind-camera handling (docs/conventions.md §1-2).
#include <random>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "camera/camera.h"

using namespace geostation;

namespace
{
  Camera makeCamera( DistortionModel model )
  {
    Camera c;
    c.id = "test";
    c.width = 640;
    c.height = 480;
    c.f = 500.0;
    c.aspect = 1.02;
    c.cx = 322.3;
    c.cy = 238.9;
    c.pixelSizeMm = 0.0098;
    c.distortion.model = model;
    if ( model == DistortionModel::OpenCV )
      c.distortion.coeffs = { -0.28, 0.09, 0.0012, -0.0008, -0.012 }; // strong barrel, ~25 px at the corners
    if ( model == DistortionModel::BrownPhoto )
      c.distortion.coeffs = { 2.5e-3, -1.5e-5, 3e-5, -2e-5, 1e-8 }; // mm units, ~8 px at the corners
    return c;
  }

  double maxDistortionPx( const Camera &c )
  {
    Camera ideal = c;
    ideal.distortion.model = DistortionModel::None;
    double worst = 0.0;
    for ( const Eigen::Vector2d &corner : { Eigen::Vector2d( 0, 0 ), Eigen::Vector2d( c.width, c.height ) } )
    {
      const Eigen::Vector3d ray = *c.rayInCameraFromPixel( corner );
      worst = std::max( worst, ( ideal.pixelFromCamera( ray ).pixelInImage - corner ).norm() );
    }
    return worst;
  }
} // namespace

TEST( Camera, OpenCvModelAgreesWithProjectPoints )
{
  const Camera c = makeCamera( DistortionModel::OpenCV );
  // OpenCV's pixel centres are integers: its principal point is ours - 0.5.
  const cv::Matx33d K( c.fx(), 0, c.cx - 0.5, 0, c.fy(), c.cy - 0.5, 0, 0, 1 );
  const cv::Mat dist = ( cv::Mat_<double>( 1, 5 ) << c.distortion.k1(), c.distortion.k2(), c.distortion.p1(), c.distortion.p2(), c.distortion.k3() );

  std::mt19937 rng( 42 );
  std::uniform_real_distribution<double> u( -0.7, 0.7 );
  std::vector<cv::Point3d> pointsCv;
  std::vector<Eigen::Vector3d> points;
  for ( int i = 0; i < 2000; ++i )
  {
    const double depth = 2.0 + 40.0 * std::abs( u( rng ) );
    const Eigen::Vector3d p( u( rng ) * depth, u( rng ) * depth, -depth ); // ours: y up, z back
    points.push_back( p );
    pointsCv.emplace_back( p.x(), -p.y(), -p.z() );                         // OpenCV: y down, z forward
  }
  std::vector<cv::Point2d> pixelsCv;
  cv::projectPoints( pointsCv, cv::Vec3d( 0, 0, 0 ), cv::Vec3d( 0, 0, 0 ), K, dist, pixelsCv );

  double worst = 0.0;
  for ( size_t i = 0; i < points.size(); ++i )
  {
    const PixelProjection pr = c.pixelFromCamera( points[i] );
    ASSERT_TRUE( pr.ok() );
    worst = std::max( worst, ( pr.pixelInImage - Eigen::Vector2d( pixelsCv[i].x + 0.5, pixelsCv[i].y + 0.5 ) ).norm() );
  }
  EXPECT_LT( worst, 1e-9 );
}

class CameraRoundTrip : public ::testing::TestWithParam<DistortionModel>
{
};

TEST_P( CameraRoundTrip, PixelRayPixelOverWholeFrame )
{
  const Camera c = makeCamera( GetParam() );
  if ( GetParam() != DistortionModel::None )
  {
    ASSERT_GT( maxDistortionPx( c ), 5.0 ) << "the test needs strong distortion";
  }
  double worst = 0.0;
  for ( double row = 0.0; row <= c.height; row += 4.0 )
    for ( double col = 0.0; col <= c.width; col += 4.0 )
    {
      const Eigen::Vector2d pixel( col, row );
      const std::optional<Eigen::Vector3d> ray = c.rayInCameraFromPixel( pixel );
      ASSERT_TRUE( ray.has_value() ) << col << "," << row;
      EXPECT_DOUBLE_EQ( ray->z(), -1.0 );
      for ( double depth : { 0.5, 7.0, 300.0 } )
      {
        const PixelProjection back = c.pixelFromCamera( *ray * depth );
        ASSERT_TRUE( back.ok() );
        worst = std::max( worst, ( back.pixelInImage - pixel ).norm() );
      }
    }
  EXPECT_LT( worst, 1e-6 );
}

TEST_P( CameraRoundTrip, PrincipalPointIsTheAxis )
{
  const Camera c = makeCamera( GetParam() );
  const Eigen::Vector3d ray = *c.rayInCameraFromPixel( { c.cx, c.cy } );
  EXPECT_NEAR( ray.x(), 0.0, 1e-15 );
  EXPECT_NEAR( ray.y(), 0.0, 1e-15 );
  const PixelProjection pr = c.pixelFromCamera( { 0.0, 0.0, -12.0 } );
  EXPECT_NEAR( pr.pixelInImage.x(), c.cx, 1e-12 );
  EXPECT_NEAR( pr.pixelInImage.y(), c.cy, 1e-12 );
}

TEST_P( CameraRoundTrip, BehindCameraIsReportedNeverProjected )
{
  const Camera c = makeCamera( GetParam() );
  for ( const Eigen::Vector3d &p : { Eigen::Vector3d( 0.1, 0.2, 5.0 ), Eigen::Vector3d( 1.0, -1.0, 0.0 ), Eigen::Vector3d( 0, 0, 1e-12 ) } )
  {
    const PixelProjection pr = c.pixelFromCamera( p );
    EXPECT_EQ( pr.status, PixelProjection::Status::BehindCamera );
    EXPECT_FALSE( pr.ok() );
  }
}

TEST_P( CameraRoundTrip, ImageAxesFollowCameraAxes )
{
  // x right -> col grows; y up -> row shrinks (docs/conventions.md §1, §3).
  const Camera c = makeCamera( GetParam() );
  const Eigen::Vector2d centre = c.pixelFromCamera( { 0, 0, -10 } ).pixelInImage;
  const Eigen::Vector2d right = c.pixelFromCamera( { 1, 0, -10 } ).pixelInImage;
  const Eigen::Vector2d up = c.pixelFromCamera( { 0, 1, -10 } ).pixelInImage;
  EXPECT_GT( right.x(), centre.x() + 40 );
  EXPECT_NEAR( right.y(), centre.y(), 0.5 );
  EXPECT_LT( up.y(), centre.y() - 40 );
}

INSTANTIATE_TEST_SUITE_P( AllModels, CameraRoundTrip,
                          ::testing::Values( DistortionModel::None, DistortionModel::OpenCV, DistortionModel::BrownPhoto ),
                          []( const auto & info ) { return distortionModelName( info.param ); } );

TEST_P( CameraRoundTrip, FarOutsideTheFieldIsNotProjected )
{
  const Camera c = makeCamera( GetParam() );
  // Frame corner farthest from (322.3, 238.9) is (0, 480): about 0.81 normalised for f = 500.
  const double corner = std::hypot( 322.3 / 500.0, 241.1 / 510.0 );
  const PixelProjection inside = c.pixelFromCamera( { 1.9 * corner, 0.0, -1.0 } );
  const PixelProjection outside = c.pixelFromCamera( { 2.1 * corner, 0.0, -1.0 } );
  EXPECT_TRUE( inside.ok() );
  if ( GetParam() == DistortionModel::None )
  {
    EXPECT_TRUE( std::isinf( c.lensFieldRadius() ) );
    EXPECT_TRUE( outside.ok() ); // a pinhole is exact everywhere in front
  }
  else
  {
    EXPECT_NEAR( c.lensFieldRadius(), 2.0 * corner, 1e-12 );
    EXPECT_EQ( outside.status, PixelProjection::Status::OutsideLensField );
  }
}

TEST_P( CameraRoundTrip, PixelJacobianMatchesFiniteDifferences )
{
  const Camera c = makeCamera( GetParam() );
  for ( const Eigen::Vector2d &pixel : { Eigen::Vector2d( 20.0, 30.0 ), Eigen::Vector2d( 322.3, 238.9 ), Eigen::Vector2d( 600.0, 450.0 ) } )
  {
    const Eigen::Vector3d ray = *c.rayInCameraFromPixel( pixel );
    const Eigen::Matrix2d jacobian = *c.pixelJacobianWrtIdeal( pixel );
    const double h = 1e-6;
    Eigen::Matrix2d numeric;
    for ( int k = 0; k < 2; ++k )
    {
      Eigen::Vector3d plus = ray, minus = ray;
      plus[k] += h;
      minus[k] -= h;
      numeric.col( k ) = ( c.pixelFromCamera( plus ).pixelInImage - c.pixelFromCamera( minus ).pixelInImage ) / ( 2 * h );
    }
    EXPECT_LT( ( jacobian - numeric ).norm(), 1e-4 * jacobian.norm() ) << pixel.transpose() << "\n" << jacobian << "\n" << numeric;
  }
}

TEST( Camera, PixelCentresAreAtHalfIntegers )
{
  // An undistorted camera whose axis hits the centre of pixel (10, 20).
  Camera c = makeCamera( DistortionModel::None );
  c.aspect = 1.0;
  c.cx = 10.5;
  c.cy = 20.5;
  const PixelProjection pr = c.pixelFromCamera( { 0, 0, -3 } );
  EXPECT_DOUBLE_EQ( pr.pixelInImage.x(), 10.5 );
  EXPECT_DOUBLE_EQ( pr.pixelInImage.y(), 20.5 );
  EXPECT_TRUE( c.isInFrame( { 0.0, 0.0 } ) );
  EXPECT_TRUE( c.isInFrame( { 639.999, 479.999 } ) );
  EXPECT_FALSE( c.isInFrame( { 640.0, 10.0 } ) );
  EXPECT_FALSE( c.isInFrame( { 10.0, 480.0 } ) );
  EXPECT_FALSE( c.isInFrame( { -0.001, 10.0 } ) );
}

TEST( Camera, NoDistortionHandComputed )
{
  Camera c = makeCamera( DistortionModel::None );
  // col = cx + f * (-p.x/p.z), row = cy - f*aspect * (-p.y/p.z)
  const PixelProjection pr = c.pixelFromCamera( { 2.0, -1.0, -10.0 } );
  EXPECT_NEAR( pr.pixelInImage.x(), 322.3 + 500.0 * 0.2, 1e-12 );
  EXPECT_NEAR( pr.pixelInImage.y(), 238.9 + 510.0 * 0.1, 1e-12 );
}

TEST( Camera, BrownPhotoHandComputed )
{
  // Photo coordinates: xb = (col - cx) ps, yb = -(row - cy) ps / aspect.
  Camera c = makeCamera( DistortionModel::None );
  c.distortion.model = DistortionModel::BrownPhoto;
  c.pixelSizeMm = 0.01;
  c.aspect = 1.25;
  c.distortion.coeffs = { 1e-3, 0.0, 2e-4, 0.0, 0.0 }; // k1, p1 only
  const double col = c.cx + 100.0, row = c.cy - 125.0;   // xb = 1 mm, yb = +1 mm (up)
  const double xb = 1.0, yb = 1.0, r2 = 2.0;
  const double xi = xb + xb * 1e-3 * r2 + 2e-4 * ( r2 + 2 * xb * xb );
  const double yi = yb + yb * 1e-3 * r2 + 2 * 2e-4 * xb * yb;
  const double cMm = c.f * 0.01;
  const Eigen::Vector3d ray = *c.rayInCameraFromPixel( { col, row } );
  EXPECT_NEAR( ray.x(), xi / cMm, 1e-15 );
  EXPECT_NEAR( ray.y(), yi / cMm, 1e-15 );
  EXPECT_DOUBLE_EQ( c.principalDistanceMm(), 5.0 );
}

TEST( Camera, ValidateNamesTheProblem )
{
  Camera c = makeCamera( DistortionModel::BrownPhoto );
  EXPECT_NO_THROW( c.validate() );
  c.pixelSizeMm.reset();
  EXPECT_THROW( c.validate(), std::invalid_argument );
  EXPECT_THROW( c.principalDistanceMm(), std::logic_error );
  c = makeCamera( DistortionModel::None );
  c.f = -1.0;
  try
  {
    c.validate();
    FAIL() << "negative f accepted";
  }
  catch ( const std::invalid_argument &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "principal distance" ), std::string::npos );
  }
}

TEST( Camera, DistortionModelNames )
{
  for ( DistortionModel m : { DistortionModel::None, DistortionModel::OpenCV, DistortionModel::BrownPhoto } )
    EXPECT_EQ( distortionModelFromName( distortionModelName( m ) ), m );
  EXPECT_FALSE( distortionModelFromName( "fisheye" ).has_value() );
}
