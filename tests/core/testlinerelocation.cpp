// Putting traced points back onto the line (core/tracing/linerelocation) on a
// scene built here (stripedroad.h): a painted stripe on a flat road, worn
// along one side or the other in patches of a few decimetres, seen by a
// forward camera of a van; and the scale across a line against a nadir
// camera's f / H.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "tracing/linerelocation.h"
#include "stripedroad.h"
#include "vanrig.h"

using namespace geostation;

namespace
{
  using namespace stripedroad;

  //! Paint at ground x (stripe centre kStripeX): patches 0.3 m long where 40 % of the width is worn away on one side.
  bool paintAt( double x, double y )
  {
    const double u = ( x - kStripeX ) / kStripeHalfWidth; // -1 .. 1 across the stripe
    if ( std::abs( u ) > 1.0 )
      return false;
    const int patch = static_cast<int>( std::floor( y / 0.3 ) );
    const unsigned hash = static_cast<unsigned>( patch * 2654435761u ) >> 29; // 0..7
    if ( hash < 3 )
      return u < 0.2;  // the right side worn
    if ( hash < 6 )
      return u > -0.2; // the left side worn
    return true;
  }

  //! RMS (m) of the points' distance on the road from the stripe's centre line.
  double rmsOnRoad( const OrientedImage &image, const std::vector<Eigen::Vector2d> &points )
  {
    double sum = 0.0;
    for ( const Eigen::Vector2d &p : points )
      sum += std::pow( onRoad( image, p )->x() - kStripeX, 2 );
    return std::sqrt( sum / points.size() );
  }
}

TEST( LineRelocation, ScaleAcrossALineIsFOverHeightFromNadir )
{
  const Camera camera = vanCamera();
  const double height = 12.0;
  const Eigen::Vector3d centre( 0.0, 0.0, kRoadZ + height );
  const OrientedImage nadir( camera, vanrig::lookAt( centre, centre + Eigen::Vector3d( 0.0, 1e-4, -height ) ) );
  const Eigen::Vector3d ground( 0.3, -0.2, kRoadZ );
  for ( const Eigen::Vector3d &along : { Eigen::Vector3d( 0, 1, 0 ), Eigen::Vector3d( 1, 1, 0.2 ), Eigen::Vector3d( -1, 0.1, 0 ) } )
    EXPECT_NEAR( pixelsPerMetreAcross( nadir, ground, along ), camera.f / height, 1e-3 * camera.f / height );
  // a forward camera sees a line on the road foreshortened with range, and not at all behind it
  const Eigen::Vector3d van( 1.0, 0.0, kRoadZ + 2.65 );
  const OrientedImage forward( camera, vanrig::lookAt( van, van + Eigen::Vector3d( 0.0, 30.0, -3.7 ) ) );
  const double near = pixelsPerMetreAcross( forward, Eigen::Vector3d( kStripeX, 8.0, kRoadZ ), Eigen::Vector3d::UnitY() );
  const double far = pixelsPerMetreAcross( forward, Eigen::Vector3d( kStripeX, 24.0, kRoadZ ), Eigen::Vector3d::UnitY() );
  EXPECT_GT( near, 2.5 * far );
  EXPECT_EQ( pixelsPerMetreAcross( forward, Eigen::Vector3d( kStripeX, -8.0, kRoadZ ), Eigen::Vector3d::UnitY() ), 0.0 );
}

TEST( LineRelocation, WornStripeCentredOverALengthOfLine )
{
  std::mt19937 rng( 5 );
  const Camera camera = vanCamera();
  const Eigen::Vector3d van( 1.0, 0.0, kRoadZ + 2.65 );
  const OrientedImage image( camera, vanrig::lookAt( van, van + Eigen::Vector3d( 0.0, 30.0, -3.7 ) ) );
  const cv::Mat grey = render( image, paintAt, 1.5, rng );
  const StereoImage view { "forward", &image, &grey };

  // a follower's points 7-16 m ahead every 0.4 m, strayed 1.5 px to one side of the line
  std::vector<Eigen::Vector2d> followed;
  for ( double y = 7.0; y <= 16.0; y += 0.4 )
  {
    const Eigen::Vector3d on( kStripeX, y, kRoadZ ), beside( kStripeX + 0.01, y, kRoadZ );
    const Eigen::Vector2d p = image.projectGroundToPixel( on ).pixelInImage, q = image.projectGroundToPixel( beside ).pixelInImage;
    followed.push_back( p + 1.5 * ( q - p ).normalized() );
  }
  ASSERT_GT( rmsOnRoad( image, followed ), 0.02 );

  LineProfile stripe;
  stripe.kind = LineKind::BrightStripe;
  stripe.contrast = 140.0;
  const double range = 10.0;
  stripe.widthPx = 2 * kStripeHalfWidth * pixelsPerMetreAcross( image, Eigen::Vector3d( kStripeX, range, kRoadZ ), Eigen::Vector3d::UnitY() );
  LineRelocation relocation;
  relocation.profile = stripe;
  relocation.widthTimesRange = stripe.widthPx * std::hypot( kStripeX - van.x(), range );
  const GroundOfPixel ground = []( const OrientedImage &i, const Eigen::Vector2d &p ) { return onRoad( i, p ); };

  // one short profile stack: on the line, but its centre is off wherever one side is worn
  std::vector<Eigen::Vector2d> shortWindow = followed;
  std::vector<double> sigmas( followed.size(), 0.5 );
  LineRelocation single = relocation;
  single.windowM = 0.0;
  // (a worn profile can also fail the width test: such a point stays where the follower left it)
  EXPECT_GE( recentreOnLine( view, shortWindow, sigmas, ground, single ), static_cast<int>( 0.8 * followed.size() ) );
  const double rmsShort = rmsOnRoad( image, shortWindow );

  // a metre of line: the patches worn on either side average out
  std::vector<Eigen::Vector2d> metre = followed;
  EXPECT_EQ( recentreOnLine( view, metre, sigmas, ground, relocation ), static_cast<int>( followed.size() ) );
  const double rmsMetre = rmsOnRoad( image, metre );
  std::printf( "followed %.4f m, one profile stack %.4f m, a metre of line %.4f m (RMS on the road)\n", rmsOnRoad( image, followed ), rmsShort, rmsMetre );
  EXPECT_LT( rmsMetre, 0.5 * rmsShort );
  EXPECT_LT( rmsMetre, 0.012 ); // RoadTraceOptions::stripeSigmaM
  for ( const double s : sigmas )
    EXPECT_GT( s, 0.0 );

  // a point off the stripe by more than the search distance stays where it is
  std::vector<Eigen::Vector2d> lost { followed[5] + Eigen::Vector2d( 40.0, 0.0 ), followed[6] + Eigen::Vector2d( 40.0, 0.0 ) };
  std::vector<double> lostSigmas( 2, 0.5 );
  const std::vector<Eigen::Vector2d> before = lost;
  EXPECT_EQ( recentreOnLine( view, lost, lostSigmas, ground, relocation ), 0 );
  EXPECT_EQ( lost, before );

  LineRelocation bad = relocation;
  bad.windowM = -1.0;
  EXPECT_THROW( recentreOnLine( view, metre, sigmas, ground, bad ), std::invalid_argument );
}
