/***************************************************************************
  testlinebridging.cpp - gaps bridged by followLine(), and where they are
  not; a start in a gap; worn paint at a seed; what lies beside the line
  beyond a gap
 ***************************************************************************/
#include <optional>
#include <vector>

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
  ASSERT_TRUE( seed.ok() ) << seed.message;
  EXPECT_EQ( seed.status, SeedAnalysis::Status::Ok );
  EXPECT_EQ( analyseSeed( grey, Eigen::Vector2d( -4.0, -4.0 ), std::nullopt ).status, SeedAnalysis::Status::OutsideImage );
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
    ASSERT_TRUE( seed.ok() ) << seed.message;
    EXPECT_EQ( seed.profile.kind, LineKind::BrightStripe );
    EXPECT_GT( std::abs( seed.direction.dot( along ) ), std::cos( 10.0 * 3.14159265358979 / 180.0 ) ) << seed.direction.transpose();
  }
}

namespace
{
  //! Tarmac (180) left of x = 200, lawn (80) right: a path's edge up the image.
  cv::Mat pathEdge()
  {
    cv::Mat grey( 400, 400, CV_8UC1, cv::Scalar( 80 ) );
    cv::rectangle( grey, cv::Point( 0, 0 ), cv::Point( 199, 399 ), cv::Scalar( 180 ), cv::FILLED );
    return grey;
  }
}

TEST( LineBridging, SidesOfEdgesAndStripesAndWhenTheyAgree )
{
  cv::Mat edge = pathEdge();
  cv::GaussianBlur( edge, edge, cv::Size( 5, 5 ), 1.0 );
  LineProfile edgeProfile;
  edgeProfile.kind = LineKind::Edge;
  edgeProfile.polarity = -1;
  const std::optional<LineSides> up = lineSides( edge, Eigen::Vector2d( 200.0, 200.0 ), Eigen::Vector2d( 0.0, -1.0 ), edgeProfile );
  ASSERT_TRUE( up );
  EXPECT_NEAR( up->left, 180.0, 1.0 );
  EXPECT_NEAR( up->right, 80.0, 1.0 );
  EXPECT_NEAR( up->contrast, 100.0, 2.0 );
  // the way back: the sides change places
  const std::optional<LineSides> down = lineSides( edge, Eigen::Vector2d( 200.0, 200.0 ), Eigen::Vector2d( 0.0, 1.0 ), edgeProfile );
  ASSERT_TRUE( down );
  EXPECT_NEAR( down->left, 80.0, 1.0 );
  EXPECT_NEAR( down->right, 180.0, 1.0 );
  // a stripe's sides lie beyond its half width
  const cv::Mat painted = stripe( 20 );
  const std::optional<LineSides> stripeSides = lineSides( painted, Eigen::Vector2d( 200.0, 200.0 ), Eigen::Vector2d( 0.0, -1.0 ), upFrom( Eigen::Vector2d::Zero() ).profile );
  ASSERT_TRUE( stripeSides );
  EXPECT_NEAR( stripeSides->left, 60.0, 3.0 );
  EXPECT_NEAR( stripeSides->right, 60.0, 3.0 );
  EXPECT_NEAR( stripeSides->contrast, 140.0, 5.0 );
  EXPECT_FALSE( lineSides( edge, Eigen::Vector2d( 3.0, 200.0 ), Eigen::Vector2d( 0.0, -1.0 ), edgeProfile ) ) << "too near the border";

  const double tolerance = 15.0; // 0.15 of the contrast
  EXPECT_TRUE( sidesAgree( *up, LineSides { 90.0, 40.0, 50.0 }, tolerance ) ) << "the same edge in a shadow";
  EXPECT_TRUE( sidesAgree( *up, LineSides { 190.0, 90.0, 100.0 }, tolerance ) ) << "the same edge in brighter light";
  EXPECT_FALSE( sidesAgree( *up, LineSides { 180.0, 120.0, 60.0 }, tolerance ) ) << "tarmac against a stone";
  EXPECT_FALSE( sidesAgree( *up, LineSides { 130.0, 80.0, 50.0 }, tolerance ) ) << "a kerb against the lawn";
  EXPECT_FALSE( sidesAgree( *up, LineSides { 80.0, 180.0, 100.0 }, tolerance ) ) << "the other polarity";
}

TEST( LineBridging, TheLineBeyondAGapHasTheSidesItHadBefore )
{
  // A path's edge with a stone (120) lying across it, rows 200-300. For 20 px (rows 270-250) the stone's
  // outline runs along the edge's course: tarmac against stone, the edge's polarity and half its contrast.
  // Above, the outline turns away 15 degrees and the lawn shows again beside the edge.
  cv::Mat grey = pathEdge();
  const std::vector<cv::Point> stone { { 185, 300 }, { 185, 280 }, { 200, 270 }, { 200, 250 }, { 213, 200 }, { 260, 200 }, { 260, 300 } };
  cv::fillPoly( grey, std::vector<std::vector<cv::Point>> { stone }, cv::Scalar( 120 ) );
  cv::GaussianBlur( grey, grey, cv::Size( 5, 5 ), 1.0 );
  const SeedAnalysis seed = analyseSeed( grey, Eigen::Vector2d( 200.0, 360.0 ), std::nullopt );
  ASSERT_TRUE( seed.ok() ) << seed.message;
  ASSERT_EQ( seed.profile.kind, LineKind::Edge );
  FollowRequest request;
  request.start = seed.pixelInImage;
  request.direction = seed.direction;
  request.profile = seed.profile;
  LineFollowOptions options;
  options.maxGapPx = 100.0;
  int resumedOnTheOutline = 0;
  for ( const TraceMethod method : { TraceMethod::LeastSquares, TraceMethod::Polynomial, TraceMethod::Directional } )
  {
    SCOPED_TRACE( traceMethodName( method ) );
    // the stone's outline is not the line: the bridges resume above it (the polynomial strips follow the
    // outline's straight stretch, and still know the line beyond: the sides are those of the last 100 px)
    const FollowResult line = followLine( grey, request, method, options ).line;
    ASSERT_GE( line.points.size(), 2u );
    EXPECT_LE( line.points.back().y(), 10.0 ) << traceStopName( line.stop );
    for ( size_t i = 0; i < line.points.size(); ++i )
    {
      EXPECT_NEAR( line.points[i].x(), 200.0, 1.0 ) << line.points[i].transpose();
      if ( line.bridged[i] )
      {
        EXPECT_LE( line.points[i].y(), 245.0 ) << "resumed on the stone's outline";
      }
    }
    // with any line of the profile taken beyond a gap, the least-squares and skeleton bridges resume on the outline
    LineFollowOptions anySides = options;
    anySides.sideTolerance = 0.0;
    const FollowResult any = followLine( grey, request, method, anySides ).line;
    for ( size_t i = 0; i < any.points.size(); ++i )
      if ( any.bridged[i] && any.points[i].y() > 250.0 && any.points[i].y() < 275.0 )
        ++resumedOnTheOutline;
  }
  EXPECT_EQ( resumedOnTheOutline, 2 );
}
