/***************************************************************************
  testlinebridging.cpp - gaps bridged by followLine(), and where they are
  not; a start in a gap; worn paint at a seed
 ***************************************************************************/
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tracing/linefollower.h"
#include "tracing/lineprofile.h"

using namespace geostation;

namespace
{
  //! A painted stripe 6 px wide up the image on dark asphalt, from row 380 to `endRow`.
  cv::Mat stripe( int endRow )
  {
    cv::Mat grey( 400, 400, CV_8UC1, cv::Scalar( 60 ) );
    cv::rectangle( grey, cv::Point( 197, endRow ), cv::Point( 202, 380 ), cv::Scalar( 200 ), cv::FILLED );
    cv::GaussianBlur( grey, grey, cv::Size( 5, 5 ), 1.0 );
    return grey;
  }

  FollowRequest upFrom( const Eigen::Vector2d &start )
  {
    FollowRequest request;
    request.start = start;
    request.direction = Eigen::Vector2d( 0.0, -1.0 );
    request.profile.kind = LineKind::BrightStripe;
    request.profile.widthPx = 6.0;
    request.profile.contrast = 140.0;
    return request;
  }
}

TEST( LineBridging, AnUnfollowableFleckIsNotBridgedAgainAndAgain )
{
  // the line ends at row 250; 20 px on, a fleck of paint 4 px long, then nothing
  cv::Mat grey = stripe( 250 );
  cv::rectangle( grey, cv::Point( 198, 226 ), cv::Point( 201, 229 ), cv::Scalar( 200 ), cv::FILLED );
  for ( const TraceMethod method : { TraceMethod::Directional, TraceMethod::LeastSquares, TraceMethod::Polynomial } )
  {
    SCOPED_TRACE( traceMethodName( method ) );
    const LineFollowResult r = followLine( grey, upFrom( Eigen::Vector2d( 200.0, 370.0 ) ), method );
    ASSERT_GE( r.line.points.size(), 2u );
    EXPECT_TRUE( r.line.stop == TraceStop::EndOfLine || r.line.stop == TraceStop::LeftImage ) << traceStopName( r.line.stop );
    EXPECT_LE( r.bridgedGaps, 1 ); // the same bridge is not tried again and again (up to the 64 legs)
    EXPECT_GE( r.line.points.back().y(), 224.0 ); // the line's end or the fleck, nothing beyond
    EXPECT_NEAR( r.line.points.front().y(), 370.0, 3.0 );
  }
}

TEST( LineBridging, AGapInTheLineIsBridged )
{
  // the same stripe with 40 px missing (rows 250-290): followed across to its end at row 150
  cv::Mat grey = stripe( 150 );
  cv::rectangle( grey, cv::Point( 190, 250 ), cv::Point( 210, 290 ), cv::Scalar( 60 ), cv::FILLED );
  cv::GaussianBlur( grey, grey, cv::Size( 3, 3 ), 0.8 );
  for ( const TraceMethod method : { TraceMethod::Directional, TraceMethod::LeastSquares, TraceMethod::Polynomial } )
  {
    SCOPED_TRACE( traceMethodName( method ) );
    const LineFollowResult r = followLine( grey, upFrom( Eigen::Vector2d( 200.0, 370.0 ) ), method );
    ASSERT_GE( r.line.points.size(), 2u );
    EXPECT_GE( r.bridgedGaps, 1 );
    EXPECT_LE( r.bridgedGaps, 2 );
    EXPECT_NEAR( r.line.points.back().y(), 152.0, 5.0 );
    for ( const Eigen::Vector2d &p : r.line.points )
      EXPECT_NEAR( p.x(), 200.0, 1.0 );
  }
}

