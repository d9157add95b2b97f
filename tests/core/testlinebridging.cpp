/***************************************************************************
  testlinebridging.cpp - gaps bridged by followLine(), and where they are not
 ***************************************************************************/
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tracing/linefollower.h"

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
