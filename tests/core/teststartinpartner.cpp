// The traced line's start found in a partner image (matchStartInPartner(),
// core/tracing/stereolinematcher) on a scene built here (stripedroad.h):
// a stripe painted in short patches of irregular length on a flat road,
// seen by a van's forward camera and by partners that see the same patch
// of road at a different scale and shear - the stereo partner beside it,
// and a camera 8 m further along the road. The correlation window follows
// the road surface into the partner, so the start is found where a window
// of the reference's shape no longer correlates.
#include <cmath>
#include <random>
#include <utility>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "tracing/stereolinematcher.h"
#include "stripedroad.h"
#include "vanrig.h"

using namespace geostation;

namespace
{
  using namespace stripedroad;

  //! Paint in patches 0.15-0.45 m long with gaps of 0.1-0.3 m between them (a worn, broken stripe).
  bool brokenStripe( double x, double y )
  {
    if ( std::abs( x - kStripeX ) > kStripeHalfWidth )
      return false;
    const int cell = static_cast<int>( std::floor( y / 0.6 ) );
    const unsigned hash = static_cast<unsigned>( cell * 2654435761u );
    const double paintFrom = 0.1 + 0.2 * ( ( hash >> 24 ) & 0xff ) / 255.0, paintTo = 0.45 + 0.15 * ( ( hash >> 16 ) & 0xff ) / 255.0;
    const double u = y - 0.6 * cell;
    return u >= paintFrom && u < paintTo;
  }

  struct View
  {
    OrientedImage image;
    cv::Mat grey;
  };

  View viewFrom( const Eigen::Vector3d &centre, const Eigen::Vector3d &target, std::mt19937 &rng )
  {
    OrientedImage image( vanCamera(), vanrig::lookAt( centre, target ) );
    cv::Mat grey = render( image, brokenStripe, 2.0, rng );
    return { std::move( image ), grey };
  }

  //! The stripe's point at `start` in an image, and the stripe's direction there (unit, along +Y on the road).
  std::pair<Eigen::Vector2d, Eigen::Vector2d> seenAt( const OrientedImage &image, const Eigen::Vector3d &start )
  {
    const Eigen::Vector2d pixel = image.projectGroundToPixel( start ).pixelInImage;
    return { pixel, ( image.projectGroundToPixel( start + Eigen::Vector3d( 0, 1, 0 ) ).pixelInImage - pixel ).normalized() };
  }

  //! The stripe's profile as the reference sees it at `start`.
  LineProfile stripeAt( const OrientedImage &reference, const Eigen::Vector3d &start )
  {
    LineProfile stripe;
    stripe.kind = LineKind::BrightStripe;
    stripe.contrast = 140.0;
    stripe.widthPx = 2 * kStripeHalfWidth * pixelsPerMetreAcross( reference, start, Eigen::Vector3d::UnitY() );
    return stripe;
  }
}