TEST( LineBridging, AStartInAGapIsNotPartOfTheLine )
{
  // a dash from row 300 up to row 150; following starts 40 px below it, on bare asphalt
  // (a station's start predicted into the gap before the next dash)
  const cv::Mat grey = [] {
    cv::Mat g( 400, 400, CV_8UC1, cv::Scalar( 60 ) );
    cv::rectangle( g, cv::Point( 197, 150 ), cv::Point( 202, 300 ), cv::Scalar( 200 ), cv::FILLED );
    cv::GaussianBlur( g, g, cv::Size( 5, 5 ), 1.0 );
    return g;
  }();
  const LineFollowResult forward = followLine( grey, upFrom( Eigen::Vector2d( 200.0, 340.0 ) ), TraceMethod::Polynomial );
  ASSERT_GE( forward.line.points.size(), 2u );
  // the polynomial strip is not extrapolated back from the dash to the start
  EXPECT_LE( forward.line.points.front().y(), 303.0 );
  EXPECT_GE( forward.line.points.front().y(), 290.0 );

  // followed both ways from a start in the gap between two dashes: the line joining them is bridged
  cv::Mat two = grey.clone();
  cv::rectangle( two, cv::Point( 197, 360 ), cv::Point( 202, 395 ), cv::Scalar( 200 ), cv::FILLED );
  FollowResult up = followLine( two, upFrom( Eigen::Vector2d( 200.0, 330.0 ) ), TraceMethod::Polynomial ).line;
  FollowRequest downRequest = upFrom( Eigen::Vector2d( 200.0, 330.0 ) );
  downRequest.direction = Eigen::Vector2d( 0.0, 1.0 );
  const FollowResult down = followLine( two, downRequest, TraceMethod::Polynomial ).line;
  ASSERT_GE( down.points.size(), 2u );
  joinBackward( down, up );
  ASSERT_EQ( up.points.size(), up.bridged.size() );
  size_t junction = 0;
  for ( size_t i = 1; i < up.points.size(); ++i )
    if ( up.points[i - 1].y() >= 355.0 && up.points[i].y() <= 305.0 )
      junction = i;
  ASSERT_GT( junction, 0u ) << "the two dashes are joined";
  EXPECT_TRUE( up.bridged[junction] ) << "the segment across the gap is bridged, not followed";
  for ( size_t i = 1; i < up.points.size(); ++i )
    if ( i != junction )
    {
      EXPECT_FALSE( up.bridged[i] ) << i;
    }
}

TEST( LineBridging, AWornCrackAtTheClickDoesNotTurnTheSeedDirection )
{
  // a stripe 10 px wide running up and to the left; just ahead of the click, worn paint: a crack 4 px wide
  // across the stripe at 30 degrees to it, whose edges dominate the structure tensor at the click
  const Eigen::Vector2d along = Eigen::Vector2d( -0.72, -0.70 ).normalized(), click( 200.0, 200.0 );
  const double a = 30.0 * 3.14159265358979 / 180.0;
  const Eigen::Vector2d crack( along.x() * std::cos( a ) - along.y() * std::sin( a ), along.x() * std::sin( a ) + along.y() * std::cos( a ) );
  cv::Mat grey( 400, 400, CV_8UC1, cv::Scalar( 60 ) );
  const auto pt = []( const Eigen::Vector2d &p ) { return cv::Point( static_cast<int>( std::lround( p.x() ) ), static_cast<int>( std::lround( p.y() ) ) ); };
  cv::line( grey, pt( click - 180.0 * along ), pt( click + 180.0 * along ), cv::Scalar( 200 ), 10 );
  const Eigen::Vector2d onCrack = click + 9.0 * along;
  cv::line( grey, pt( onCrack - 14.0 * crack ), pt( onCrack + 14.0 * crack ), cv::Scalar( 60 ), 4 );
  cv::GaussianBlur( grey, grey, cv::Size( 5, 5 ), 1.0 );
  const SeedAnalysis seed = analyseSeed( grey, click, std::nullopt );
  ASSERT_TRUE( seed.ok ) << seed.message;
  EXPECT_EQ( seed.profile.kind, LineKind::BrightStripe );
  EXPECT_GT( std::abs( seed.direction.dot( along ) ), std::cos( 8.0 * 3.14159265358979 / 180.0 ) ) << seed.direction.transpose();
  EXPECT_NEAR( seed.profile.widthPx, 10.0, 2.5 );
}

TEST( LineBridging, AClickOnAShortDashKeepsTheDashsDirection )
{
  // a far dash: 14 px long, 4 px wide, on asphalt with some texture; the click in its middle
  for ( const double degrees : { 20.0, 45.0, 70.0 } )
  {
    SCOPED_TRACE( degrees );
    const double a = degrees * 3.14159265358979 / 180.0;
    const Eigen::Vector2d along( std::cos( a ), -std::sin( a ) ), click( 100.0, 100.0 );
    cv::Mat grey( 200, 200, CV_8UC1, cv::Scalar( 70 ) );
    cv::randn( grey, 70, 6 );
    const auto pt = []( const Eigen::Vector2d &p ) { return cv::Point( static_cast<int>( std::lround( p.x() ) ), static_cast<int>( std::lround( p.y() ) ) ); };
    cv::line( grey, pt( click - 7.0 * along ), pt( click + 7.0 * along ), cv::Scalar( 190 ), 4 );
    cv::GaussianBlur( grey, grey, cv::Size( 5, 5 ), 0.8 );
    const SeedAnalysis seed = analyseSeed( grey, click, std::nullopt );
    ASSERT_TRUE( seed.ok ) << seed.message;
    EXPECT_EQ( seed.profile.kind, LineKind::BrightStripe );
    EXPECT_GT( std::abs( seed.direction.dot( along ) ), std::cos( 10.0 * 3.14159265358979 / 180.0 ) ) << seed.direction.transpose();
  }
}
