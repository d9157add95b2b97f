// Edge and feature primitives: gradients, the 1 x 7 line filter, thinning
// with the 256-entry table, Förstner points, centre of gravity, Douglas-Peucker.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "imageproc/edgeprimitives.h"

using namespace geostation;

TEST( EdgePrimitives, GradientsFindStepsInEveryDirection )
{
  cv::Mat step( 30, 30, CV_8U, cv::Scalar( 50 ) );
  step( cv::Rect( 15, 0, 15, 30 ) ).setTo( 150 );
  const cv::Mat g = gradientMagnitude( step, GradientFilter::Sobel );
  EXPECT_FLOAT_EQ( g.at<float>( 10, 5 ), 0.0f );
  EXPECT_FLOAT_EQ( g.at<float>( 10, 14 ), 400.0f ); // (150 - 50) * (1 + 2 + 1)
  // a diagonal edge: the extended filter responds at least as strongly
  cv::Mat diagonal( 30, 30, CV_8U, cv::Scalar( 50 ) );
  for ( int r = 0; r < 30; ++r )
    for ( int c = 0; c < 30; ++c )
      if ( c > r )
        diagonal.at<uint8_t>( r, c ) = 150;
  EXPECT_GE( gradientMagnitude( diagonal, GradientFilter::ExtendedSobel ).at<float>( 15, 15 ), gradientMagnitude( diagonal, GradientFilter::Sobel ).at<float>( 15, 15 ) );
  EXPECT_THROW( gradientMagnitude( cv::Mat( 5, 5, CV_32F ), GradientFilter::Sobel ), std::invalid_argument );
}

TEST( EdgePrimitives, LineFilterKeepsStepsAndDropsBitErrors )
{
  // an edge as a camera sees it: a ramp over a few pixels
  cv::Mat image( 10, 40, CV_8U, cv::Scalar( 60 ) );
  image( cv::Rect( 20, 0, 20, 10 ) ).setTo( 160 );
  cv::GaussianBlur( image, image, cv::Size( 0, 0 ), 1.0, 0.01 );
  image.at<uint8_t>( 5, 8 ) = 255; // a bit error
  const cv::Mat edges = lineFilterEdges( image, 20 );
  EXPECT_EQ( edges.at<uint8_t>( 5, 8 ), 0 );
  int onStep = 0;
  for ( int c = 17; c <= 22; ++c )
    onStep += edges.at<uint8_t>( 5, c ) ? 1 : 0;
  EXPECT_GE( onStep, 1 );
  EXPECT_EQ( cv::countNonZero( edges( cv::Rect( 0, 0, 15, 10 ) ) ), 0 );
}

TEST( EdgePrimitives, ThinningTableAndSkeleton )
{
  const auto &tables = skeletonTables();
  EXPECT_EQ( tables[0][0], 1 );             // an isolated pixel goes
  EXPECT_EQ( tables[0][1 << 3], 0 );        // a line end (one neighbour) stays
  EXPECT_EQ( tables[1][( 1 << 3 ) | ( 1 << 7 )], 0 ); // the middle of a horizontal line stays
  cv::Mat binary( 30, 60, CV_8U, cv::Scalar( 0 ) );
  binary( cv::Rect( 5, 10, 50, 7 ) ).setTo( 255 ); // a bar 7 px thick
  binary.at<uint8_t>( 25, 30 ) = 255;              // and a bit error
  const int iterations = skeletonise( binary );
  EXPECT_GE( iterations, 2 );
  EXPECT_EQ( binary.at<uint8_t>( 25, 30 ), 0 );
  for ( int c = 12; c < 48; ++c )
    EXPECT_EQ( cv::countNonZero( binary.col( c ) ), 1 ) << "column " << c;
  cv::Mat labels;
  EXPECT_EQ( cv::connectedComponents( binary, labels, 8 ), 2 ); // background + one line
  // the line runs through the middle of the bar
  for ( int c = 12; c < 48; ++c )
  {
    cv::Point at;
    cv::minMaxLoc( binary.col( c ), nullptr, nullptr, nullptr, &at );
    EXPECT_NEAR( at.y, 13, 1 );
  }
}

TEST( EdgePrimitives, ForstnerLocatesCorners )
{
  cv::Mat square( 60, 60, CV_8U, cv::Scalar( 40 ) );
  square( cv::Rect( 20, 20, 20, 20 ) ).setTo( 200 );
  cv::GaussianBlur( square, square, cv::Size( 0, 0 ), 0.7 );
  const std::vector<InterestPoint> points = forstnerPoints( square );
  const std::vector<Eigen::Vector2d> corners { { 20, 20 }, { 40, 20 }, { 20, 40 }, { 40, 40 } };
  for ( const Eigen::Vector2d &corner : corners )
  {
    double best = 1e9;
    for ( const InterestPoint &p : points )
      best = std::min( best, ( p.pixelInImage - corner ).norm() );
    EXPECT_LT( best, 0.5 ) << corner.transpose(); // a blurred corner is rounded: the estimate moves inside by a fraction of the blur
  }
  for ( const InterestPoint &p : points )
    EXPECT_GE( p.roundness, 0.5 );
}

TEST( EdgePrimitives, CentreOfGravityOfADisc )
{
  const Eigen::Vector2d centre( 30.37, 25.81 );
  cv::Mat image( 50, 60, CV_8U, cv::Scalar( 30 ) );
  for ( int r = 15; r < 37; ++r )
    for ( int c = 20; c < 42; ++c )
    {
      int inside = 0;
      for ( int s = 0; s < 64; ++s )
        inside += ( Eigen::Vector2d( c + ( s % 8 + 0.5 ) / 8, r + ( s / 8 + 0.5 ) / 8 ) - centre ).norm() <= 4.0 ? 1 : 0;
      image.at<uint8_t>( r, c ) = static_cast<uint8_t>( std::lround( 30 + 200.0 * inside / 64 ) );
    }
  const std::optional<Eigen::Vector2d> found = centreOfGravity( image, { 31, 25 }, 7 );
  ASSERT_TRUE( found.has_value() );
  EXPECT_LT( ( *found - centre ).norm(), 0.03 );
  EXPECT_FALSE( centreOfGravity( cv::Mat( 50, 60, CV_8U, cv::Scalar( 30 ) ), { 31, 25 }, 7 ).has_value() );
  EXPECT_FALSE( centreOfGravity( image, { 3, 3 }, 7 ).has_value() );
}

TEST( EdgePrimitives, DouglasPeuckerKeepsTheCorner )
{
  std::vector<Eigen::Vector2d> line;
  for ( int i = 0; i <= 20; ++i )
    line.emplace_back( i, 0.05 * ( i % 2 ) );
  for ( int i = 1; i <= 20; ++i )
    line.emplace_back( 20, i );
  const std::vector<Eigen::Vector2d> simple = douglasPeucker( line, 0.2 );
  ASSERT_EQ( simple.size(), 3u );
  EXPECT_EQ( simple[1], Eigen::Vector2d( 20, 0 ) );
  EXPECT_GT( douglasPeucker( line, 0.01 ).size(), 20u ); // below the zig-zag's amplitude it stays
}