TEST( StartInPartner, FoundThroughTheRoadSurfaceAtAnotherScale )
{
  std::mt19937 rng( 11 );
  const Eigen::Vector3d van( 1.0, 0.0, kRoadZ + 2.65 );
  const View reference = viewFrom( van, van + Eigen::Vector3d( 0.0, 30.0, -3.7 ), rng );
  // the stereo partner 1.4 m to the right, toed in; a camera of the van 8 m further along, looking down more steeply
  const Eigen::Vector3d right = van + Eigen::Vector3d( 1.4, 0.0, 0.0 ), further = van + Eigen::Vector3d( 0.0, 8.0, 0.0 );
  const View beside = viewFrom( right, right + Eigen::Vector3d( -2.0, 30.0, -3.7 ), rng );
  const View ahead = viewFrom( further, further + Eigen::Vector3d( 0.6, 30.0, -6.0 ), rng );

  // the start on the stripe 15.3 m ahead of the reference, the line running up the image
  const Eigen::Vector3d start( kStripeX, 15.3, kRoadZ );
  const auto [pixel, direction] = seenAt( reference.image, start );
  const LineProfile stripe = stripeAt( reference.image, start );
  const StereoImage ref { "reference", &reference.image, &reference.grey };

  for ( const View *partner : { &beside, &ahead } )
  {
    const auto [truth, truthDirection] = seenAt( partner->image, start );
    // the road plane 0.25 m too high (a crossfall the plane from the cameras' heights does not know): the start is
    // found by correlation along the epipolar curve, the window shaped for each candidate's height, not copied
    const GroundOfPixel raised = [&]( const OrientedImage &i, const Eigen::Vector2d &p ) -> std::optional<Eigen::Vector3d>
    {
      const std::optional<Ray> ray = i.worldRayFromPixel( p );
      if ( !ray || ray->direction.z() > -1e-6 )
        return std::nullopt;
      return Eigen::Vector3d( ray->origin + ( kRoadZ + 0.25 - ray->origin.z() ) / ray->direction.z() * ray->direction );
    };
    const StartMatch match = matchStartInPartner( ref, pixel, direction, { "partner", &partner->image, &partner->grey }, raised, stripe );
    ASSERT_TRUE( match.ok() ) << ( partner == &ahead ? "ahead: " : "beside: " ) << match.message;
    EXPECT_LT( ( match.pixelInImage - truth ).norm(), 0.7 ) << ( partner == &ahead ? "ahead" : "beside" );
    EXPECT_GT( match.score, 0.8 );
    EXPECT_GT( match.direction.dot( truthDirection ), std::cos( 3.0 * M_PI / 180.0 ) );
  }
}

TEST( StartInPartner, NoMatchWhereTheWindowLeavesThePartner )
{
  // the stereo partner 1.4 m to the left, turned 14.6 degrees to the left, sees the start 12.5 m ahead 40 px from
  // its right border, the line running up and to the left from there: the window (some 60 px along the line) fits only
  // beside the true place, where the correlation still rises towards it. That is no match - the caller tries a
  // point further along the line - not the best of the candidates that fit.
  std::mt19937 rng( 12 );
  const Eigen::Vector3d van( 1.0, 0.0, kRoadZ + 2.65 ), left = van - Eigen::Vector3d( 1.4, 0.0, 0.0 );
  const View reference = viewFrom( van, van + Eigen::Vector3d( 0.0, 30.0, -3.7 ), rng );
  const double turn = 14.6 * M_PI / 180.0;
  const View partner = viewFrom( left, left + Eigen::Vector3d( -30.0 * std::sin( turn ), 30.0 * std::cos( turn ), -3.7 ), rng );
  const Eigen::Vector3d start( kStripeX, 12.5, kRoadZ );
  const Eigen::Vector2d truth = partner.image.projectGroundToPixel( start ).pixelInImage;
  ASSERT_GT( truth.x(), 755.0 );
  ASSERT_LT( truth.x(), 765.0 );

  const auto [pixel, direction] = seenAt( reference.image, start );
  const LineProfile stripe = stripeAt( reference.image, start );
  const GroundOfPixel ground = []( const OrientedImage &i, const Eigen::Vector2d &p ) { return onRoad( i, p ); };
  const StereoImage ref { "reference", &reference.image, &reference.grey }, par { "partner", &partner.image, &partner.grey };
  const StartMatch match = matchStartInPartner( ref, pixel, direction, par, ground, stripe );
  EXPECT_FALSE( match.ok() ) << "matched at " << match.pixelInImage.transpose() << ", the line is at " << truth.transpose();
  EXPECT_EQ( match.status, StartMatch::Status::AtSearchEnd ) << match.message;
  EXPECT_NE( match.message.find( "end of the start's search" ), std::string::npos ) << match.message << " " << truth.transpose();
  // 2 m further along the line, in full view of the partner: found
  const Eigen::Vector3d further( kStripeX, 14.5, kRoadZ );
  const Eigen::Vector2d furtherPixel = reference.image.projectGroundToPixel( further ).pixelInImage;
  const StartMatch found = matchStartInPartner( ref, furtherPixel, direction, par, ground, stripe );
  ASSERT_TRUE( found.ok() ) << found.message;
  EXPECT_LT( ( found.pixelInImage - partner.image.projectGroundToPixel( further ).pixelInImage ).norm(), 0.7 );
}
